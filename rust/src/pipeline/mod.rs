//! The whole chain in one pass: correction -> threshold -> low-pass -> HDR -> de-lag -> integrate.
//! No intermediate arrays: every enabled stage sees each sample once, in order.
//!
//! - [`config`]: what runs ([`PipelineConfig`], its rules, the [`Preset`]s);
//! - `engine`: the chains composed from a configuration and the loop over a block;
//! - `output`: what the pipeline writes per sample ([`Output`], [`Outputs`]);
//! - this module: the public [`Pipeline`], which takes samples one at a time ([`Pipeline::update`])
//!   or a block at a time ([`Pipeline::process_block`]), and the slow path that the loop leaves
//!   to it: the first sample, the rest window, gaps the policy restarts at, and readings it holds
//!   or skips;
//! - `slow_path`: one sample off the loop, admitted under the input policy and taken as the first
//!   sample, one after a gap, or a step;
//! - `clock`: a restart of the clock after it jumped back ([`Pipeline::restart_clock`]).

mod clock;
pub mod config;
mod engine;
mod output;
#[cfg(feature = "serde")]
mod readback;
mod slow_path;

pub use config::{NoiseScaled, PipelineConfig, Preset};
pub use output::{Output, Outputs};

use engine::{Block, Cursor, Engine};

use crate::input::{GapAction, InputReport, NonFinite};
use crate::rest::BiasEstimate;
use crate::rest::RestStatistics;
use crate::rest_tracker::{check_speed, Rest, RestTracker};
use crate::stage::Clock;
use crate::validate::{check_block, check_lengths, interval_key, Checks};
use crate::Error;

/// The composed pipeline; see the module doc for the order of the stages.
///
/// With the `serde` feature it serialises whole (its configuration, every stage's state and the
/// input report), and a pipeline read back carries on bit for bit where it was (with
/// `serde_json`, enable its `float_roundtrip` feature: without it the last digit of a float may
/// change). Reading one back checks it as [`Pipeline::new`] checks a configuration, and checks
/// that its stages are the ones the configuration builds, with the values the rest of the state
/// gives them (the configured bias, dead band and HDR bound wherever nothing measured changes
/// them, the static bias test's bias, the noise-scaled values its rest window gives), holding
/// values that valid input reaches (`Kernel::check_state`, a method of that feature alone), and
/// that its parts agree with each other (the rest window with the configured one and the clock,
/// the rest tracker's times and sums): a state edited by hand or
/// damaged is the deserialiser's error (with this crate's words), never a pipeline that runs on
/// values `new` refuses. To change a parameter, build a new pipeline from the edited
/// configuration.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(remote = "Self")
)]
pub struct Pipeline {
    config: PipelineConfig,
    engine: Engine,
    /// The static bias test of the rest window, while it runs and after.
    bias: BiasEstimate,
    clock: Clock,
    /// The last finite (rate, temperature) reading, for [`NonFinite::Hold`].
    last_reading: Option<(f64, Option<f64>)>,
    /// The last output, repeated (with a NaN rate) for a skipped sample.
    last_output: Output,
    report: InputReport,
    /// True until the [`NoiseScaled`] values are set from the rest window.
    scaling_pending: bool,
    /// True from [`Pipeline::restart_clock`] to the next sample taken, which starts the new
    /// time base.
    #[cfg_attr(feature = "serde", serde(default))]
    clock_restarted: bool,
    /// How many times [`Pipeline::restart_clock`] restarted the clock.
    #[cfg_attr(feature = "serde", serde(default))]
    clock_restarts: u64,
}

