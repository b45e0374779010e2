//! [`Streaming`]: any [`Kernel`] as a stand-alone stage with its own clock (the [`Stage`]
//! trait), so that each stage is usable and testable on its own.

use super::{Kernel, Signal, Validated};
use crate::stage::{check_len, check_stage_block, Clock, Stage};
use crate::validate::{
    check_lengths, interval_key, usable_reading, Checks, MAX_TIME, MIN_INTERVAL,
};
use crate::Error;

/// A kernel as a stand-alone stage: its configuration, its state and its own [`Clock`], fed
/// `(t, rate)` samples through the [`Stage`] trait. The pipeline does not use this wrapper: it
/// keeps one clock for the whole chain.
///
/// Read back with the `serde` feature, its configuration is checked ([`Validated::check`]), its
/// state (`Kernel::check_state`, a method of that feature alone), its clock within
/// +-[`MAX_TIME`] and its last output.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(bound = "", remote = "Self")
)]
pub struct Streaming<K: Kernel> {
    config: K::Config,
    state: K::State,
    clock: Clock,
    /// True once the stage has had its first sample.
    started: bool,
    /// The last output, repeated for a sample whose timestamp does not move forward.
    last: f64,
}

impl<K: Validated> Streaming<K> {
    /// Validates `settings` and builds the stage.
    pub fn new(settings: K::Settings) -> Result<Self, Error> {
        let config = K::configure(settings)?;
        Ok(Streaming {
            config,
            state: K::start(&config),
            clock: Clock::default(),
            started: false,
            last: 0.0,
        })
    }

    /// The checks of a stage read back (`serde` feature): its configuration as `new` checks it,
    /// its state, its clock, and its last output (repeated as it is for a skipped sample).
    #[cfg(feature = "serde")]
    pub(crate) fn check_restored(&self) -> Result<(), Error> {
        K::check(&self.config)?;
        K::check_state(&self.config, &self.state)?;
        self.clock.check_restored()?;
        crate::error::check_stored("last output", self.last)
    }

    /// The configuration and the state.
    pub(crate) fn parts(&self) -> (&K::Config, &K::State) {
        (&self.config, &self.state)
    }

    /// Mutable access to the configuration and the state, for a stage's own methods.
    pub(crate) fn parts_mut(&mut self) -> (&mut K::Config, &mut K::State) {
        (&mut self.config, &mut self.state)
    }

    /// Feeds one sample whose interval is `dt` \[s\] (ignored for the stage's first sample),
    /// for a caller that keeps its own clock. An interval that is NaN, below [`MIN_INTERVAL`] or
    /// beyond twice [`MAX_TIME`] (no two valid timestamps lie further apart), or a reading
    /// [`Stage::update`] skips, leaves the stage as it was and gets the last output again: a NaN
    /// or negative interval made the low-pass NaN for good, and a NaN one stopped HDR's steps.
    /// It keeps no clock: a stage fed by `step`, then by [`Stage::update`] or
    /// [`Stage::process_block`], takes their first sample as the start of its clock only.
    #[inline]
    pub fn step(&mut self, dt: f64, rate: f64) -> f64 {
        let interval_valid = !self.started || interval_key(dt) <= interval_key(2.0 * MAX_TIME);
        if interval_valid && usable_reading(rate, None) {
            self.take(dt, rate)
        } else {
            self.last
        }
    }

    /// [`Streaming::step`] of a sample already checked.
    #[inline(always)]
    fn take(&mut self, dt: f64, rate: f64) -> f64 {
        let x = Signal::corrected(rate);
        let y = if self.started {
            K::step(&self.config, &mut self.state, dt, x)
        } else {
            self.started = true;
            K::first(&self.config, &mut self.state, x)
        };
        self.last = K::output(y);
        self.last
    }
}

impl<K: Validated> Stage for Streaming<K> {
    type Output = f64;

    /// Feeds one sample. A sample whose timestamp [`Clock::interval`] refuses, or whose rate is
    /// not finite or lies beyond [`MAX_READING`](crate::MAX_READING), leaves the stage as it was
    /// and gets the last output again (0 before the first), as [`crate::Pipeline::update`] skips
    /// it: a NaN taken into the state made every later output NaN.
    #[inline]
    fn update(&mut self, t: f64, rate: f64) -> f64 {
        match self.clock.interval(t) {
            Some(dt) if usable_reading(rate, None) => {
                self.clock.set(t);
                // `step`, not `take`: after `step`, which keeps no clock, the clock's first
                // interval is 0, which the stage must not take (the de-lag divided by it)
                self.step(dt, rate)
            }
            _ => self.last,
        }
    }

    fn last_time(&self) -> Option<f64> {
        self.clock.last()
    }

    /// Checked as [`Stage::process_block`] checks a block, the same outputs as
    /// [`Stage::update`], at about the loop's cost alone: as the pipeline's loop does, each sample
    /// is taken as it comes and checked on the way (a few integer operations beside the stage's
    /// work, where a pass of its own over a block too large for the cache cost as much as the
    /// stage); only if one may have failed is the block checked exactly, and the stage restored
    /// if it did.
    fn process_block(&mut self, t: &[f64], rate: &[f64], out: &mut [f64]) -> Result<(), Error> {
        check_lengths(t, rate, None)?;
        check_len("out", out.len(), t.len())?;
        let (Some(&first), Some(&end)) = (t.first(), t.last()) else {
            return Ok(());
        };
        let before = (self.state, self.clock, self.started, self.last);
        let mut checks = Checks::default();
        checks.reading(rate[0], None);
        // The stage's first sample has no interval (and ignores the one it is given); a stage
        // fed by `step`, which keeps no clock, has none for the block's first sample, which only
        // starts the clock (as `update` takes it).
        let (mut previous, skip) = match (self.clock.last(), self.started) {
            (Some(last), _) => (last, 0),
            (None, true) => (first, 1),
            (None, false) => (first - MIN_INTERVAL, 0),
        };
        out[..skip].fill(self.last);
        let taken = out[skip..].iter_mut().zip(&t[skip..]).zip(&rate[skip..]);
        for ((o, &ti), &ri) in taken {
            let dt = ti - previous;
            checks.interval(dt);
            checks.reading(ri, None);
            *o = self.take(dt, ri);
            previous = ti;
        }
        checks.time(first);
        checks.time(end);
        self.clock.set(end);
        if !checks.passed() {
            if let Err(e) = check_stage_block(t, rate, out.len(), before.1.last()) {
                (self.state, self.clock, self.started, self.last) = before;
                return Err(e);
            }
        }
        Ok(())
    }

    fn reset(&mut self) {
        self.state = K::start(&self.config);
        self.clock = Clock::default();
        self.started = false;
        self.last = 0.0;
    }
}
