//! The chains the pipeline composes from its configuration, and the loop that runs one over a
//! block.
//!
//! A chain is a tuple of kernels (see [`crate::kernel`]): the stages a configuration leaves out
//! are not in the type, so they cost nothing per sample. Three chains cover every configuration:
//! the common ones without and with HDR, each compiled for what it holds, and a general one in
//! which every stage may be off. To add a stage, write its kernel and put it into these tuples.

use crate::correction::{Calibration, CorrectionKernel, SingleFactorKernel};
use crate::hdr::{HdrKernel, HdrRule};
use crate::integrate::{IntegratorKernel, Method, TrapezoidKernel};
use crate::kernel::{Event, Kernel, Measured, Signal};
use crate::lag_free::{LagFree, LagFreeConfig};
use crate::lowpass::LowPassKernel;
use crate::rest_tracker::{Rest, RestTracker, Tracked, TrackedConfig, TrackerSettings};
use crate::threshold::{ThresholdConfig, ThresholdKernel};
use crate::validate::{interval_key, usable_reading, Checks};

use super::{Output, Outputs, PipelineConfig};
#[cfg(feature = "serde")]
use crate::error::{check_range, check_reading};
#[cfg(feature = "serde")]
use crate::Error;

/// The presets without HDR (`raw`, `static_bias`, `hong_park`): correction, dead band, trapezoid.
pub(crate) type PlainChain = (SingleFactorKernel, ThresholdKernel, TrapezoidKernel);

/// The HDR presets (`hdr`, `combined`, `tuned`): HDR eq 7-13 between the dead band and the
/// trapezoid rule, the low-pass and the de-lag in closed form (see [`LagFree`]).
pub(crate) type HdrChain = (
    SingleFactorKernel,
    ThresholdKernel,
    LagFree<HdrKernel>,
    TrapezoidKernel,
);

/// Any other configuration: factors per turn direction, a temperature model, the rectangle
/// rule, or any subset of the filters. The low-pass runs as a stage of its own only without the
/// de-lag; with it, the two are [`LagFree`]'s `tau`.
pub(crate) type GeneralChain = (
    CorrectionKernel,
    ThresholdKernel,
    Option<LowPassKernel>,
    LagFree<Option<HdrKernel>>,
    IntegratorKernel,
);

/// The general chain under the rest tracker (a configuration with `rest_tracker`).
pub(crate) type TrackedChain = Tracked<GeneralChain>;

/// A chain's configuration and state.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(bound = ""))]
pub(crate) struct Chain<C: Kernel> {
    config: C::Config,
    state: C::State,
}

/// The chain a configuration runs.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
// The tracker's variant holds the general chain's configuration twice (as built and as the rests
// changed it) and the tracker (about 1.6 KB): one engine per pipeline, and the crate allocates
// nothing (no_std), so it is not boxed.
#[allow(clippy::large_enum_variant)]
pub(crate) enum Engine {
    Plain(Chain<PlainChain>),
    Hdr(Chain<HdrChain>),
    General(Chain<GeneralChain>),
    Tracked(Chain<TrackedChain>),
}

/// Runs `$body` with `$chain` bound to the engine's chain, whichever it is.
macro_rules! with_chain {
    ($engine:expr, |$chain:ident| $body:expr) => {
        match $engine {
            Engine::Plain($chain) => $body,
            Engine::Hdr($chain) => $body,
            Engine::General($chain) => $body,
            Engine::Tracked($chain) => $body,
        }
    };
}

impl Engine {
    /// The chain for a valid configuration.
    pub(crate) fn new(config: &PipelineConfig) -> Engine {
        let calibration = Calibration::new(config.correction);
        let threshold = config
            .threshold
            .unwrap_or(ThresholdConfig { threshold: 0.0 });
        let c = &config.correction;
        let common = c.c_cw == c.c_ccw
            && c.temperature.is_none()
            && config.integrator.method == Method::Trapezoid;
        let integrator = config.integrator;
        let delag_tau = config
            .lowpass
            .filter(|_| config.delag)
            .map_or(0.0, |l| l.tau);
        let general = (
            calibration,
            threshold,
            config.lowpass.filter(|_| !config.delag),
            LagFreeConfig {
                inner: config.hdr.map(HdrRule::new),
                tau: delag_tau,
            },
            integrator,
        );
        if let Some(tracker) = config.rest_tracker {
            return Engine::Tracked(Chain::new(TrackedConfig {
                tracker: TrackerSettings {
                    config: tracker,
                    threshold_sigmas: config.noise_scaled.threshold_sigmas,
                    hdr_bound_sigmas: config.noise_scaled.hdr_bound_sigmas,
                },
                bias: calibration.bias,
                inner: general,
            }));
        }
        match (common, config.lowpass, config.hdr, config.delag) {
            (true, None, None, false) => {
                Engine::Plain(Chain::new((calibration, threshold, integrator)))
            }
            (true, Some(lowpass), Some(hdr), true) => Engine::Hdr(Chain::new((
                calibration,
                threshold,
                LagFreeConfig {
                    inner: HdrRule::new(hdr),
                    tau: lowpass.tau,
                },
                integrator,
            ))),
            _ => Engine::General(Chain::new(general)),
        }
    }

