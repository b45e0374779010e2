//! First-order low-pass (HDR eq 7) and its exact inverse, the de-lag (HDR eq 13).
//!
//! Both use the actual interval `T_i` of each sample, so the time constant keeps its meaning at
//! any (and at an irregular) sample rate. De-lag after low-pass restores the input exactly (up to
//! rounding): in the pipeline the low-pass only shapes what HDR decides on, and the de-lag removes
//! its lag from the heading.

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
        check_range(
            "lowpass_tau",
            self.tau,
            0.0,
            MAX_TIME,
            ">= 0 and at most 2^40 s (about 35,000 years)",
        )
    }
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

impl Kernel for LowPassKernel {
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
    fn step(config: &LowPassConfig, state: &mut f64, dt: f64, x: Signal) -> Signal {
        *state = Self::filter(config.tau, *state, dt, x.rate);
        Signal { rate: *state, ..x }
    }
}

/// De-lag, HDR eq 13: `w_d,i = w_i + tau / T_i (w_i - w_{i-1})`, the inverse of eq 7. The first
/// sample passes unchanged. State: the last input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DeLagKernel;

impl Kernel for DeLagKernel {
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
    fn step(config: &LowPassConfig, state: &mut f64, dt: f64, x: Signal) -> Signal {
        let y = x.rate + config.tau / dt * (x.rate - *state);
        *state = x.rate;
        Signal { rate: y, ..x }
    }
}

settings_are_config!(LowPassKernel, DeLagKernel);

/// The low-pass as a stand-alone stage.
pub type LowPass = Streaming<LowPassKernel>;

/// The de-lag as a stand-alone stage.
pub type DeLag = Streaming<DeLagKernel>;
