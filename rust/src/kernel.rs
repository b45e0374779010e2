//! The shape every per-sample stage has: a validated `Copy` configuration, a small `Copy` state
//! and one `step(&config, &mut state, dt, signal) -> signal`. Stages compose into a chain by
//! putting them in a tuple, which is itself a [`Kernel`]; the pipeline's driver runs one chain
//! per configuration, so a stage that is not in the chain costs nothing per sample.
//!
//! A stage is one file: its config (with `validate`), its state, and `impl Kernel`. To add one,
//! write that file and put the stage into the chain where the pipeline composes it
//! (`pipeline/engine.rs`). [`Streaming`] wraps any kernel into a stand-alone stage with its own
//! clock (the [`Stage`] trait), so each stage is also usable and testable on its own.

use crate::stage::{check_len, check_stage_block, Clock, Stage};
use crate::validate::{
    check_lengths, interval_key, usable_reading, Checks, MAX_TIME, MIN_INTERVAL,
};
use crate::Error;

/// Serde for configurations and states behind the `serde` feature (nothing without it).
#[cfg(feature = "serde")]
pub trait Persist: serde::Serialize + serde::de::DeserializeOwned {}
#[cfg(feature = "serde")]
impl<T: serde::Serialize + serde::de::DeserializeOwned> Persist for T {}
/// Serde for configurations and states behind the `serde` feature (nothing without it).
#[cfg(not(feature = "serde"))]
pub trait Persist {}
#[cfg(not(feature = "serde"))]
impl<T> Persist for T {}

/// What flows from one stage to the next for one sample.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Signal {
    /// The rate as the stages so far have made it [rad/s].
    pub rate: f64,
    /// The corrected rate after the dead band, before any filter: what HDR decides on [rad/s].
    pub corrected: f64,
    /// HDR's drift estimate `-I` applied to this sample [rad/s] (0 without HDR).
    pub drift: f64,
    /// The heading \[rad\] (set by the integrator, the last stage).
    pub heading: f64,
    /// The sensor temperature \[degC\], NaN where there is none.
    pub temperature: f64,
    /// The vehicle's speed [m/s], NaN where none is given (read by the rest tracker alone).
    pub speed: f64,
}

impl Signal {
    /// A reading entering the chain, with the sensor temperature \[degC\] or NaN.
    #[inline(always)]
    pub fn reading(rate: f64, temperature: f64) -> Self {
        Signal {
            rate,
            corrected: rate,
            drift: 0.0,
            heading: 0.0,
            temperature,
            speed: f64::NAN,
        }
    }

    /// A rate that needs no correction, entering a stage of its own.
    #[inline(always)]
    pub fn corrected(rate: f64) -> Self {
        Signal::reading(rate, f64::NAN)
    }
}

/// Which case of a sample a stage sees outside the chain's plain [`Kernel::step`]: the driver
/// handles the first sample, gaps and the rest window once, on the slow path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Event {
    /// The interval since the previous sample \[s\] (0 for the first).
    pub dt: f64,
    /// What kind of sample it is.
    pub kind: EventKind,
    /// True while the static bias is still being measured (the rest window).
    pub measuring: bool,
}

/// The kind of an [`Event`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    /// The first sample of the stream: no interval.
    First,
    /// A sample like any other.
    Step,
    /// The first sample after a gap, when the input policy restarts the stages with memory.
    AfterGap,
}

/// What the pipeline measures while it runs and hands to the stages: the static bias while the
/// rest window is measured, and the bounds the rest sets once it is over (see
/// [`crate::NoiseScaled`]). `None` leaves a setting as it is.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Measured {
    /// The static bias [rad/s] (what the gyro reads at rest).
    pub bias: Option<f64>,
    /// The dead band [rad/s], if it scales with the rest's noise.
    pub threshold: Option<f64>,
    /// The bound on HDR's correction [rad/s], if it scales with the bias's standard error.
    pub hdr_bound: Option<f64>,
    /// What the rest window measured besides the bias, once it is over (for the rest tracker).
    pub rest: Option<crate::rest::RestStatistics>,
}

/// One stage of the per-sample chain.
pub trait Kernel {
    /// What the stage reads and never changes per sample: validated settings.
    type Config: Copy + core::fmt::Debug + PartialEq + Persist;
    /// What the stage remembers from one sample to the next.
    type State: Copy + core::fmt::Debug + PartialEq + Persist;

    /// The state before the first sample.
    fn start(config: &Self::Config) -> Self::State;