    /// One sample on the slow path (see [`Event`]).
    pub(crate) fn event(&mut self, e: Event, x: Signal) -> Signal {
        with_chain!(self, |chain| chain.event(e, x))
    }

    /// The rest tracker, when the configuration has one.
    pub(crate) fn rest_tracker(&self) -> Option<&RestTracker> {
        match self {
            Engine::Tracked(chain) => Some(&chain.state.tracker),
            _ => None,
        }
    }

    /// Hands `on_rest` the rest the tracker found since it had found `found` (at most one: the
    /// loop stops after each), and counts it; true if there was one.
    pub(crate) fn report_rest(&self, found: &mut u64, on_rest: &mut dyn FnMut(Rest)) -> bool {
        let Some(tracker) = self.rest_tracker().filter(|r| r.rests_found() > *found) else {
            return false;
        };
        *found = tracker.rests_found();
        tracker.last_rest().into_iter().for_each(on_rest);
        true
    }

    /// Hands what the pipeline measured to every stage.
    pub(crate) fn measured(&mut self, m: &Measured) {
        with_chain!(self, |chain| chain.measured(m))
    }

    /// What the stages have been handed so far (under the tracker, what it set in its chain).
    #[cfg(feature = "serde")]
    pub(crate) fn in_force(&self) -> Measured {
        match self {
            Engine::Plain(chain) => PlainChain::in_force(&chain.config),
            Engine::Hdr(chain) => HdrChain::in_force(&chain.config),
            Engine::General(chain) => GeneralChain::in_force(&chain.config),
            Engine::Tracked(chain) => GeneralChain::in_force(&chain.state.config),
        }
    }

    /// True for the chain under the rest tracker.
    #[cfg(feature = "serde")]
    pub(crate) fn is_tracked(&self) -> bool {
        matches!(self, Engine::Tracked(_))
    }

    /// Checks an engine read back against `config` (valid) and `handed`, what the pipeline's own
    /// state says its stages were handed (`None` where a stage keeps what `config` gives it):
    /// the values in force within their ranges, and the stages `config` builds, handed those
    /// values, equal to the stored ones (an edited copy of a setting runs as stored, whatever
    /// `config` says).
    #[cfg(feature = "serde")]
    pub(crate) fn check_restored(
        &self,
        config: &PipelineConfig,
        handed: &Measured,
    ) -> Result<(), Error> {
        let measured = self.in_force();
        if let Some(bias) = measured.bias {
            check_reading("bias", bias)?;
        }
        if let Some(threshold) = measured.threshold {
            check_range("threshold", threshold, 0.0, f64::MAX, "finite and >= 0")?;
        }
        if let Some(bound) = measured.hdr_bound {
            let valid = ">= 0 (inf: no bound)";
            check_range("hdr_max_correction", bound, 0.0, f64::INFINITY, valid)?;
        }
        let mut built = Engine::new(config);
        built.measured(handed);
        let same = match (&built, self) {
            (Engine::Plain(a), Engine::Plain(b)) => a.config == b.config,
            (Engine::Hdr(a), Engine::Hdr(b)) => a.config == b.config,
            (Engine::General(a), Engine::General(b)) => a.config == b.config,
            (Engine::Tracked(a), Engine::Tracked(b)) => {
                a.config == b.config && a.state.config == b.state.config
            }
            _ => false,
        };
        if !same {
            return Err(Error::StagesMismatch);
        }
        with_chain!(self, |chain| chain.check_state())
    }

    /// The settled samples of `block` from `cursor.next` on, through the chain's loop; see
    /// [`Chain::run`].
    pub(crate) fn run(
        &mut self,
        block: &Block<'_>,
        cursor: &mut Cursor,
        stops: Option<u64>,
        out: &mut Outputs<'_>,
    ) {
        match stops {
            None => with_chain!(self, |chain| chain.run::<false>(block, cursor, 0, out)),
            Some(key) => with_chain!(self, |chain| chain.run::<true>(block, cursor, key, out)),
        }
    }
}

/// A block's samples.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Block<'a> {
    pub(crate) t: &'a [f64],
    pub(crate) rate: &'a [f64],
    pub(crate) temperature: Option<&'a [f64]>,
    /// The vehicle's speed [m/s] per sample, for the rest tracker.
    pub(crate) speed: Option<&'a [f64]>,
}

/// Where the loop over a block stands.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Cursor {
    /// The next sample to take.
    pub(crate) next: usize,
    /// The timestamp of the last sample taken.
    pub(crate) previous: f64,
    /// Validity of every sample taken.
    pub(crate) checks: Checks,
    /// The output of the last sample taken.
    pub(crate) last: Output,
}

impl<C: Kernel> Chain<C> {
    fn new(config: C::Config) -> Self {
        Chain {
            state: C::start(&config),
            config,
        }
    }

