//! First-order low-pass (HDR eq 7) and its exact inverse, the de-lag (HDR eq 13).
//!
//! Both use the actual interval `T_i` of each sample, so the time constant keeps its meaning at
//! any (and at an irregular) sample rate. De-lag after low-pass restores the input exactly (up to
//! rounding): in the pipeline the low-pass only shapes what HDR decides on, and the de-lag removes
//! its lag from the heading.

use crate::error::check_range;
use crate::stage::{interval_stage, Clock};
use crate::Error;

/// Configuration shared by [`LowPass`] and [`DeLag`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LowPassConfig {
    /// Time constant `tau` \[s\], >= 0 (0 makes the stage the identity). HDR Table III: 0.75 s.
    pub tau: f64,
}

impl LowPassConfig {
    /// Checks `tau`.
    pub fn validate(&self) -> Result<(), Error> {
        check_range("lowpass_tau", self.tau, 0.0, f64::MAX, "finite and >= 0")
    }
}

/// Defines a stage that remembers one value of the signal, and its primed form for the pipeline's
/// loop over a block: the stage once it has that value, for intervals > 0, with no first-sample
/// case to check (its `step`, the stage's equation, is written beside each). The first sample, and
/// one for which `$defined` (of the interval `$dt` and `$tau`) is false, pass unchanged.
macro_rules! remembers_one_value {
    (
        $(#[$doc:meta])* $stage:ident,
        $(#[$primed_doc:meta])* $primed:ident,
        $step_doc:literal,
        |$dt:ident, $tau:ident| $defined:expr
    ) => {
        $(#[$doc])*
        #[derive(Debug, Clone, PartialEq)]
        #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
        pub struct $stage {
            config: LowPassConfig,
            previous: Option<f64>,
            clock: Clock,
        }

        impl $stage {
            /// Validates `config` and builds the stage.
            pub fn new(config: LowPassConfig) -> Result<Self, Error> {
                config.validate()?;
                Ok(Self::start(config))
            }

            /// The stage before the first sample, from a configuration validated already.
            pub(crate) fn start(config: LowPassConfig) -> Self {
                $stage {
                    config,
                    previous: None,
                    clock: Clock::default(),
                }
            }

            #[doc = $step_doc]
            #[inline(always)]
            pub fn step(&mut self, $dt: f64, rate: f64) -> f64 {
                let $tau = self.config.tau;
                match self.primed() {
                    Some(mut primed) if $defined => {
                        let y = primed.step($dt, rate);
                        self.set_primed(primed);
                        y
                    }
                    _ => {
                        self.previous = Some(rate);
                        rate
                    }
                }
            }

            /// The stage as its primed form, once it has the value it remembers.
            #[inline(always)]
            pub(crate) fn primed(&self) -> Option<$primed> {
                self.previous.map(|previous| $primed {
                    tau: self.config.tau,
                    previous,
                })
            }

            /// Takes over the state of `primed`, made by `primed()`.
            #[inline(always)]
            pub(crate) fn set_primed(&mut self, primed: $primed) {
                self.previous = Some(primed.previous);
            }
        }

        $(#[$primed_doc])*
        #[derive(Debug, Clone, Copy)]
        pub(crate) struct $primed {
            tau: f64,
            previous: f64,
        }

        interval_stage!($stage, clock, config);
    };
}

remembers_one_value!(
    /// Low-pass filter, HDR eq 7: `w'_i = (w_i T_i + tau w'_{i-1}) / (T_i + tau)`.
    ///
    /// The first sample passes unchanged (no start-up transient).
    LowPass,
    /// A [`LowPass`] that has an output, for intervals > 0.
    PrimedLowPass,
    "Filters one sample whose interval is `dt` \\[s\\] (HDR eq 7).",
    |dt, tau| dt + tau > 0.0
);

impl PrimedLowPass {
    /// Filters one sample whose interval `dt` is > 0 (HDR eq 7).
    #[inline(always)]
    pub(crate) fn step(&mut self, dt: f64, rate: f64) -> f64 {
        // Eq 7 as two weights: the division does not wait for the previous output, so the chain
        // from one output to the next is a multiply and an add.
        let inv = 1.0 / (dt + self.tau);
        self.previous = rate * (dt * inv) + self.previous * (self.tau * inv);
        self.previous
    }
}

remembers_one_value!(
    /// De-lag, HDR eq 13: `w_d,i = w_i + tau / T_i (w_i - w_{i-1})`, the inverse of eq 7.
    ///
    /// The first sample, and a sample with no interval (`T_i = 0`), pass unchanged.
    DeLag,
    /// A [`DeLag`] that has an input, for intervals > 0.
    PrimedDeLag,
    "De-lags one sample whose interval is `dt` \\[s\\] (HDR eq 13).",
    |dt, _tau| dt > 0.0
);

impl PrimedDeLag {
    /// De-lags one sample whose interval `dt` is > 0 (HDR eq 13).
    #[inline(always)]
    pub(crate) fn step(&mut self, dt: f64, rate: f64) -> f64 {
        let y = rate + self.tau / dt * (rate - self.previous);
        self.previous = rate;
        y
    }
}
