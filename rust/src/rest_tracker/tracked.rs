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
    /// Dead band in noise standard deviations, set at each rest.
    pub threshold_sigmas: Option<f64>,
    /// HDR's bound in standard errors of the filtered bias, set at each rest.
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
    /// ends (the filtered bias, the dead band from the noise at rest, HDR's bound from the
    /// bias's standard error), or, at each new block, HDR's bound grown with the random walk.
    #[inline(always)]
    fn track(
        s: &TrackerSettings,
        state: &mut TrackedState<C::Config, C::State>,
        e: Event,
        x: Signal,
    ) {
        let block = state.tracker.block.index;
        let rest = state.tracker.observe(&s.config, e, x.rate, x.speed);
        let error = state.tracker.std_error(&s.config);
        let hdr_bound = s.hdr_bound_sigmas.zip(error).map(|(k, e)| k * e);
        let m = if rest.is_some() {
            Measured {
                bias: Some(state.tracker.bias),
                threshold: s
                    .threshold_sigmas
                    .zip(state.tracker.noise)
                    .map(|(k, n)| k * n),
                hdr_bound,
                rest: None,
            }
        } else if state.tracker.block.index != block && hdr_bound.is_some() {
            Measured {
                hdr_bound,
                ..Measured::default()
            }
        } else {
            return;
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

    fn measured(config: &mut Self::Config, state: &mut Self::State, m: &Measured) {
        let _ = config;
        state.tracker.prior(m.bias, m.rest);
        C::measured(&mut state.config, &mut state.state, m);
    }
}
