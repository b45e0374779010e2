//! Rest tracking: the rests of a drive found as it streams, each one re-measuring the static bias
//! through a one-state Kalman filter, so that a bias that wanders, or a log that starts moving,
//! still gets its bias removed from the first stop on.
//!
//! Not in the papers, which measure the bias once (HDR eq 2). Time is cut into blocks of
//! [`RestTrackerConfig::block`] seconds from the first sample (so the blocks, and everything
//! found, are the same however the stream is chunked). A finished block is *still* when the
//! vehicle's speed stayed below [`RestTrackerConfig::speed_threshold`] in all its samples; where
//! no speed is given, when its reading noise is at most [`RestTrackerConfig::noise_ratio`] times
//! the noise at rest; and in both cases, when its mean moved from the previous block's by no more
//! than [`RestTrackerConfig::change_sigmas`] standard errors (a rest reads a constant plus noise). A run
//! of still blocks is a rest; its first and last blocks are dropped (the vehicle may be settling
//! or starting), and the rest counts once what is left lasts [`RestTrackerConfig::min_duration`].
//!
//! A finished rest is a measurement of the bias: its time-weighted mean reading, with the
//! batch-means standard error of its blocks (never below the white-noise error
//! `noise / sqrt(n)`). The filter's state is the bias, a random walk of intensity
//! [`RestTrackerConfig::bias_walk`] (`K^2` from the rate random walk, plus the bias instability's
//! share, see `gyrocore.rests.bias_walk`): predict `P += q dt`, gate the innovation at
//! [`RestTrackerConfig::gate_sigmas`], update `b += P/(P+R) (z - b)`, `P = P R/(P+R)` (the
//! update of [`crate::bias_walk`], the filter whole mode runs over a whole log's rests). A rest
//! that stopped short or crept gives a mean with a large standard error, or one the gate refuses,
//! and so moves the bias little.

use crate::bias_walk::BiasEstimate;
use crate::kernel::Event;
use crate::rest::RestStatistics;
use crate::Error;

mod config;
#[cfg(feature = "serde")]
mod readback;
mod tracked;
pub use config::RestTrackerConfig;
pub use tracked::{Tracked, TrackedConfig, TrackedState, TrackerSettings};

/// One rest the tracker found.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Rest {
    /// Start and end of the part measured \[s since the first sample\] (the rest without its first
    /// and last block).
    pub start: f64,
    /// See `start`.
    pub end: f64,
    /// The mean reading over it [rad/s]: the bias it measured.
    pub bias: f64,
    /// That mean's standard error [rad/s].
    pub std_error: f64,
    /// The noise of one reading over it [rad/s] (from successive differences).
    pub noise: f64,
    /// The readings it holds.
    pub samples: u64,
    /// True when a speed below the threshold found it (every sample had a speed), false when the
    /// rate alone did.
    pub by_speed: bool,
    /// False when the filter's gate refused it.
    pub accepted: bool,
    /// The filtered bias after this rest [rad/s].
    pub filtered: f64,
}

/// Sums over one block, or over the blocks of a rest.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Sums {
    start: f64,
    end: f64,
    /// Integral of the readings [rad] and time covered \[s\] (the rectangle rule, as the static
    /// bias test weighs them).
    integral: f64,
    duration: f64,
    samples: u64,
    squared_differences: f64,
    differences: u64,
    /// Block means and their squares (a rest's batch means).
    blocks: u64,
    means: f64,
    squared_means: f64,
    /// Every block added had a speed for every sample.
    by_speed: bool,
}

impl Sums {
    fn mean(&self) -> f64 {
        if self.duration > 0.0 {
            self.integral / self.duration
        } else {
            0.0
        }
    }

    /// One reading's noise from successive differences (as [`RestStatistics::noise`]).
    fn noise(&self) -> f64 {
        libm::sqrt(self.squared_differences / (2.0 * self.differences.max(1) as f64))
    }

