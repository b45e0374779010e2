//! HDR between the low-pass (HDR eq 7) and the de-lag (eq 13), in closed form.
//!
//! Eq 13 inverts eq 7 exactly: for `w'_i = (w_i T_i + tau w'_{i-1}) / (T_i + tau)`,
//! `w'_i + tau / T_i (w'_i - w'_{i-1}) = w_i`. HDR adds its `I` between the two (eq 12), so the
//! three stages give `w_i + I_i + tau / T_i (I_i - I_{i-1})`: the rate, HDR's correction, and the
//! de-lag of the correction's steps. [`LagFree`] computes that sum. No filter runs per sample,
//! and there is a division only at the sample after `I` moved (at most once per HDR step).
//!
//! Run stage after stage, the same sum carries the rounding of eq 7 and of its inverse, which
//! eq 13 amplifies by `tau / T_i`; the two differ by that rounding alone (docs/performance.md).

use core::marker::PhantomData;

use crate::kernel::{Event, EventKind, Kernel, Measured, Signal};
#[cfg(feature = "serde")]
use crate::{error::check_range, hdr::MAX_INTEGRATOR, Error};

/// The low-pass, the stage `H` (HDR, or HDR that may be off) and the de-lag as one kernel: see
/// the module doc. With `tau` = 0 (no de-lag) it is `H` alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct LagFree<H>(PhantomData<H>);

/// [`LagFree`]'s configuration: the inner stage's, and the time constant of eq 7 and 13 \[s\].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct LagFreeConfig<C> {
    pub(crate) inner: C,
    pub(crate) tau: f64,
}

/// [`LagFree`]'s state: the inner stage's, and the correction it added to the last sample.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct LagFreeState<S> {
    inner: S,
    applied: f64,
}

/// The de-lag of a step `jump` in the correction, `tau / T_i jump` (eq 13): out of line, as it
/// runs once per HDR step at most, so that the loop does not divide on every sample.
#[cold]
#[inline(never)]
fn delagged_step(tau: f64, dt: f64, jump: f64) -> f64 {
    tau / dt * jump
}

impl<H: Kernel> LagFree<H> {
    /// `y`, the inner stage's output, with the de-lag of the step its correction made since the
    /// last sample.
    #[inline(always)]
    fn delag(config: &LagFreeConfig<H::Config>, applied: &mut f64, dt: f64, y: Signal) -> Signal {
        // The inner stage's correction: HDR reports `-I` as the drift, and no stage else sets it.
        let now = -y.drift;
        let jump = now - *applied;
        *applied = now;
        if jump == 0.0 {
            return y;
        }
        Signal {
            rate: y.rate + delagged_step(config.tau, dt, jump),
            ..y
        }
    }
}

impl<H: Kernel> Kernel for LagFree<H> {
    type Config = LagFreeConfig<H::Config>;
    type State = LagFreeState<H::State>;
    const REMEMBERS: bool = true;

    fn start(config: &Self::Config) -> Self::State {
        LagFreeState {
            inner: H::start(&config.inner),
            applied: 0.0,
        }
    }

    /// The first sample passes the low-pass and the de-lag unchanged.
    #[inline(always)]
    fn first(config: &Self::Config, state: &mut Self::State, x: Signal) -> Signal {
        let y = H::first(&config.inner, &mut state.inner, x);
        state.applied = -y.drift;
        y
    }

    #[inline(always)]
    fn step(config: &Self::Config, state: &mut Self::State, dt: f64, x: Signal) -> Signal {
        let y = H::step(&config.inner, &mut state.inner, dt, x);
        Self::delag(config, &mut state.applied, dt, y)
    }

    /// The inner stage sees the event as it would alone (HDR waits for the bias and restarts
    /// after a gap in its own way); the low-pass and the de-lag start afresh at the first sample
    /// and after a gap, as stages that remember.
    #[inline(always)]
    fn event(config: &Self::Config, state: &mut Self::State, e: Event, x: Signal) -> Signal {
        let y = H::event(&config.inner, &mut state.inner, e, x);
        match e.kind {
            EventKind::First | EventKind::AfterGap => {
                state.applied = -y.drift;
                y
            }
            EventKind::Step => Self::delag(config, &mut state.applied, e.dt, y),
        }
    }

    fn measured(config: &mut Self::Config, state: &mut Self::State, m: &Measured) {
        H::measured(&mut config.inner, &mut state.inner, m);
    }

    fn in_force(config: &Self::Config) -> Measured {
        H::in_force(&config.inner)
    }

    /// The correction applied to the last sample is HDR's `I` then: within the largest `|I|`
    /// (a stored one of 1e308 gave infinite headings at the next step of `I`).
    #[cfg(feature = "serde")]
    fn check_state(config: &Self::Config, state: &Self::State) -> Result<(), Error> {
        let (bound, valid) = (
            MAX_INTEGRATOR,
            "within about 2^101 rad/s, HDR's largest |I|",
        );
        check_range("applied correction", state.applied, -bound, bound, valid)?;
        H::check_state(&config.inner, &state.inner)
    }
}
