//! The shape every per-sample stage has: a validated `Copy` configuration, a small `Copy` state
//! and one `step(&config, &mut state, dt, signal) -> signal`. Stages compose into a chain by
//! putting them in a tuple, which is itself a [`Kernel`]; the pipeline's driver runs one chain
//! per configuration, so a stage that is not in the chain costs nothing per sample.
//!
//! A stage is one file: its config (with `validate`), its state, and `impl Kernel`. To add one,
//! write that file and put the stage into the chain where the pipeline composes it
//! (`pipeline/engine.rs`). [`Streaming`] wraps any kernel into a stand-alone stage with its own
//! clock (the [`Stage`](crate::Stage) trait), so each stage is also usable and testable on its own.

use crate::Error;

mod streaming;
pub use streaming::Streaming;

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