    /// Adds a finished block to a rest.
    fn add(&mut self, b: &Sums, by_speed: bool) {
        if self.blocks == 0 {
            self.start = b.start;
            self.by_speed = true;
        }
        self.by_speed &= by_speed;
        self.end = b.end;
        self.integral += b.integral;
        self.duration += b.duration;
        self.samples = self.samples.saturating_add(b.samples);
        self.squared_differences += b.squared_differences;
        self.differences = self.differences.saturating_add(b.differences);
        let m = b.mean();
        self.blocks = self.blocks.saturating_add(1);
        self.means += m;
        self.squared_means += m * m;
    }

    /// The batch-means standard error of a rest's mean, at least the white-noise error.
    fn std_error(&self) -> f64 {
        let k = self.blocks as f64;
        let mean = self.means / k;
        let spread = (self.squared_means - k * mean * mean).max(0.0) / (k - 1.0);
        let white = self.noise() / libm::sqrt(self.samples as f64);
        libm::sqrt(spread / k).max(white)
    }
}

/// The relative rounding of a block's mean (`integral / duration`, sums of products over the
/// block's intervals) below which two means read the same: far above a block's few hundred
/// roundings of 2^-53 each, far below any change a gyro's noise or a motion shows.
const MEAN_ROUNDING: f64 = 1e-9;

/// Whether two means `a` and `b` agree: within `sigmas` standard errors `error`, or within the
/// rounding of a mean ([`MEAN_ROUNDING`]), all a gyro that reads one value at rest (its noise below
/// one count) leaves to judge by. `sigmas = inf` is no test (`inf * 0` is NaN where `error` is 0).
fn means_agree(a: f64, b: f64, sigmas: f64, error: f64) -> bool {
    let rounding = MEAN_ROUNDING * libm::fabs(a).max(libm::fabs(b));
    sigmas == f64::INFINITY || libm::fabs(a - b) <= sigmas * error + rounding
}

/// The block being filled.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Filling {
    index: u64,
    sums: Sums,
    previous_rate: Option<f64>,
    /// Every sample had a speed, and some was at or above the threshold.
    all_speeds: bool,
    moving: bool,
}

/// The rest tracker's state: detection and the bias filter.
///
/// It has no constructor of its own: a [`Pipeline`](crate::Pipeline) runs it and feeds it
/// ([`PipelineConfig::rest_tracker`](crate::PipelineConfig::rest_tracker)). For the tracker
/// alone, give one to [`Preset::Raw`](crate::Preset::Raw)'s configuration and read it through
/// [`Pipeline::rest_tracker`](crate::Pipeline::rest_tracker) (its `Default` is a tracker that
/// has seen nothing, which nothing feeds).
///
/// ```
/// use gyrocore::{Pipeline, Preset, RestTrackerConfig};
/// let mut config = Preset::Raw.config();
/// config.rest_tracker = Some(RestTrackerConfig::default());
/// let mut p = Pipeline::new(config).unwrap();
/// for i in 0..1000 {
///     // stopped (speed 0) for 5 s, then moving at 5 m/s, a bias of 0.01 rad/s
///     let speed = if i < 500 { 0.0 } else { 5.0 };
///     p.update_with_speed(i as f64 * 0.01, 0.01, None, speed);
/// }
/// let tracker = p.rest_tracker().unwrap();
/// assert_eq!(tracker.rests_found(), 1);
/// assert!((tracker.bias() - 0.01).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RestTracker {
    /// The time since the first sample \[s\] (the sum of the intervals: kernels see no clock).
    now: f64,
    block: Filling,
    /// The last finished block (its mean and sample count), for the change test.
    previous: Option<(f64, u64)>,
    /// The still run: its blocks so far but the latest, which waits in `pending`.
    run: Option<(Sums, Option<Filling>)>,
    /// The filtered bias [rad/s] and its variance [rad^2/s^2] (`None`: nothing known yet), at
    /// time `updated`.
    bias: f64,
    variance: Option<f64>,
    updated: f64,
    /// The reading noise at rest [rad/s], once known.
    noise: Option<f64>,
    /// The latest rest found, how many were found, and whether the latest sample ended one
    /// (the pipeline hands each to its caller as it ends: nothing is kept but the latest).
    last: Option<Rest>,
    found: u64,
    ended: bool,
}