impl Pipeline {
    /// Validates the configuration ([`PipelineConfig::validate`]) and builds the pipeline.
    pub fn new(config: PipelineConfig) -> Result<Self, Error> {
        config.validate()?;
        Ok(Pipeline {
            config,
            engine: Engine::new(&config),
            bias: BiasEstimate::new(config.correction.bias),
            clock: Clock::default(),
            last_reading: None,
            last_output: Output {
                heading: config.integrator.initial_heading,
                ..Output::default()
            },
            report: InputReport::default(),
            scaling_pending: config.noise_scaled.any() || config.rest_tracker.is_some(),
            clock_restarted: false,
            clock_restarts: 0,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &PipelineConfig {
        &self.config
    }

    /// The static bias in use now [rad/s] and how many readings it averages.
    pub fn bias(&self) -> (f64, u64) {
        (self.bias.value(), self.bias.count())
    }

    /// True while a rest window is still being measured.
    pub fn bias_learning(&self) -> bool {
        self.bias.learning()
    }

    /// The last timestamp processed, if any.
    pub fn last_time(&self) -> Option<f64> {
        self.clock.last()
    }

    /// What the input policy has done so far (held, skipped samples; gaps).
    pub fn report(&self) -> InputReport {
        self.report
    }

    /// Returns every stage to its initial state (same as a new pipeline with the same config).
    pub fn reset(&mut self) {
        // The configuration was validated when the pipeline was built.
        if let Ok(fresh) = Pipeline::new(self.config) {
            *self = fresh;
        }
    }

    /// The rest window's noise and the standard error of the bias measured in it, once the
    /// window is over (see [`crate::Correction::rest_statistics`]).
    pub fn rest_statistics(&self) -> Option<RestStatistics> {
        self.bias.rest_statistics()
    }

    /// The error for a rest window that the stream has passed without a reading inside it, once a
    /// sample past the window's end has come (`None` before, and for every other bias source).
    ///
    /// [`Pipeline::process_block`] returns this error itself; a caller of the infallible
    /// [`Pipeline::update`] asks here, because such a pipeline goes on with a bias of 0.
    pub fn rest_window_missed(&self) -> Option<Error> {
        let last = self.clock.last()?;
        self.bias.missed(last).filter(|_| !self.bias.learning())
    }

    /// The rest tracker (the filtered bias and the rests found), when the configuration has one.
    pub fn rest_tracker(&self) -> Option<&RestTracker> {
        self.engine.rest_tracker()
    }

    /// Feeds one sample (`t` \[s\], `rate` [rad/s]) without a temperature; see
    /// [`Pipeline::update_with_temperature`] for what is skipped. With a temperature model
    /// ([`CorrectionConfig::temperature`](crate::CorrectionConfig::temperature)) every sample
    /// needs a temperature, and each one given here is skipped (counted in [`Pipeline::report`]).
    #[inline]
    pub fn update(&mut self, t: f64, rate: f64) -> Output {
        self.update_with_temperature(t, rate, None)
    }

    /// Feeds one sample with the sensor temperature \[degC\] for the temperature scale model.
    ///
    /// Infallible and allocation-free. A sample whose timestamp [`Clock::interval`] refuses is
    /// skipped, and so is a reading that is not finite or lies beyond
    /// [`MAX_READING`](crate::MAX_READING) unless the policy holds the last one (a missing
    /// temperature where the model needs one counts as non-finite): a skipped sample leaves every
    /// stage untouched and gets the last heading and drift with a NaN rate (counted in
    /// [`Pipeline::report`]). A clock that jumps back (a time sync) has every sample skipped
    /// until it passes the last time taken, the heading frozen meanwhile: feed a monotonic clock
    /// (a jump forward is a gap, [`InputPolicy::gap_limit`](crate::InputPolicy::gap_limit)), or
    /// watch `report().skipped` and go on with [`Pipeline::restart_clock`]. Use
    /// [`Pipeline::process_block`] to have bad input rejected instead; a rest window the samples
    /// pass without a reading inside leaves the bias at 0 here, which
    /// [`Pipeline::rest_window_missed`] tells.
    pub fn update_with_temperature(
        &mut self,
        t: f64,
        rate: f64,
        temperature: Option<f64>,
    ) -> Output {
        self.update_with_speed(t, rate, temperature, f64::NAN)
    }

    /// [`Pipeline::update_with_temperature`] with the vehicle's speed [m/s] for the rest tracker
    /// (NaN: none for this sample, the tracker judges it by the rate alone). An infinite speed,
    /// which [`Pipeline::process_block_with_speed`] refuses, is taken as none.
    pub fn update_with_speed(
        &mut self,
        t: f64,
        rate: f64,
        temperature: Option<f64>,
        speed: f64,
    ) -> Output {
        // A speed sensor's garbage: taken as moving, it cut a rest in two without a word.
        let speed = if speed.is_infinite() { f64::NAN } else { speed };
        let first = self.clock.last().is_none();
        let Some((dt, rate, temperature)) = self.admit(t, rate, temperature) else {
            self.report.skipped = self.report.skipped.saturating_add(1);
            return Output {
                rate: f64::NAN,
                ..self.last_output
            };
        };
        self.last_output = self.take(first, dt, rate, temperature, speed);
        self.last_output
    }

    /// Checks a block (lengths; finite, strictly increasing time, also after the previous block;
    /// finite readings unless the policy holds or skips them; a rest window that holds a sample)
    /// and feeds it through the pipeline, writing the outputs asked for. On an error the
    /// pipeline is as it was before the block (the outputs are not).
    ///
    /// The settled samples (after the first, past the rest window) run through the chain's loop,
    /// which checks them on the way; the pipeline is restored if any fails, and the block is
    /// checked again only then, to name the first bad sample. The copy it restores from lives on
    /// the stack for the call: `size_of::<Pipeline>()`, about 2.3 KB with the rest tracker's
    /// chain (a small target's stack must hold it twice).
    pub fn process_block(
        &mut self,
        t: &[f64],
        rate: &[f64],
        temperature: Option<&[f64]>,
        out: Outputs<'_>,
    ) -> Result<(), Error> {
        self.process_block_with_speed(t, rate, temperature, None, out)
    }

    /// [`Pipeline::process_block`] with the vehicle's speed [m/s] per sample for the rest
    /// tracker (NaN where there is none: the tracker judges that sample by the rate alone). A
    /// speed of the wrong length is an error, and an infinite one is refused (naming its index).
    pub fn process_block_with_speed(
        &mut self,
        t: &[f64],
        rate: &[f64],
        temperature: Option<&[f64]>,
        speed: Option<&[f64]>,
        out: Outputs<'_>,
    ) -> Result<(), Error> {
        self.process_block_reporting(t, rate, temperature, speed, out, &mut |_| {})
    }

    /// [`Pipeline::process_block_with_speed`] that hands `on_rest` every rest the tracker finds,
    /// as it ends, in order (however many: nothing is kept). On an error the pipeline is as it
    /// was before the block, and the rests handed over during the call are void.
    pub fn process_block_reporting(
        &mut self,
        t: &[f64],
        rate: &[f64],
        temperature: Option<&[f64]>,
        speed: Option<&[f64]>,
        mut out: Outputs<'_>,
        on_rest: &mut dyn FnMut(Rest),
    ) -> Result<(), Error> {
        if self.config.correction.temperature.is_some() && temperature.is_none() {
            return Err(Error::MissingTemperature);
        }
        check_lengths(t, rate, temperature)?;
        if let Some(s) = speed {
            check_speed(s, t.len())?;
        }
        out.check(t.len())?;
        let block = Block {
            t,
            rate,
            temperature,
            speed,
        };
        let before = self.clone();
        let result = self.feed(&block, &mut out, on_rest);
        if result.is_err() {
            *self = before;
        }
        result.map_err(Error::of_stream)
    }

    /// [`Pipeline::process_block`] after its checks of lengths.
    fn feed(
        &mut self,
        block: &Block<'_>,
        out: &mut Outputs<'_>,
        on_rest: &mut dyn FnMut(Rest),
    ) -> Result<(), Error> {
        let n = block.t.len();
        let mut next = 0;
        let mut found = self.rest_tracker().map_or(0, RestTracker::rests_found);
        while next < n {
            if self.settled() {
                next = self.run(block, next, out)?;
                // The loop stops after a sample that ends a rest: hand it over, and go on.
                if self.engine.report_rest(&mut found, on_rest) {
                    continue;
                }
                if next == n {
                    break;
                }
            }
            let o = self.sample_of_block(block, next)?;
            out.first(n).set(next, o);
            next += 1;
            self.engine.report_rest(&mut found, on_rest);
        }
        Ok(())
    }

    /// True once the first sample is in and the rest window is over and applied: from then on
    /// the chain's loop takes the samples.
    fn settled(&self) -> bool {
        self.previous_time().is_some() && !self.bias.learning() && !self.scaling_pending
    }

    /// The chain's loop from sample `from` of a settled pipeline, to the end of the block or to
    /// a sample that needs the slow path; returns where it stopped, or the block's first error.
    fn run(
        &mut self,
        block: &Block<'_>,
        from: usize,
        out: &mut Outputs<'_>,
    ) -> Result<usize, Error> {
        let policy = self.config.input;
        let previous = self.clock.last().unwrap_or(f64::NAN);
        let mut cursor = Cursor {
            next: from,
            previous,
            checks: Checks::default(),
            last: self.last_output,
        };
        // The loop stops only where the policy needs the slow path: at a gap it restarts at, or
        // a reading it holds or skips. Otherwise it takes every sample and they are checked.
        let stops = (policy.gap_action == GapAction::Reset
            || policy.non_finite != NonFinite::Error)
            .then(|| match policy.gap_action {
                GapAction::Reset => interval_key(policy.gap_limit.min(f64::MAX)),
                GapAction::Bridge => interval_key(f64::MAX),
            });
        self.engine.run(block, &mut cursor, stops, out);
        let end = cursor.next;
        if end > from {
            // time increases within the samples taken, so their ends bound them all
            cursor.checks.time(block.t[from]);
            cursor.checks.time(block.t[end - 1]);
        }
        let (t, rate) = (&block.t[from..end], &block.rate[from..end]);
        let temperature = block.temperature.map(|temp| &temp[from..end]);
        if !cursor.checks.passed() {
            let must_be_finite = policy.non_finite == NonFinite::Error;
            check_block(t, rate, temperature, Some(previous), must_be_finite)
                .map_err(|e| e.with_index_offset(from))?;
        }
        // The checks have the longest interval; only if it is a gap are the gaps counted, in a
        // pass over the timestamps: the loop carries nothing for them.
        if let Some(longest) = cursor
            .checks
            .longest_interval()
            .filter(|&dt| dt > policy.gap_limit)
        {
            self.report
                .gaps_up_to(intervals_over(previous, t, policy.gap_limit), longest);
        }
        if end > from {
            let last = end - 1;
            self.clock.set(block.t[last]);
            self.last_reading = Some((block.rate[last], block.temperature.map(|temp| temp[last])));
            self.last_output = cursor.last;
        }
        Ok(end)
    }

    /// Sample `i` of a block on the slow path: checked first, then taken as
    /// [`Pipeline::update_with_temperature`] takes it.
    fn sample_of_block(&mut self, block: &Block<'_>, i: usize) -> Result<Output, Error> {
        let (t, rate) = (block.t[i], block.rate[i]);
        let temperature = block.temperature.map(|temp| temp[i]);
        let must_be_finite = self.config.input.non_finite == NonFinite::Error;
        let temperatures = block.temperature.map(|temp| &temp[i..=i]);
        check_block(
            &[t],
            &[rate],
            temperatures,
            self.previous_time(),
            must_be_finite,
        )
        .map_err(|e| e.with_index_offset(i))?;
        let speed = block.speed.map_or(f64::NAN, |s| s[i]);
        let out = self.update_with_speed(t, rate, temperature, speed);
        match self.rest_window_missed() {
            Some(e) => Err(e),
            None => Ok(out),
        }
    }
}

/// How many of the intervals from `start` to `t[0]` and between the timestamps `t` are longer
/// than `limit`.
fn intervals_over(start: f64, t: &[f64], limit: f64) -> u64 {
    let previous = core::iter::once(start).chain(t.iter().copied());
    previous
        .zip(t)
        .map(|(a, &b)| u64::from(b - a > limit))
        .sum()
}
