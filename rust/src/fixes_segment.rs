//! The heading-fix filter between two fixes, in closed form: the state and covariance at any
//! time after the last fix (or the first sample) follow from theirs there and three running
//! integrals of the rate, instead of a covariance step `F P F^T + Q` per sample.
//!
//! Between fixes Hong eq 4 moves the heading alone (`s_bar` and `b_bar` are constant), so from a
//! knot at `t_0` the heading is `psi = psi_0 + s_bar A + b_bar C`, with `A` the integral of the
//! gyro's rate since the knot (the trapezoid rule: the rate linear between samples) and
//! `C = t - t_0`. The samples' transitions `[[1, dt m, dt], [0, 1, 0], [0, 0, 1]]` (`m` an
//! interval's mean rate) compose into `F = [[1, A, C], [0, 1, 0], [0, 0, 1]]`, and the covariance
//! is `F P_0 F^T + Q` with the white noises on `psi'` (`N^2`), `s_bar'` (`q_s`) and `b_bar'`
//! (`K^2`) integrated over the segment:
//!
//! - `Q00 = N^2 C + K^2 C^3 / 3 + q_s J`, `J = int (A - a)^2 dt = A^2 C - 2 A I_1 + I_2`,
//! - `Q01 = q_s int (A - a) dt = q_s (A C - I_1)`, `Q02 = K^2 C^2 / 2`,
//! - `Q11 = q_s C`, `Q22 = K^2 C`, `Q12 = 0`,
//!
//! where `a` is the rate's integral from the knot (linear within each interval, as the
//! per-sample discretisation takes it), `I_1 = int a dt` and `I_2 = int a^2 dt`. In exact
//! arithmetic this is the product of the per-sample steps; tests/fixes.rs checks it against them.
//! It costs a few operations per sample where the step cost about forty, and the covariance is
//! formed only where it is used: at a fix, and for a sample whose heading sigma is asked for.

use crate::fixes::FusionConfig;
use crate::fixes_output::{calibration_of, sigma_of};
use crate::fixes_smooth::Mat3;

/// The last gyro sample and the point the state is propagated to (a sample or a fix time).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Anchor {
    pub(crate) sample_t: f64,
    pub(crate) sample_rate: f64,
    pub(crate) t: f64,
    pub(crate) rate: f64,
}

impl Anchor {
    /// The anchor at a gyro sample `(t, rate)`.
    pub(crate) fn of_sample(t: f64, rate: f64) -> Self {
        Anchor {
            sample_t: t,
            sample_rate: rate,
            t,
            rate,
        }
    }

    /// Checks an anchor read back (`serde` feature): its times within +-2^40 s, its rates
    /// within [`MAX_STORED`](crate::error::MAX_STORED) (a stored rate of 1e308 gave NaN
    /// headings).
    #[cfg(feature = "serde")]
    pub(crate) fn check(&self) -> Result<(), crate::Error> {
        use crate::error::{check_range, check_stored};
        let limit = crate::MAX_TIME;
        for t in [self.sample_t, self.t] {
            check_range("filter time", t, -limit, limit, "within +-2^40 s")?;
        }
        check_stored("filter rate", self.sample_rate)?;
        check_stored("filter rate", self.rate)
    }
}

/// The filter from its last knot (a fix applied, or the first sample) to the last point it was
/// moved to.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Segment {
    /// The knot's time \[s\].
    t: f64,
    /// The state `[psi, s_bar, b_bar]` at the knot.
    x: [f64; 3],
    /// Its covariance.
    p: Mat3,
    /// `A`: the rate's integral from the knot to the last point \[rad\].
    a: f64,
    /// `2 I_1 = 2 int a dt` \[rad s\] (the factor taken out of every sample's term).
    i1_2: f64,
    /// `3 I_2 = 3 int a^2 dt` \[rad^2 s\] (likewise: no division per sample).
    i2_3: f64,
}

impl Segment {
    /// A segment starting at `t` from state `x` with covariance `p`.
    pub(crate) fn new(t: f64, x: [f64; 3], p: Mat3) -> Self {
        Segment {
            t,
            x,
            p,
            a: 0.0,
            i1_2: 0.0,
            i2_3: 0.0,
        }
    }

    /// The same state and covariance, knotted at `t` (the first sample: nothing has moved yet).
    pub(crate) fn starting_at(self, t: f64) -> Self {
        Segment::new(t, self.x, self.p)
    }

    /// Checks a segment read back (`serde` feature): its time within +-2^40 s, every value
    /// within [`MAX_STORED`](crate::error::MAX_STORED) (a stored rate integral of 1e308 gave
    /// infinite headings), the heading within [`MAX_HEADING`](crate::error::MAX_HEADING), a
    /// scale `s_bar` of which Hong eq 1's bias and scale are finite (one of 0 gave a NaN bias),
    /// and a covariance that is one ([`check`](crate::fixes_covariance::check): a negative bias
    /// variance gave NaN or imaginary sigmas).
    #[cfg(feature = "serde")]
    pub(crate) fn check(&self) -> Result<(), crate::Error> {
        use crate::error::{check_range, check_stored};
        let limit = crate::MAX_TIME;
        check_range("segment time", self.t, -limit, limit, "within +-2^40 s")?;
        for v in self.x.iter().chain(self.p.iter().flatten()) {
            check_stored("filter state", *v)?;
        }
        crate::error::check_heading("filter heading", self.x[0])?;
        for v in [self.a, self.i1_2, self.i2_3] {
            check_stored("rate integral", v)?;
        }
        let (bias, scale) = self.calibration();
        // Not required > 0: fixes far tighter than the gyro and contradicting each other drive
        // the filter itself there (tests/fixes_precision.rs), and its state must read back.
        if !(bias.is_finite() && scale.is_finite()) {
            return Err(crate::Error::InvalidParameter {
                name: "filter scale",
                value: self.x[1],
                valid: "s_bar = 1/(1+s) of Hong eq 3, of which eq 1's bias -b_bar/s_bar and \
                        scale 1/s_bar - 1 are finite (not 0)",
            });
        }
        crate::fixes_covariance::check(&self.p)
    }

