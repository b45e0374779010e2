//! The checks of a block's samples and fixes before the filter takes any of them: a bad fix, or
//! one that comes before a fix or a sample already processed, is an error that names it.

use super::{Fix, Fusion, FusionOutputs, MIN_FIX_SIGMA};
use crate::fixes_error::{FixProblem, FusionError};
use crate::{check_block, Error, MAX_READING, MAX_TIME};

impl Fusion {
    /// The checks of a block before any sample: the outputs' lengths, the samples, the fixes.
    pub(super) fn check_inputs(
        &self,
        t: &[f64],
        rate: &[f64],
        fixes: &[Fix],
        out: &FusionOutputs<'_>,
    ) -> Result<(), FusionError> {
        out.check(t.len())?;
        check_block(t, rate, None, self.previous_sample(), true).map_err(Error::of_stream)?;
        self.check_fixes(reachable(fixes, t.last().copied()))
    }

    /// Checks every fix of `fixes`, processing nothing: the error names the first bad one (a
    /// stage after other stages checks its fixes before any stage runs). A block checks the fixes
    /// it reaches ([`reachable`]): a bad fix past its last sample is an error of the block that
    /// reaches it.
    pub fn check_fixes(&self, fixes: &[Fix]) -> Result<(), FusionError> {
        let mut previous = self.last_fix;
        for (index, f) in fixes.iter().enumerate() {
            let bad = |what, value, problem| FusionError::Fix {
                index,
                what,
                value,
                problem,
            };
            if !f.t.is_finite() {
                return Err(bad("t", f.t, FixProblem::NonFinite));
            }
            if f.t.abs() >= MAX_TIME {
                return Err(bad("t", f.t, FixProblem::OutOfRange));
            }
            if !f.heading.is_finite() {
                return Err(bad("heading", f.heading, FixProblem::NonFinite));
            }
            // Beyond about 1e16 rad, wrapping the innovation gives 0: the fix would pass for one
            // that agrees exactly.
            if f.heading.abs() > MAX_READING {
                return Err(bad("heading", f.heading, FixProblem::OutOfRange));
            }
            if !f.sigma.is_finite() {
                return Err(bad("sigma", f.sigma, FixProblem::NonFinite));
            }
            if f.sigma <= 0.0 {
                return Err(bad("sigma", f.sigma, FixProblem::NotPositive));
            }
            // Its square must be a normal number: two fixes of sigma 1e-200 at one time gave an
            // innovation variance of 0, and 0 / 0 from then on.
            if !(MIN_FIX_SIGMA..=MAX_READING).contains(&f.sigma) {
                return Err(bad("sigma", f.sigma, FixProblem::OutOfRange));
            }
            if let Some(p) = previous.filter(|&p| f.t < p) {
                return Err(bad("t", f.t, FixProblem::OutOfOrder { previous: p }));
            }
            if let Some(a) = self.anchor.filter(|a| f.t < a.t && !self.restarted) {
                return Err(bad("t", f.t, FixProblem::Late { processed: a.t }));
            }
            previous = Some(f.t);
        }
        Ok(())
    }
}

/// The fixes a block whose last sample is at `last` (None: an empty block) reaches, and the first
/// one past it: the ones it checks. The rest wait for a later block, which checks them when it
/// reaches them, so that a caller who passes every fix still to come with each block (as
/// [`Fusion::process_block`] asks: the unused ones again) pays for the fixes a block reaches, not
/// for all of them on every call.
pub fn reachable(fixes: &[Fix], last: Option<f64>) -> &[Fix] {
    let until = last.unwrap_or(f64::NEG_INFINITY);
    // `<=` is false for a NaN time: the scan stops there and the NaN fix is checked
    let before = fixes.iter().take_while(|f| f.t <= until).count();
    &fixes[..fixes.len().min(before + 1)]
}
