//! Heading from rate: rectangle rule (HDR eq 3 and eq 14) or trapezoid rule, on the actual
//! interval of each sample. The heading is continuous (never wrapped).
//!
//! The printed HDR eq 14, `psi_i = psi_0 + psi_{i-1} + w_d,i T_i`, would add the initial heading
//! at every step; the text defines `psi_0` as the heading at the start of the drive, so it is used
//! once, as the starting value: `psi_i = psi_{i-1} + w_d,i T_i`, `psi` at the first sample = `psi_0`.

use crate::error::{check_finite, check_range};
use crate::kernel::{settings_are_config, Kernel, Signal, Streaming};
use crate::{Error, MAX_READING};

/// Integration rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Method {
    /// `psi_i = psi_{i-1} + w_i T_i` (HDR eq 3, eq 14).
    Rectangle,
    /// `psi_i = psi_{i-1} + (w_i + w_{i-1}) T_i / 2`: exact for piecewise-linear rates.
    #[default]
    Trapezoid,
}

/// Configuration of [`Integrator`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct IntegratorConfig {
    /// Integration rule.
    pub method: Method,
    /// Heading at the first sample, `psi_0` \[rad\].
    pub initial_heading: f64,
}

impl IntegratorConfig {
    /// Checks the initial heading: finite and within +-[`MAX_READING`] (2^20 rad), where a
    /// double still resolves 2e-10 rad; beyond, a sample's increment is lost (at 1e300 rad the
    /// heading never moved). The heading-fix filter's initial heading has the same check.
    pub fn validate(&self) -> Result<(), Error> {
        check_initial_heading(self.initial_heading)
    }
}

/// Checks an initial heading \[rad\] (the integrator's, and the heading-fix filter's): finite and
/// within +-[`MAX_READING`] (2^20 rad), where a double still resolves 2e-10 rad; beyond, a
/// sample's increment is lost (at 1e300 rad the heading never moved; at 2^40 rad an increment
/// below 2.4e-4 rad).
pub(crate) fn check_initial_heading(heading: f64) -> Result<(), Error> {
    check_finite("initial_heading", heading)?;
    let most = MAX_READING;
    check_range(
        "initial_heading",
        heading,
        -most,
        most,
        "within +-2^20 rad (continuous headings may turn many times; wrap a larger one)",
    )
}

/// What an integrator remembers: the heading so far and the last rate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Heading {
    /// The heading \[rad\].
    pub heading: f64,
    /// The last rate integrated [rad/s].
    pub previous: f64,
}

impl Heading {
    /// Checks a state read back (`serde` feature): the heading within
    /// [`MAX_HEADING`](crate::error::MAX_HEADING) (one of 2^255 took no increment any more) and
    /// the last rate within [`MAX_STORED`](crate::error::MAX_STORED) (a stored last rate of
    /// 1e308 made the next heading infinite).
    #[cfg(feature = "serde")]
    fn check(&self) -> Result<(), Error> {
        crate::error::check_heading("heading", self.heading)?;
        crate::error::check_stored("previous rate", self.previous)
    }

    /// Adds one sample with interval `dt` \[s\] by the rule `trapezoid` (else the rectangle rule).
    #[inline(always)]
    fn add(&mut self, trapezoid: bool, dt: f64, rate: f64) -> f64 {
        self.heading += if trapezoid {
            0.5 * (rate + self.previous) * dt
        } else {
            rate * dt
        };
        self.previous = rate;
        self.heading
    }
}

/// Integrates by the configured rule (HDR eq 3 and 14, or the trapezoid rule); the heading is
/// the signal's `heading`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IntegratorKernel;

/// Integrates by the trapezoid rule, known when the chain is composed (the pipeline's common
/// chains), so the loop does not choose the rule sample by sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TrapezoidKernel;

/// Implements [`Kernel`] for an integrator whose rule is `$trapezoid` (of its config `$c`).
macro_rules! integrator_kernel {
    ($ty:ty, |$c:ident| $trapezoid:expr) => {
        impl Kernel for $ty {
            type Config = IntegratorConfig;
            type State = Heading;

            fn start(config: &IntegratorConfig) -> Heading {
                Heading {
                    heading: config.initial_heading,
                    previous: 0.0,
                }
            }

            #[inline(always)]
            fn first(_config: &IntegratorConfig, state: &mut Heading, x: Signal) -> Signal {
                state.previous = x.rate;
                Signal {
                    heading: state.heading,
                    ..x
                }
            }

            #[inline(always)]
            fn step($c: &IntegratorConfig, state: &mut Heading, dt: f64, x: Signal) -> Signal {
                Signal {
                    heading: state.add($trapezoid, dt, x.rate),
                    ..x
                }
            }

            #[cfg(feature = "serde")]
            fn check_state(_config: &IntegratorConfig, state: &Heading) -> Result<(), Error> {
                state.check()
            }
        }

        settings_are_config!($ty; output |y: Signal| y.heading);
    };
}
integrator_kernel!(IntegratorKernel, |c| c.method == Method::Trapezoid);
integrator_kernel!(TrapezoidKernel, |_c| true);

/// Integrates rate [rad/s] into a continuous heading \[rad\], as a stand-alone stage.
pub type Integrator = Streaming<IntegratorKernel>;

impl Integrator {
    /// The heading so far \[rad\].
    pub fn heading(&self) -> f64 {
        self.parts().1.heading
    }
}
