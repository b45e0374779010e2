//! The drift of a run of rejected fixes: a straight line fitted to their innovations against
//! time. A filter too sure of a wrong bias sees its innovations grow steadily (the heading runs
//! away at the bias's error), and may see them pass [`READMIT_REACH`](crate::READMIT_REACH) gate
//! radii before `readmit_after`; a receiver's lasting wrong course (a reflection, reversing)
//! lies off by a constant. The line's slope tells the two apart.

/// Running sums of a run's innovations `y` (unwrapped along the run) at the times `tau` since
/// its first fix: the least-squares line through them, with the run's count kept beside it
/// (`Fusion::rejected_run`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Drift {
    sum_t: f64,
    sum_tt: f64,
    sum_y: f64,
    sum_ty: f64,
    sum_yy: f64,
    /// The last innovation, unwrapped: the next is taken within half a turn of it.
    last: f64,
}

impl Drift {
    /// A run's first fix, its innovation `nu`.
    pub(crate) fn first(nu: f64) -> Self {
        Drift {
            sum_y: nu,
            sum_yy: nu * nu,
            last: nu,
            ..Drift::default()
        }
    }

    /// The run with a fix `tau` seconds after its first, its innovation `nu` (wrapped).
    pub(crate) fn with(&self, tau: f64, nu: f64) -> Self {
        let y = self.last + crate::fixes::wrap_angle(nu - self.last);
        Drift {
            sum_t: self.sum_t + tau,
            sum_tt: self.sum_tt + tau * tau,
            sum_y: self.sum_y + y,
            sum_ty: self.sum_ty + tau * y,
            sum_yy: self.sum_yy + y * y,
            last: y,
        }
    }

    /// The line through the run's `m` innovations: its value at the run's first fix \[rad\],
    /// its slope \[rad/s\], the residuals' variance \[rad^2\], and the spread of the times
    /// \[s^2\] (the slope's variance is the residuals' over it); None with under 3 points or no
    /// spread.
    pub(crate) fn line(&self, m: u64) -> Option<(f64, f64, f64, f64)> {
        let n = m as f64;
        let stt = self.sum_tt - self.sum_t * self.sum_t / n;
        if m < 3 || stt <= 0.0 || !stt.is_finite() {
            return None;
        }
        let sty = self.sum_ty - self.sum_t * self.sum_y / n;
        let syy = self.sum_yy - self.sum_y * self.sum_y / n;
        let slope = sty / stt;
        let start = (self.sum_y - slope * self.sum_t) / n;
        Some((start, slope, (syy - slope * sty) / (n - 2.0), stt))
    }

    /// The checks of a run's drift read back: every sum finite, the sums of squares >= 0.
    #[cfg(feature = "serde")]
    pub(crate) fn check(&self) -> Result<(), crate::Error> {
        let sums = [
            self.sum_t,
            self.sum_tt,
            self.sum_y,
            self.sum_ty,
            self.sum_yy,
            self.last,
        ];
        let squares = [self.sum_tt, self.sum_yy];
        let bad = sums.into_iter().find(|v| !v.is_finite());
        match bad.or(squares.into_iter().find(|&v| v < 0.0)) {
            Some(value) => Err(crate::Error::InvalidParameter {
                name: "rejected run drift",
                value,
                valid: "finite, its sums of squares >= 0",
            }),
            None => Ok(()),
        }
    }
}
