//! Where the heading-fix filter's block loop ([`Fusion::run`]) writes each sample's estimate:
//! the filtered one into the caller's columns, or the smoothed one of a whole log.

use super::{Fusion, Knot};
use crate::fixes_output::{Estimate, FusionOutputs};
use crate::fixes_smooth::smoothed;

/// Where [`Fusion::run`] writes each sample's estimate.
pub(crate) trait Write {
    /// Sample `k`'s estimate: the filter `fusion` standing at `now`, whose segment's calibration
    /// is `calibration`.
    fn write(&mut self, k: usize, fusion: &Fusion, now: f64, calibration: (f64, f64));
}

/// The filtered estimate into the columns, the bias and scale only if `CALIBRATION`.
pub(super) struct Columns<'a, const CALIBRATION: bool>(pub(super) FusionOutputs<'a>);

impl<const CALIBRATION: bool> Write for Columns<'_, CALIBRATION> {
    #[inline(always)]
    fn write(&mut self, k: usize, fusion: &Fusion, now: f64, calibration: (f64, f64)) {
        let (segment, config) = (&fusion.segment, &fusion.config);
        self.0
            .set::<CALIBRATION>(k, segment, now, config, calibration);
    }
}

/// The smoothed estimate into the columns, from the filtered one and the next knot's correction.
pub(super) struct Smoothing<'a, 'k> {
    pub(super) out: FusionOutputs<'a>,
    pub(super) knots: &'k [Knot],
}

impl Write for Smoothing<'_, '_> {
    #[inline(always)]
    fn write(&mut self, k: usize, fusion: &Fusion, now: f64, _calibration: (f64, f64)) {
        let s = &fusion.segment;
        let (x, p) = (s.state(now), s.covariance(now, &fusion.config));
        // The segment's knot is the first sample's, the last fix applied or the last restart
        // of the clock: the next is the knot after it, if any.
        let next = fusion
            .counts
            .applied
            .checked_add(fusion.restarts)
            .and_then(|j| usize::try_from(j).ok())
            .and_then(|j| self.knots.get(j.checked_add(1)?));
        let (x, p) = match next {
            Some(next) => {
                let c = next.reached_at() - now;
                smoothed(&x, &p, next.a - s.a(), c, &next.w, &next.e)
            }
            None => (x, p),
        };
        self.out.set_estimate(k, &Estimate::of(&x, &p));
    }
}