    /// Fails unless the knot's time is at or before `now`, the time the filter stands at: the
    /// segment runs forward from its knot (one after it integrated the time between as rate).
    #[cfg(feature = "serde")]
    pub(crate) fn check_before(&self, now: f64) -> Result<(), crate::Error> {
        let valid = "at or before the time the filter stands at (the knot is a fix or sample \
                     already passed)";
        crate::error::check_range("segment time", self.t, f64::NEG_INFINITY, now, valid)
    }

    /// Extends the segment by an interval `dt` \[s\] over which the rate's mean is `m` \[rad/s\].
    #[inline(always)]
    pub(crate) fn extend(&mut self, dt: f64, m: f64) {
        let (a0, a1) = (self.a, self.a + dt * m);
        self.i1_2 += dt * (a0 + a1);
        self.i2_3 += dt * (a0 * a0 + a0 * a1 + a1 * a1);
        self.a = a1;
    }

    /// `A`: the rate's integral from the knot to the last point \[rad\].
    #[inline(always)]
    pub(crate) fn a(&self) -> f64 {
        self.a
    }

    /// Hong eq 1's bias and scale error of the segment (constant until the next fix).
    #[inline(always)]
    pub(crate) fn calibration(&self) -> (f64, f64) {
        calibration_of(&self.x)
    }

    /// The heading at `t`, the time of the last point (Hong eq 4 summed over the segment).
    #[inline(always)]
    pub(crate) fn heading(&self, t: f64) -> f64 {
        self.x[0] + self.x[1] * self.a + self.x[2] * (t - self.t)
    }

    /// The state at `t`, the time of the last point.
    #[inline(always)]
    pub(crate) fn state(&self, t: f64) -> [f64; 3] {
        [self.heading(t), self.x[1], self.x[2]]
    }

    /// The heading's variance at `t`, the time of the last point: `P00` of
    /// [`Segment::covariance`] alone, `[1, A, C] P_0 [1, A, C]^T + Q00`, written out so that a
    /// sample whose sigma is asked for takes a dozen operations.
    #[inline(always)]
    pub(crate) fn heading_variance(&self, t: f64, config: &FusionConfig) -> f64 {
        let (c, a, p) = (t - self.t, self.a, &self.p);
        let (qs, qb) = noise_densities(config);
        let quadratic = p[0][0]
            + a * (2.0 * p[0][1] + a * p[1][1] + 2.0 * c * p[1][2])
            + c * (2.0 * p[0][2] + c * p[2][2]);
        // J >= 0 in exact arithmetic; rounding of its terms can take a tiny one below.
        let j = (a * (a * c - self.i1_2) + self.i2_3 * THIRD).max(0.0);
        quadratic + c * (config.arw * config.arw + qb * THIRD * c * c) + qs * j
    }

    /// The heading's standard deviation at `t` ([`sigma_of`] its variance; docs/fixes_rust.md,
    /// "A heading variance that rounds below 0", on why no branch). The covariance the filter carries on with keeps the variance
    /// as computed.
    #[inline(always)]
    pub(crate) fn heading_sigma(&self, t: f64, config: &FusionConfig) -> f64 {
        sigma_of(self.heading_variance(t, config))
    }

    /// The covariance at `t`, the time of the last point.
    #[inline(always)]
    pub(crate) fn covariance(&self, t: f64, config: &FusionConfig) -> Mat3 {
        let (c, a, p) = (t - self.t, self.a, &self.p);
        // the first row of F P_0
        let r: [f64; 3] = core::array::from_fn(|j| p[0][j] + a * p[1][j] + c * p[2][j]);
        let (qs, qb) = noise_densities(config);
        let p00 = self.heading_variance(t, config);
        let p01 = r[1] + qs * (a * c - self.i1_2 / 2.0);
        let p02 = r[2] + qb * c * c / 2.0;
        [
            [p00, p01, p02],
            [p01, p[1][1] + qs * c, p[1][2]],
            [p02, p[2][1], p[2][2] + qb * c],
        ]
    }
}

/// One third, multiplied by where the formulas divide by 3 (a division per sample costs more
/// than the rest of a sample's arithmetic).
const THIRD: f64 = 1.0 / 3.0;

/// The scale walk's and the bias walk's noise densities `(q_s, K^2)`.
#[inline(always)]
fn noise_densities(config: &FusionConfig) -> (f64, f64) {
    (
        config.scale_walk * config.scale_walk,
        config.bias_walk * config.bias_walk,
    )
}