impl RestTracker {
    fn new(config: &RestTrackerConfig, bias: f64) -> Self {
        RestTracker {
            bias,
            noise: config.noise,
            block: Filling::start(0),
            ..RestTracker::default()
        }
    }

    /// The filtered bias [rad/s].
    pub fn bias(&self) -> f64 {
        self.bias
    }

    /// Its standard error now [rad/s] (the variance at the last rest plus the random walk since),
    /// `None` before the first rest or rest window. The dead band and HDR's bound follow it.
    /// `config` is the pipeline's (`pipeline.config().rest_tracker`), whose `bias_walk` it reads.
    pub fn std_error(&self, config: &RestTrackerConfig) -> Option<f64> {
        self.variance
            .map(|p| libm::sqrt(p + config.bias_walk * (self.now - self.updated).max(0.0)))
    }

    /// How many rests were found (accepted or not).
    pub fn rests_found(&self) -> u64 {
        self.found
    }

    /// The latest rest found, if any. Every rest reaches the caller of
    /// [`crate::Pipeline::process_block_reporting`] as it ends; a caller of
    /// [`crate::Pipeline::update_with_speed`] reads it here after each sample that
    /// [`RestTracker::ended_rest`].
    pub fn last_rest(&self) -> Option<Rest> {
        self.last
    }

    /// True when the latest sample ended a rest (it is [`RestTracker::last_rest`]).
    pub fn ended_rest(&self) -> bool {
        self.ended
    }

    /// Takes one reading (`speed` NaN where none is given); returns the measurement of a rest
    /// that this reading ended, once filtered.
    fn observe(&mut self, c: &RestTrackerConfig, e: Event, rate: f64, speed: f64) -> Option<Rest> {
        let t = self.now + e.dt;
        self.now = t;
        self.ended = false;
        let index = (t / c.block) as u64;
        if e.measuring {
            // The rest window is the pipeline's to measure; blocks start after it.
            self.block = Filling::start(index);
            (self.previous, self.run) = (None, None);
            return None;
        }
        let mut found = None;
        if index != self.block.index {
            let finished = self.block;
            let still = finished.index.checked_add(1) == Some(index) && self.still(c, &finished);
            self.previous = Some((finished.sums.mean(), finished.sums.samples));
            found = self.extend_run(c, still, &finished);
            self.block = Filling::start(index);
        }
        self.block.take(t, e.dt, rate, speed, c.speed_threshold);
        found
    }

    /// Whether a finished block is still (see the module doc).
    fn still(&self, c: &RestTrackerConfig, b: &Filling) -> bool {
        let Some((previous, n)) = self.previous.filter(|_| b.sums.samples >= 2) else {
            return false;
        };
        // The change test with the block's own noise: a vehicle that creeps or turns slowly
        // while its speed reads zero changes its mean faster than its noise explains.
        let own = b.sums.noise();
        let error = own * libm::sqrt(1.0 / b.sums.samples as f64 + 1.0 / n.max(1) as f64);
        // A gyro that reads one value at rest (its noise below one count) has no noise to judge
        // by: its block means then differ only by the rounding of `integral / duration`, which
        // moves with the clock's origin (a rest split in two at t0 = 1000 s, whole at 100 s).
        let constant = means_agree(b.sums.mean(), previous, c.change_sigmas, error);
        constant
            && if b.all_speeds {
                !b.moving
            } else {
                self.noise.is_some_and(|noise| own <= c.noise_ratio * noise)
            }
    }