    /// The first sample of a stream (it has no interval).
    fn first(config: &Self::Config, state: &mut Self::State, x: Signal) -> Signal;

    /// Every later sample; `dt` > 0 is the interval since the one before \[s\].
    fn step(config: &Self::Config, state: &mut Self::State, dt: f64, x: Signal) -> Signal;

    /// True for a stage that keeps a memory of the recent signal: after a gap, when the input
    /// policy says so, it starts again as at the first sample.
    const REMEMBERS: bool = false;

    /// True for a chain whose stages read [`Signal::speed`]: only such a chain's loop reads the
    /// speed, so the others carry none.
    const READS_SPEED: bool = false;

    /// True for a stage that must not run while the static bias is still measured (HDR: it would
    /// only chase the running estimate of the bias); the signal passes it unchanged.
    const WAITS_FOR_BIAS: bool = false;

    /// The sample as the slow path sees it (first sample, gap, rest window): see [`Event`].
    #[inline(always)]
    fn event(config: &Self::Config, state: &mut Self::State, e: Event, x: Signal) -> Signal {
        if Self::WAITS_FOR_BIAS && e.measuring {
            return x;
        }
        match e.kind {
            EventKind::First => Self::first(config, state, x),
            EventKind::AfterGap if Self::REMEMBERS => {
                *state = Self::start(config);
                Self::restarted(config, state, e.dt, x)
            }
            EventKind::AfterGap | EventKind::Step => Self::step(config, state, e.dt, x),
        }
    }

    /// The first sample after a restart, `dt` the gap \[s\]; by default the stream's first sample.
    #[inline(always)]
    fn restarted(config: &Self::Config, state: &mut Self::State, dt: f64, x: Signal) -> Signal {
        let _ = dt;
        Self::first(config, state, x)
    }

    /// True when the sample just taken ended something the caller is told of at once (a rest the
    /// tracker found): the chain's loop stops after it. No other stage does.
    #[inline(always)]
    fn stop_after(state: &Self::State) -> bool {
        let _ = state;
        false
    }

    /// Takes what the pipeline measured (see [`Measured`]); most stages need none of it.
    fn measured(config: &mut Self::Config, state: &mut Self::State, m: &Measured) {
        let _ = (config, state, m);
    }

    /// What [`Kernel::measured`] has set in `config` (`None` where the stage takes nothing): a
    /// restored pipeline hands these to the stages its configuration builds, and is whole only
    /// if they then equal the stored ones.
    fn in_force(config: &Self::Config) -> Measured {
        let _ = config;
        Measured::default()
    }

    /// Checks a state read back (`serde` feature) against its configuration: its values within
    /// what valid input reaches, so that the outputs stay finite (by default it takes any).
    #[cfg(feature = "serde")]
    fn check_state(config: &Self::Config, state: &Self::State) -> Result<(), Error> {
        let _ = (config, state);
        Ok(())
    }
}

impl Measured {
    /// Each value of `self`, or of `other` where `self` has none.
    pub fn or(self, other: Measured) -> Measured {
        Measured {
            bias: self.bias.or(other.bias),
            threshold: self.threshold.or(other.threshold),
            hdr_bound: self.hdr_bound.or(other.hdr_bound),
            rest: self.rest.or(other.rest),
        }
    }
}

/// A stage the configuration may leave out: `None` passes the signal unchanged. For the
/// general chain only; the common chains leave an absent stage out of their type.
impl<K: Kernel> Kernel for Option<K> {
    type Config = Option<K::Config>;
    type State = Option<K::State>;

    fn start(config: &Self::Config) -> Self::State {
        config.as_ref().map(K::start)
    }

    #[inline(always)]
    fn first(config: &Self::Config, state: &mut Self::State, x: Signal) -> Signal {
        match (config, state) {
            (Some(c), Some(s)) => K::first(c, s, x),
            _ => x,
        }
    }

    #[inline(always)]
    fn step(config: &Self::Config, state: &mut Self::State, dt: f64, x: Signal) -> Signal {
        match (config, state) {
            (Some(c), Some(s)) => K::step(c, s, dt, x),
            _ => x,
        }
    }

    #[inline(always)]
    fn event(config: &Self::Config, state: &mut Self::State, e: Event, x: Signal) -> Signal {
        match (config, state) {
            (Some(c), Some(s)) => K::event(c, s, e, x),
            _ => x,
        }
    }

    fn measured(config: &mut Self::Config, state: &mut Self::State, m: &Measured) {
        if let (Some(c), Some(s)) = (config, state) {
            K::measured(c, s, m);
        }
    }

