//! The rest tracker in the pipeline: [`Tracked`] runs a chain under it and hands the chain what
//! each rest measured.

use super::{RestTracker, RestTrackerConfig};
use crate::kernel::{Event, EventKind, Kernel, Measured, Signal};

/// The tracker's settings and the bounds it scales (as [`crate::pipeline::NoiseScaled`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TrackerSettings {
    /// The detection and the filter.
    pub config: RestTrackerConfig,
    /// Dead band in standard deviations of the noise at rest and the filtered bias's standard
    /// error together, set at each rest and each new block.
    pub threshold_sigmas: Option<f64>,
    /// HDR's bound in standard errors of the filtered bias, set at each rest and each new block.
    pub hdr_bound_sigmas: Option<f64>,
}

/// The configuration of a chain run under the tracker.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TrackedConfig<K> {
    /// The tracker's settings.
    pub tracker: TrackerSettings,
    /// The bias the chain starts with [rad/s] (the filter's until a rest says otherwise).
    pub bias: f64,
    /// The chain's configuration as built.
    pub inner: K,
}

/// The tracker and the chain it drives: the chain's configuration lives in the state, because
/// each rest changes the bias, the dead band and HDR's bound in it.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TrackedState<K, S> {
    /// Detection and filter.
    pub tracker: RestTracker,
    /// The chain's configuration now.
    pub config: K,
    /// The chain's state.
    pub state: S,
}

/// A chain `C` under rest tracking: each reading goes to the tracker, then through `C`; a rest
/// that ends hands `C` the filtered bias and the bounds it scales (see [`Measured`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tracked<C>(core::marker::PhantomData<C>);

impl<C: Kernel> Tracked<C> {
    /// The reading through the tracker, and the chain's configuration updated: by a rest it
    /// ends (the filtered bias), and then and at each new block the bounds that follow the
    /// bias's standard error now, which grows with the random walk between rests.
    #[inline(always)]
    fn track(
        s: &TrackerSettings,
        state: &mut TrackedState<C::Config, C::State>,
        e: Event,
        x: Signal,
    ) {
        let block = state.tracker.block.index;
        let ended = state
            .tracker
            .observe(&s.config, e, x.rate, x.speed)
            .is_some();
        if !ended && state.tracker.block.index == block {
            return;
        }
        let Some(error) = state.tracker.std_error(&s.config) else {
            return;
        };
        // A reading at rest, once the bias is removed, is off zero by its noise and by the
        // bias's error: the dead band is `threshold_sigmas` standard deviations of both.
        let threshold = s
            .threshold_sigmas
            .zip(state.tracker.noise)
            .map(|(k, n)| k * libm::sqrt(n * n + error * error));
        let m = Measured {
            bias: ended.then_some(state.tracker.bias),
            threshold,
            hdr_bound: s.hdr_bound_sigmas.map(|k| k * error),
            rest: None,
        };
        C::measured(&mut state.config, &mut state.state, &m);
    }
}

impl<C: Kernel> Kernel for Tracked<C> {
    type Config = TrackedConfig<C::Config>;
    type State = TrackedState<C::Config, C::State>;

    const READS_SPEED: bool = true;

    fn start(config: &Self::Config) -> Self::State {
        TrackedState {
            tracker: RestTracker::new(&config.tracker.config, config.bias),
            config: config.inner,
            state: C::start(&config.inner),
        }
    }

    fn first(config: &Self::Config, state: &mut Self::State, x: Signal) -> Signal {
        let e = Event {
            dt: 0.0,
            kind: EventKind::First,
            measuring: false,
        };
        Self::event(config, state, e, x)
    }

    #[inline(always)]
    fn step(config: &Self::Config, state: &mut Self::State, dt: f64, x: Signal) -> Signal {
        let e = Event {
            dt,
            kind: EventKind::Step,
            measuring: false,
        };
        Self::track(&config.tracker, state, e, x);
        C::step(&state.config, &mut state.state, dt, x)
    }

    fn event(config: &Self::Config, state: &mut Self::State, e: Event, x: Signal) -> Signal {
        Self::track(&config.tracker, state, e, x);
        C::event(&state.config, &mut state.state, e, x)
    }

    #[inline(always)]
    fn stop_after(state: &Self::State) -> bool {
        state.tracker.ended
    }

    fn measured(config: &mut Self::Config, state: &mut Self::State, m: &Measured) {
        let _ = config;
        state.tracker.prior(m.bias, m.rest);
        C::measured(&mut state.config, &mut state.state, m);
    }

    /// The tracker's state (its variance, noise, times and sums), the bias in the chain's
    /// configuration the tracker's (each rest hands it over), and the chain's state against the
    /// chain's configuration now.
    #[cfg(feature = "serde")]
    fn check_state(config: &Self::Config, state: &Self::State) -> Result<(), crate::Error> {
        let _ = config;
        state.tracker.check()?;
        if let Some(bias) = C::in_force(&state.config).bias {
            if bias != state.tracker.bias {
                return Err(crate::Error::InvalidParameter {
                    name: "rest tracker chain bias",
                    value: bias,
                    valid: "the rest tracker's filtered bias, which each rest hands the chain",
                });
            }
        }
        C::check_state(&state.config, &state.state)
    }
}