    /// Grows the still run by a block, or ends it; returns a rest that ended.
    fn extend_run(&mut self, c: &RestTrackerConfig, still: bool, b: &Filling) -> Option<Rest> {
        match (still, &mut self.run) {
            (true, None) => {
                // The first block of a rest is dropped.
                self.run = Some((Sums::default(), None));
                None
            }
            (true, Some((sums, pending))) => {
                if let Some(p) = pending.replace(*b) {
                    sums.add(&p.sums, p.all_speeds);
                }
                None
            }
            (false, run) => {
                // The latest block (in `pending`) is dropped: the vehicle may have been starting.
                let (sums, _) = run.take()?;
                (sums.blocks >= 2 && sums.duration >= c.min_duration).then(|| self.filter(c, &sums))
            }
        }
    }

    /// The Kalman update with a rest's mean (see the module doc).
    fn filter(&mut self, c: &RestTrackerConfig, sums: &Sums) -> Rest {
        let z = sums.mean();
        let r = sums.std_error() * sums.std_error();
        let at = 0.5 * (sums.start + sums.end);
        let accepted = match self.variance {
            None => {
                self.bias = z;
                self.variance = Some(r);
                true
            }
            Some(p) => {
                let p = p + c.bias_walk * (at - self.updated).max(0.0);
                let s = p + r;
                // No bias walk and a gyro that reads one value at rest leave `s = 0`: with no
                // gate every rest was refused, and with one a mean that differs from the bias by
                // its rounding alone; the gate is the change test's rule.
                let accepted = means_agree(z, self.bias, c.gate_sigmas, libm::sqrt(s));
                if accepted && s > 0.0 {
                    let at = BiasEstimate {
                        mean: self.bias,
                        variance: p,
                    }
                    .update(z, r);
                    (self.bias, self.variance) = (at.mean, Some(at.variance));
                } else {
                    self.variance = Some(p);
                }
                accepted
            }
        };
        self.updated = at;
        if self.noise.is_none() && accepted {
            self.noise = Some(sums.noise());
        }
        let rest = Rest {
            start: sums.start,
            end: sums.end,
            bias: z,
            std_error: libm::sqrt(r),
            noise: sums.noise(),
            samples: sums.samples,
            by_speed: sums.by_speed,
            accepted,
            filtered: self.bias,
        };
        self.last = Some(rest);
        self.found = self.found.saturating_add(1);
        self.ended = true;
        rest
    }

    /// Takes what the rest window measured: its mean as the bias, and its standard error and
    /// noise once it is over.
    fn prior(&mut self, bias: Option<f64>, rest: Option<RestStatistics>) {
        if let Some(b) = bias {
            self.bias = b;
        }
        if let Some(r) = rest {
            self.variance = Some(r.bias_std_error * r.bias_std_error);
            self.updated = self.now;
            self.noise.get_or_insert(r.noise);
        }
    }
}

impl Filling {
    fn start(index: u64) -> Self {
        Filling {
            index,
            all_speeds: true,
            ..Filling::default()
        }
    }

    fn take(&mut self, t: f64, dt: f64, rate: f64, speed: f64, threshold: f64) {
        let s = &mut self.sums;
        if s.samples == 0 {
            s.start = t;
        } else {
            s.integral += rate * dt;
            s.duration += dt;
        }
        s.end = t;
        s.samples = s.samples.saturating_add(1);
        if let Some(p) = self.previous_rate {
            s.squared_differences += (rate - p) * (rate - p);
            s.differences = s.differences.saturating_add(1);
        }
        self.previous_rate = Some(rate);
        self.all_speeds &= !speed.is_nan();
        self.moving |= libm::fabs(speed) >= threshold;
    }
}

/// Fails unless `speed` holds `n` samples, none of them infinite (NaN is "no speed here").
pub(crate) fn check_speed(speed: &[f64], n: usize) -> Result<(), Error> {
    crate::stage::check_len("speed", speed.len(), n)?;
    match speed.iter().position(|s| s.is_infinite()) {
        Some(index) => Err(Error::NonFinite {
            what: "speed",
            index,
            value: speed[index],
        }),
        None => Ok(()),
    }
}