    fn in_force(config: &Self::Config) -> Measured {
        config.as_ref().map_or_else(Measured::default, K::in_force)
    }

    #[cfg(feature = "serde")]
    fn check_state(config: &Self::Config, state: &Self::State) -> Result<(), Error> {
        match (config, state) {
            (Some(c), Some(s)) => K::check_state(c, s),
            _ => Ok(()),
        }
    }
}

/// Composes kernels in a tuple: the signal passes them in order.
macro_rules! chain {
    ($($k:ident $i:tt),+) => {
        impl<$($k: Kernel),+> Kernel for ($($k,)+) {
            type Config = ($($k::Config,)+);
            type State = ($($k::State,)+);

            fn start(config: &Self::Config) -> Self::State {
                ($($k::start(&config.$i),)+)
            }

            #[inline(always)]
            fn first(config: &Self::Config, state: &mut Self::State, x: Signal) -> Signal {
                $(let x = $k::first(&config.$i, &mut state.$i, x);)+
                x
            }

            #[inline(always)]
            fn step(config: &Self::Config, state: &mut Self::State, dt: f64, x: Signal) -> Signal {
                $(let x = $k::step(&config.$i, &mut state.$i, dt, x);)+
                x
            }

            #[inline(always)]
            fn event(config: &Self::Config, state: &mut Self::State, e: Event, x: Signal) -> Signal {
                $(let x = $k::event(&config.$i, &mut state.$i, e, x);)+
                x
            }

            fn measured(config: &mut Self::Config, state: &mut Self::State, m: &Measured) {
                $($k::measured(&mut config.$i, &mut state.$i, m);)+
            }

            fn in_force(config: &Self::Config) -> Measured {
                Measured::default()$(.or($k::in_force(&config.$i)))+
            }

            #[cfg(feature = "serde")]
            fn check_state(config: &Self::Config, state: &Self::State) -> Result<(), Error> {
                $($k::check_state(&config.$i, &state.$i)?;)+
                Ok(())
            }
        }
    };
}
chain!(A 0, B 1);
chain!(A 0, B 1, C 2);
chain!(A 0, B 1, C 2, D 3);
chain!(A 0, B 1, C 2, D 3, E 4);
chain!(A 0, B 1, C 2, D 3, E 4, F 5);

/// A kernel whose configuration is built from settings a user gives, and checked.
pub trait Validated: Kernel {
    /// What a user gives (for most stages the configuration itself).
    type Settings: Copy;
    /// Checks `settings` (the error names the first invalid field) and builds the configuration.
    fn configure(settings: Self::Settings) -> Result<Self::Config, Error>;
    /// What the stand-alone stage emits of a signal.
    fn output(y: Signal) -> f64 {
        y.rate
    }

    /// Checks a configuration read back (`serde` feature) as [`Validated::configure`] checks
    /// settings; by default it takes any.
    fn check(config: &Self::Config) -> Result<(), Error> {
        let _ = config;
        Ok(())
    }
}

/// Implements [`Validated`] for kernels whose settings are their configuration (checked by its
/// `validate`); `output` optionally says what the stand-alone stage emits.
macro_rules! settings_are_config {
    (@one $k:ty, $out:expr) => {
        impl $crate::kernel::Validated for $k {
            type Settings = <$k as $crate::kernel::Kernel>::Config;

            fn configure(config: Self::Settings) -> Result<Self::Settings, $crate::Error> {
                config.validate()?;
                Ok(config)
            }

            fn output(y: $crate::kernel::Signal) -> f64 {
                ($out)(y)
            }

            fn check(config: &Self::Config) -> Result<(), $crate::Error> {
                config.validate()
            }
        }
    };
    ($k:ty; output $out:expr) => {
        $crate::kernel::settings_are_config!(@one $k, $out);
    };
    ($($k:ty),+) => {
        $($crate::kernel::settings_are_config!(@one $k, |y: $crate::kernel::Signal| y.rate);)+
    };
}
pub(crate) use settings_are_config;

/// A kernel as a stand-alone stage: its configuration, its state and its own [`Clock`], fed
/// `(t, rate)` samples through the [`Stage`] trait. The pipeline does not use this wrapper: it
/// keeps one clock for the whole chain.
///
/// Read back with the `serde` feature, its configuration is checked ([`Validated::check`]), its
/// state ([`Kernel::check_state`]), its clock within +-[`MAX_TIME`] and its last output.
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