    fn event(&mut self, e: Event, x: Signal) -> Signal {
        C::event(&self.config, &mut self.state, e, x)
    }

    fn measured(&mut self, m: &Measured) {
        C::measured(&mut self.config, &mut self.state, m);
    }

    /// [`Kernel::check_state`] of the chain read back.
    #[cfg(feature = "serde")]
    fn check_state(&self) -> Result<(), Error> {
        C::check_state(&self.config, &self.state)
    }

    /// The loop: every sample from `cursor.next` on through [`Kernel::step`], its output into
    /// `out`, until the end of the block or a sample after which [`Kernel::stop_after`] (a rest
    /// ended: the pipeline hands it to its caller, then runs the loop on).
    ///
    /// Each sample is taken as it comes and checked on the way (a few operations that run
    /// beside the chain's floating-point work, see [`Checks`]); the caller rejects the block if
    /// any failed. Unless `STOPS`, the loop takes every sample; with `STOPS`, it stops before a
    /// sample whose interval's [`interval_key`] exceeds `stop_key` (a gap the input policy
    /// restarts at, or a timestamp that does not move forward) or whose reading is not usable
    /// (not finite or too large, which the policy holds or skips): such a sample needs the slow
    /// path.
    #[inline(always)]
    fn run<const STOPS: bool>(
        &mut self,
        block: &Block<'_>,
        cursor: &mut Cursor,
        stop_key: u64,
        out: &mut Outputs<'_>,
    ) {
        let n = block.t.len();
        let mut out = out.first(n);
        // The loop compiled for the output sets asked for most, all three, the heading alone and
        // the rate alone (what the heading-fix filter reads), which then write what is wanted
        // without asking on every sample.
        match &mut out {
            Outputs {
                heading: Some(h),
                rate: Some(r),
                drift: Some(d),
            } => {
                let (h, r, d) = (&mut h[..n], &mut r[..n], &mut d[..n]);
                let write = |i: usize, o: Output| {
                    h[i] = o.heading;
                    r[i] = o.rate;
                    d[i] = o.drift;
                };
                return self.run_into::<STOPS>(block, write, cursor, stop_key);
            }
            Outputs {
                heading: Some(h),
                rate: None,
                drift: None,
            } => {
                let h = &mut h[..n];
                let write = |i: usize, o: Output| h[i] = o.heading;
                return self.run_into::<STOPS>(block, write, cursor, stop_key);
            }
            Outputs {
                heading: None,
                rate: Some(r),
                drift: None,
            } => {
                let r = &mut r[..n];
                let write = |i: usize, o: Output| r[i] = o.rate;
                return self.run_into::<STOPS>(block, write, cursor, stop_key);
            }
            _ => {}
        }
        self.run_into::<STOPS>(block, |i, o| out.set(i, o), cursor, stop_key);
    }

    /// [`Chain::run`] with `write(i, output)` storing sample `i`'s output.
    #[inline(always)]
    fn run_into<const STOPS: bool>(
        &mut self,
        block: &Block<'_>,
        write: impl FnMut(usize, Output),
        cursor: &mut Cursor,
        stop_key: u64,
    ) {
        let n = block.t.len();
        // The loop compiled with and without a temperature, so that it does not ask on every
        // sample whether there is one.
        match block.temperature {
            None => self.run_with::<STOPS>(block, |_| None, write, cursor, stop_key),
            Some(temp) => {
                let temp = &temp[..n];
                self.run_with::<STOPS>(block, |i| Some(temp[i]), write, cursor, stop_key);
            }
        }
    }

    /// [`Chain::run`] with `temperature(i)` the temperature of sample `i`, if any.
    #[inline(always)]
    fn run_with<const STOPS: bool>(
        &mut self,
        block: &Block<'_>,
        temperature: impl Fn(usize) -> Option<f64>,
        mut write: impl FnMut(usize, Output),
        cursor: &mut Cursor,
        stop_key: u64,
    ) {
        let n = block.t.len();
        // Slices of one length, so the loop carries no bounds checks.
        let (t, rate) = (block.t, &block.rate[..n]);
        let speed = block.speed.filter(|_| C::READS_SPEED).map(|s| &s[..n]);
        let config = &self.config;
        // Local copies, so that the loop keeps them in registers.
        let mut state = self.state;
        let mut c = *cursor;
        for i in c.next..n {
            let dt = t[i] - c.previous;
            let temp = temperature(i);
            if STOPS && (interval_key(dt) > stop_key || !usable_reading(rate[i], temp)) {
                break;
            }
            c.previous = t[i];
            c.checks.interval(dt);
            c.checks.reading(rate[i], temp);
            let mut x = Signal::reading(rate[i], temp.unwrap_or(f64::NAN));
            if C::READS_SPEED {
                x.speed = speed.map_or(f64::NAN, |s| s[i]);
            }
            c.last = Output::of(C::step(config, &mut state, dt, x));
            write(i, c.last);
            c.next = i + 1;
            if C::stop_after(&state) {
                break;
            }
        }
        self.state = state;
        *cursor = c;
    }
}
