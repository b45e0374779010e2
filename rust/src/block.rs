//! Block averaging on a grid of fixed intervals: the HDR paper's down-sampling (its second eq 14)
//! and the decision clock of the HDR stage, which keeps Table III's per-1-s-step meaning at any
//! input rate.

use crate::error::check_duration;
use crate::stage::{check_len, Clock};
use crate::validate::{check_block, usable_reading};
use crate::Error;

/// Time-weighted mean over consecutive blocks of `interval` seconds.
///
/// Sample `i` stands for the interval `(t_{i-1}, t_i]` (the rectangle rule of HDR eq 3), so the
/// mean is `sum(w_i T_i) / sum(T_i)`; for a regular rate this is the plain average of eq 14. A block
/// closes at the sample nearest to the grid boundary, and the leftover phase is carried so that
/// blocks average exactly `interval` over a long log. A gap restarts the grid.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct BlockMean {
    sum: f64,
    duration: f64,
    elapsed: f64,
}

impl BlockMean {
    /// Checks a block read back (`serde` feature) for a step of `interval` \[s\] over readings
    /// within [`MAX_READING`](crate::MAX_READING): the time taken in it >= 0 and at most the step
    /// and the longest interval, the time elapsed at least the carry a step leaves (-interval / 2),
    /// and the integral its mean within the readings' limit (a stored integral of 1e308 over a
    /// time of 1e-300 gave an infinite mean; a time of -1e308 never closed the step).
    #[cfg(feature = "serde")]
    pub(crate) fn check(&self, interval: f64) -> Result<(), Error> {
        use crate::error::check_range;
        let longest = interval + 2.0 * crate::MAX_TIME;
        let valid = "within 0 and the step's length plus the longest interval, 2^41 s";
        check_range("block duration", self.duration, 0.0, longest, valid)?;
        let valid = "within minus half the step's length and its length plus 2^41 s";
        check_range(
            "block elapsed",
            self.elapsed,
            -0.5 * interval,
            longest,
            valid,
        )?;
        crate::error::check_integral("block integral", self.sum, self.duration)
    }

    /// Adds a sample with interval `dt`; when this sample closes a block, returns the block's
    /// mean and duration [s].
    ///
    /// Always inlined: it runs on every sample of the pipeline's loop, and as a call it would
    /// make the loop's state escape to memory.
    #[inline(always)]
    pub(crate) fn push(&mut self, interval: f64, dt: f64, rate: f64) -> Option<(f64, f64)> {
        self.sum += rate * dt;
        self.duration += dt;
        self.elapsed += dt;
        if self.duration > 0.0 && self.elapsed >= interval - 0.5 * dt {
            let closed = (self.sum / self.duration, self.duration);
            // Keep the phase left over by sample placement; after a gap, start the grid afresh.
            let carry = self.elapsed - interval;
            *self = BlockMean {
                elapsed: if libm::fabs(carry) < 0.5 * interval {
                    carry
                } else {
                    0.0
                },
                ..BlockMean::default()
            };
            Some(closed)
        } else {
            None
        }
    }
}

/// Configuration of [`Downsample`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DownsampleConfig {
    /// Block length \[s\], > 0. The HDR paper averaged 10 Hz data into 1 s blocks.
    pub interval: f64,
}

impl DownsampleConfig {
    /// Checks the interval: > 0 and at most 2^40 s, as HDR's.
    pub fn validate(&self) -> Result<(), Error> {
        check_duration("interval", self.interval)
    }
}

/// Block down-sampling by averaging (the HDR paper's second eq 14:
/// `w_i^{1Hz} = 1/10 sum_j w_{10i+j}^{10Hz}`), generalised to irregular timestamps.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(remote = "Self")
)]
pub struct Downsample {
    config: DownsampleConfig,
    block: BlockMean,
    clock: Clock,
}

impl Downsample {
    /// Validates `config` ([`DownsampleConfig::validate`]) and builds the stage.
    pub fn new(config: DownsampleConfig) -> Result<Self, Error> {
        config.validate()?;
        Ok(Downsample {
            config,
            block: BlockMean::default(),
            clock: Clock::default(),
        })
    }

    /// Feeds one sample; returns `(t, mean rate)` when the sample at `t` closes a block. A
    /// sample whose time the [`Clock`] refuses, or whose rate is not finite or lies beyond
    /// [`MAX_READING`](crate::MAX_READING), is left out (a NaN made its block's mean NaN).
    #[inline]
    pub fn update(&mut self, t: f64, rate: f64) -> Option<(f64, f64)> {
        if self.clock.interval(t).is_none() || !usable_reading(rate, None) {
            return None;
        }
        let dt = self.clock.tick(t);
        self.block
            .push(self.config.interval, dt, rate)
            .map(|(mean, _)| (t, mean))
    }

    /// The checks of a stage read back (`serde` feature): its configuration as `new` checks it,
    /// its clock within +-2^40 s and its open block ([`BlockMean::check`]).
    #[cfg(feature = "serde")]
    pub(crate) fn check_restored(&self) -> Result<(), Error> {
        self.config.validate()?;
        self.clock.check_restored()?;
        self.block.check(self.config.interval)
    }

    /// The configuration.
    pub fn config(&self) -> &DownsampleConfig {
        &self.config
    }

    /// Returns the stage to its initial state.
    pub fn reset(&mut self) {
        self.block = BlockMean::default();
        self.clock = Clock::default();
    }

    /// Feeds a block; writes the closed blocks' end times and means to the front of `out_t` and
    /// `out_rate` (which must be as long as `t`) and returns how many were written. The block is
    /// checked first, as [`Stage::process_block`](crate::Stage::process_block) checks one.
    pub fn process_block(
        &mut self,
        t: &[f64],
        rate: &[f64],
        out_t: &mut [f64],
        out_rate: &mut [f64],
    ) -> Result<usize, Error> {
        check_block(t, rate, None, self.clock.last(), true)?;
        check_len("out_t", out_t.len(), t.len())?;
        check_len("out_rate", out_rate.len(), t.len())?;
        let mut n = 0;
        for (&ti, &ri) in t.iter().zip(rate) {
            if let Some((tb, mean)) = self.update(ti, ri) {
                out_t[n] = tb;
                out_rate[n] = mean;
                n += 1;
            }
        }
        Ok(n)
    }
}
