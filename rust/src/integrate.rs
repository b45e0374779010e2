//! Heading from rate: rectangle rule (HDR eq 3 and eq 14) or trapezoid rule, on the actual
//! interval of each sample. The heading is continuous (never wrapped).
//!
//! The printed HDR eq 14, `psi_i = psi_0 + psi_{i-1} + w_d,i T_i`, would add the initial heading
//! at every step; the text defines `psi_0` as the heading at the start of the drive, so it is used
//! once, as the starting value: `psi_i = psi_{i-1} + w_d,i T_i`, `psi` at the first sample = `psi_0`.

use crate::error::check_finite;
use crate::stage::{interval_stage, Clock};
use crate::Error;

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

/// Integrates rate [rad/s] into a continuous heading \[rad\].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Integrator {
    config: IntegratorConfig,
    heading: f64,
    previous: Option<f64>,
    clock: Clock,
}

impl Integrator {
    /// Validates `config` and builds the stage.
    pub fn new(config: IntegratorConfig) -> Result<Self, Error> {
        check_finite("initial_heading", config.initial_heading)?;
        Ok(Self::start(config))
    }

    fn start(config: IntegratorConfig) -> Self {
        Integrator {
            config,
            heading: config.initial_heading,
            previous: None,
            clock: Clock::default(),
        }
    }

    /// Adds one sample whose interval is `dt` \[s\]; returns the heading at that sample.
    #[inline(always)]
    pub fn step(&mut self, dt: f64, rate: f64) -> f64 {
        if self.trapezoid() {
            self.step_by::<true>(dt, rate)
        } else {
            self.step_by::<false>(dt, rate)
        }
    }

    /// [`Integrator::step`] by the rule of [`PrimedIntegrator`]`<TRAPEZOID>`.
    #[inline(always)]
    fn step_by<const TRAPEZOID: bool>(&mut self, dt: f64, rate: f64) -> f64 {
        match self.primed::<TRAPEZOID>() {
            Some(mut primed) => {
                primed.step(dt, rate);
                self.set_primed(primed);
            }
            None => self.previous = Some(rate),
        }
        self.heading
    }

    /// True if the rule is the trapezoid rule (the `TRAPEZOID` of [`Integrator::primed`]).
    #[inline(always)]
    pub(crate) fn trapezoid(&self) -> bool {
        self.config.method == Method::Trapezoid
    }

    /// The stage as a [`PrimedIntegrator`], once it has a sample; `TRAPEZOID` must be
    /// [`Integrator::trapezoid`].
    #[inline(always)]
    pub(crate) fn primed<const TRAPEZOID: bool>(&self) -> Option<PrimedIntegrator<TRAPEZOID>> {
        debug_assert_eq!(TRAPEZOID, self.trapezoid());
        self.previous.map(|previous| PrimedIntegrator {
            heading: self.heading,
            previous,
        })
    }

    /// Takes over the state of `primed`, made by [`Integrator::primed`].
    #[inline(always)]
    pub(crate) fn set_primed<const TRAPEZOID: bool>(
        &mut self,
        primed: PrimedIntegrator<TRAPEZOID>,
    ) {
        self.heading = primed.heading;
        self.previous = Some(primed.previous);
    }

    /// The heading so far \[rad\].
    pub fn heading(&self) -> f64 {
        self.heading
    }
}

interval_stage!(Integrator, clock, config);

/// An [`Integrator`] that has a sample: no first-sample case to check, for the pipeline's loop
/// over a block. Its rule is part of its type (`TRAPEZOID`, else the rectangle rule), so the
/// loop does not choose it sample by sample.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PrimedIntegrator<const TRAPEZOID: bool> {
    heading: f64,
    previous: f64,
}

impl<const TRAPEZOID: bool> PrimedIntegrator<TRAPEZOID> {
    /// Adds one sample whose interval is `dt` [s]; returns the heading at that sample.
    #[inline(always)]
    pub(crate) fn step(&mut self, dt: f64, rate: f64) -> f64 {
        self.heading += if TRAPEZOID {
            0.5 * (rate + self.previous) * dt
        } else {
            rate * dt
        };
        self.previous = rate;
        self.heading
    }
}
