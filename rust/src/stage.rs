//! What every streaming stage shares: the [`Stage`] trait and the [`Clock`] that turns
//! timestamps into the actual interval `T_i` of each sample.

use crate::validate::{check_block, MAX_TIME, MIN_INTERVAL};
use crate::Error;

/// A streaming stage: validated config + private state, fed one sample at a time.
///
/// `update` never fails and never allocates; `process_block` checks the block as
/// [`Pipeline::process_block`](crate::Pipeline::process_block) does, then runs the same loop.
pub trait Stage {
    /// What the stage emits per sample.
    type Output: Copy;

    /// Feeds one sample: `t` in seconds, `rate` in rad/s.
    fn update(&mut self, t: f64, rate: f64) -> Self::Output;

    /// Returns the stage to the state it had when it was created.
    fn reset(&mut self);

    /// The last timestamp the stage took \[s\], if it keeps one: a block must start after it.
    /// `None` (the default) checks each block on its own.
    fn last_time(&self) -> Option<f64> {
        None
    }

    /// Feeds a block of samples; `out[i]` receives the output for sample `i`.
    ///
    /// The block is checked first ([`check_block`](crate::check_block): lengths, finite and
    /// increasing times, also after [`Stage::last_time`], readings finite and within
    /// [`MAX_READING`](crate::MAX_READING)), and the error names the first bad sample by its
    /// index; a rejected block leaves the stage as it was (not `out`, which may have been
    /// written, as [`Pipeline::process_block`](crate::Pipeline::process_block)'s outputs).
    fn process_block(
        &mut self,
        t: &[f64],
        rate: &[f64],
        out: &mut [Self::Output],
    ) -> Result<(), Error> {
        check_stage_block(t, rate, out.len(), self.last_time())?;
        for ((o, &ti), &ri) in out.iter_mut().zip(t).zip(rate) {
            *o = self.update(ti, ri);
        }
        Ok(())
    }
}

/// The checks of [`Stage::process_block`]: the samples as [`check_block`] checks them after
/// `previous` (the stage's last time), and an output slice of `out` values as long as them.
pub(crate) fn check_stage_block(
    t: &[f64],
    rate: &[f64],
    out: usize,
    previous: Option<f64>,
) -> Result<(), Error> {
    check_block(t, rate, None, previous, true)?;
    check_len("out", out, t.len())
}

/// Fails with [`Error::LengthMismatch`] unless `len == expected`.
pub(crate) fn check_len(what: &'static str, len: usize, expected: usize) -> Result<(), Error> {
    if len == expected {
        Ok(())
    } else {
        Err(Error::LengthMismatch {
            what,
            len,
            expected,
        })
    }
}

/// [`check_len`] of each output slice given (`None`: not wanted), by name.
pub(crate) fn check_outputs<const N: usize>(
    slices: [(&'static str, Option<&[f64]>); N],
    expected: usize,
) -> Result<(), Error> {
    slices
        .into_iter()
        .filter_map(|(what, s)| s.map(|s| (what, s.len())))
        .try_for_each(|(what, len)| check_len(what, len, expected))
}

/// Remembers the last timestamp and gives the interval `T_i = t_i - t_{i-1}` of each sample.
///
/// The first sample has no interval (`T_0 = 0`). A timestamp that does not move forward by at
/// least [`MIN_INTERVAL`], or is not finite or beyond [`MAX_TIME`], also gets `T_i = 0`, so such a
/// sample adds nothing to any integral and cannot divide by zero; block processing rejects those
/// timestamps before they get here.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Clock {
    last: Option<f64>,
}

impl Clock {
    /// Interval since the previous timestamp, in seconds (0 for the first sample, and 0 for a
    /// timestamp [`Clock::interval`] refuses, which is then not taken as the last one).
    #[inline]
    pub fn tick(&mut self, t: f64) -> f64 {
        match self.interval(t) {
            Some(dt) => {
                self.last = Some(t);
                dt
            }
            None => 0.0,
        }
    }

    /// The interval `t` would have (0 for the first sample), or `None` if `t` is not finite, lies
    /// beyond [`MAX_TIME`] or does not move forward by at least [`MIN_INTERVAL`] (the limits of
    /// [`check_block`](crate::check_block)). Does not change the clock.
    #[inline]
    pub fn interval(&self, t: f64) -> Option<f64> {
        // also false for NaN
        let within = libm::fabs(t) < MAX_TIME;
        match self.last {
            _ if !within => None,
            Some(last) if t - last >= MIN_INTERVAL => Some(t - last),
            Some(_) => None,
            None => Some(0.0),
        }
    }

    /// Takes `t` as the last timestamp (after [`Clock::interval`] accepted it).
    #[inline]
    pub fn set(&mut self, t: f64) {
        self.last = Some(t);
    }

    /// The last accepted timestamp, if any.
    pub fn last(&self) -> Option<f64> {
        self.last
    }

    /// Checks a clock read back (`serde` feature): its last time strictly within +-2^40 s, as
    /// [`Clock::interval`] takes every time. One of -1e308 made the next block's first interval
    /// 1e308 (an infinite heading), one of 1e308 or of 2^40 itself refused every later block.
    #[cfg(feature = "serde")]
    pub(crate) fn check_restored(&self) -> Result<(), Error> {
        match self.last {
            Some(t) if libm::fabs(t) >= MAX_TIME || t.is_nan() => Err(Error::InvalidParameter {
                name: "last_time",
                value: t,
                valid: "within +-2^40 s, exclusive (as every time taken)",
            }),
            _ => Ok(()),
        }
    }
}
