//! First-order low-pass (HDR eq 7) and its exact inverse, the de-lag (HDR eq 13).
//!
//! Both use the actual interval `T_i` of each sample, so the time constant keeps its meaning at
//! any (and at an irregular) sample rate. De-lag after low-pass restores the input exactly (up to
//! rounding), so the pipeline runs the two around HDR in closed form (`lag_free.rs`); these are
//! the stand-alone stages, the equations as printed.

use crate::error::check_range;
use crate::kernel::{settings_are_config, Kernel, Signal, Streaming};
use crate::{Error, MAX_TIME};

/// Configuration shared by [`LowPass`] and [`DeLag`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LowPassConfig {
    /// Time constant `tau` \[s\], >= 0. HDR Table III: 0.75 s.
    pub tau: f64,
}

impl LowPassConfig {
    /// Checks `tau`.
    pub fn validate(&self) -> Result<(), Error> {
        check_tau("lowpass_tau", self.tau)
    }
}

/// Checks a time constant of HDR eq 7 named `name` (the low-pass's, or HDR's on its step means):
/// >= 0 and at most 2^40 s.
pub(crate) fn check_tau(name: &'static str, tau: f64) -> Result<(), Error> {
    let valid = ">= 0 and at most 2^40 s (about 35,000 years)";
    check_range(name, tau, 0.0, MAX_TIME, valid)
}

/// Low-pass filter, HDR eq 7: `w'_i = (w_i T_i + tau w'_{i-1}) / (T_i + tau)`. The first sample
/// passes unchanged (no start-up transient). State: the last output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LowPassKernel;

impl LowPassKernel {
    /// HDR eq 7 for one sample with interval `dt` > 0 after the output `previous`.
    #[inline(always)]
    pub(crate) fn filter(tau: f64, previous: f64, dt: f64, rate: f64) -> f64 {
        // Eq 7 as two weights: the division does not wait for the previous output, so the chain
        // from one output to the next is a multiply and an add.
        let inv = 1.0 / (dt + tau);
        rate * (dt * inv) + previous * (tau * inv)
    }
}

/// Implements [`Kernel`] for a filter of the rate whose state is one rate (the low-pass its last
/// output, the de-lag its last input): the first sample passes unchanged and is that state;
/// `$step` (of the config `$c`, the state `$state`, the interval `$dt` and the rate `$rate`) is
/// every later sample's output.
macro_rules! rate_filter_kernel {
    ($ty:ty, |$c:ident, $state:ident, $dt:ident, $rate:ident| $step:expr) => {
        impl Kernel for $ty {
            type Config = LowPassConfig;
            type State = f64;
            const REMEMBERS: bool = true;

            fn start(_config: &LowPassConfig) -> f64 {
                0.0
            }

            #[inline(always)]
            fn first(_config: &LowPassConfig, state: &mut f64, x: Signal) -> Signal {
                *state = x.rate;
                x
            }

            #[inline(always)]
            fn step($c: &LowPassConfig, $state: &mut f64, $dt: f64, x: Signal) -> Signal {
                let $rate = x.rate;
                Signal { rate: $step, ..x }
            }

            /// The rate within +-2^256, far beyond what valid input reaches: a de-lag's stored
            /// last input of 1e308 made its next output infinite.
            #[cfg(feature = "serde")]
            fn check_state(_config: &LowPassConfig, state: &f64) -> Result<(), Error> {
                crate::error::check_stored("filter state", *state)
            }
        }
    };
}

rate_filter_kernel!(LowPassKernel, |c, state, dt, rate| {
    *state = LowPassKernel::filter(c.tau, *state, dt, rate);
    *state
});

/// De-lag, HDR eq 13: `w_d,i = w_i + tau / T_i (w_i - w_{i-1})`, the inverse of eq 7. The first
/// sample passes unchanged. State: the last input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DeLagKernel;

rate_filter_kernel!(DeLagKernel, |c, state, dt, rate| {
    let y = rate + c.tau / dt * (rate - *state);
    *state = rate;
    y
});

settings_are_config!(LowPassKernel, DeLagKernel);

/// The low-pass as a stand-alone stage.
pub type LowPass = Streaming<LowPassKernel>;

/// The de-lag as a stand-alone stage.
pub type DeLag = Streaming<DeLagKernel>;
