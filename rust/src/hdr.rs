//! Heuristic Drift Reduction (HDR eq 4-12): a binary I-controller that drives the sign changes of
//! the corrected rate toward zero mean, gated by a turn switch and a repetition attenuator.
//!
//! Table III's parameters are per 1 s step (the paper ran its loop on 1 Hz block means, second
//! eq 14). This stage keeps that meaning at any input rate: it adds the current `I` to every sample
//! (eq 12) but decides on `I` once per `interval` seconds, exactly as the paper's 1 Hz loop did:
//! on the time-weighted mean of the step, low-passed by eq 7 with `T_i` = the step's length.
//! At 1 Hz input every sample is a step and the stage is the paper's loop; at 10 or 100 Hz, a
//! record whose step means equal the 1 Hz samples gets the same decisions, hence the same `I`.
//!
//! Two typos in the printed eq 8 are corrected, following the paper's text (section 4.2.2): the
//! switch compares the *absolute* low-passed rate `|w'|` with the threshold, and it *disables* the
//! controller (W = 0) above the threshold, enabling it (W = 1) below. As printed, eq 8 would switch
//! HDR off on straight roads and on for every left turn.

use crate::block::BlockMean;
use crate::error::{check_positive, check_range};
use crate::lowpass::{LowPass, LowPassConfig};
use crate::stage::{interval_stage, Clock};
use crate::Error;

/// Number of precomputed attenuation values `R(1..=N)` (eq 10); larger counts use `pow`.
const ATTENUATION_TABLE: usize = 32;

/// HDR parameters. Rates in rad/s; [`HdrConfig::table_iii`] gives the paper's values.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct HdrConfig {
    /// Nominal increment `i_c` per step [rad/s], >= 0 (0 disables HDR). Table III: 0.0422 deg/s.
    pub increment: f64,
    /// Turn threshold `Theta_w` [rad/s], > 0 (infinity disables the switch). Table III: 0.564 deg/s.
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_float"))]
    pub turn_threshold: f64,
    /// Repetition attenuator constant `c_1` (eq 10), >= 0. Table III: 0.16.
    pub c1: f64,
    /// Repetition attenuator power `c_2` (eq 10), > 0. Table III: 1.80.
    pub c2: f64,
    /// Length of one HDR step \[s\], > 0. The paper's step is 1 s.
    pub interval: f64,
    /// Time constant `tau` of the low-pass (eq 7) on the step means that HDR decides on \[s\], >= 0.
    /// Table III: 0.75 s.
    pub tau: f64,
    /// Bound on the correction `|I|` [rad/s], > 0; infinity (the paper's HDR) leaves it free.
    ///
    /// Not in the paper. After the static bias is removed, `I` estimates what is left of the
    /// bias; a sensor's bias does not wander further than a few times its bias instability in a
    /// drive, so a larger `I` is a gentle curve below the turn switch being taken for drift.
    /// The bound caps the heading error HDR can cause on a gyro without bias at
    /// `max_correction` times the time spent on such curves.
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_float"))]
    pub max_correction: f64,
}

impl HdrConfig {
    /// The single parameter set of the HDR paper's Table III, converted to rad/s.
    pub fn table_iii() -> Self {
        HdrConfig {
            increment: 0.0422_f64.to_radians(),
            turn_threshold: 0.564_f64.to_radians(),
            c1: 0.16,
            c2: 1.80,
            interval: 1.0,
            tau: 0.75,
            max_correction: f64::INFINITY,
        }
    }

    /// Checks every field; the error names the first invalid one.
    pub fn validate(&self) -> Result<(), Error> {
        check_range(
            "hdr_increment",
            self.increment,
            0.0,
            f64::MAX,
            "finite and >= 0",
        )?;
        check_range(
            "hdr_turn_threshold",
            self.turn_threshold,
            f64::MIN_POSITIVE,
            f64::INFINITY,
            "> 0 (infinity disables the turn switch)",
        )?;
        check_range("hdr_c1", self.c1, 0.0, f64::MAX, "finite and >= 0")?;
        check_positive("hdr_c2", self.c2)?;
        check_positive("hdr_interval", self.interval)?;
        check_range(
            "hdr_max_correction",
            self.max_correction,
            f64::MIN_POSITIVE,
            f64::INFINITY,
            "> 0 (infinity: no bound)",
        )?;
        LowPassConfig { tau: self.tau }.validate()
    }

    /// Repetition attenuator `R = (1 + c_1) / (1 + c_1 r^c_2)` (HDR eq 10).
    pub fn attenuation(&self, repetitions: u32) -> f64 {
        (1.0 + self.c1) / (1.0 + self.c1 * libm::pow(repetitions as f64, self.c2))
    }
}

/// `x` limited to `[-bound, bound]`; a NaN bound (from a block that is then rejected) leaves `x`
/// as it is, where `f64::clamp` would panic.
#[inline]
fn within(x: f64, bound: f64) -> f64 {
    x.max(-bound).min(bound)
}

/// `SIGN()` of HDR eq 4b: 1, 0 or -1.
#[inline]
fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// The evolving part of [`Hdr`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct HdrState {
    /// The integrator `I` [rad/s]; `-I` is the drift estimate.
    integrator: f64,
    block: BlockMean,
    /// Eq 7 on the step means: the `w'` that the controller sees.
    filter: LowPass,
    /// `SIGN(w)` of the previous step, for the repetition counter (eq 9).
    previous_sign: Option<i8>,
    /// Repetition counter `r` (eq 9).
    repetitions: u32,
    clock: Clock,
}

impl HdrState {
    /// The state before the first sample.
    #[inline(always)]
    fn start(config: &HdrConfig) -> Self {
        HdrState {
            integrator: 0.0,
            block: BlockMean::default(),
            filter: LowPass::start(LowPassConfig { tau: config.tau }),
            previous_sign: None,
            repetitions: 0,
            clock: Clock::default(),
        }
    }
}

/// The HDR stage: output is the input rate plus the controller output `I` (eq 12).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Hdr {
    rule: HdrRule,
    state: HdrState,
}

/// What HDR's steps read but do not change.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct HdrRule {
    config: HdrConfig,
    /// `R(r)` for `r = 1..=ATTENUATION_TABLE`: eq 10 costs a `pow`, and `r` is a small integer.
    attenuation: [f64; ATTENUATION_TABLE],
    /// The bound on `|I|` in force: [`HdrConfig::max_correction`], or the one set by
    /// [`Hdr::bound_correction`]. A property of the sensor, so [`Hdr::restart`] keeps it.
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_float"))]
    bound: f64,
}

impl Hdr {
    /// Validates `config` and builds the stage.
    pub fn new(config: HdrConfig) -> Result<Self, Error> {
        config.validate()?;
        Ok(Self::start(config))
    }

    /// The stage before the first sample, from a configuration validated already.
    fn start(config: HdrConfig) -> Self {
        let mut attenuation = [0.0; ATTENUATION_TABLE];
        for (r, a) in (1u32..).zip(attenuation.iter_mut()) {
            *a = config.attenuation(r);
        }
        Hdr {
            rule: HdrRule {
                config,
                attenuation,
                bound: config.max_correction,
            },
            state: HdrState::start(&config),
        }
    }

    /// Replaces [`HdrConfig::max_correction`] as the bound on `|I|` by `bound` [rad/s]; `I` is
    /// clamped to it at once. A bound of 0 turns HDR off.
    #[inline(always)]
    pub fn bound_correction(&mut self, bound: f64) {
        self.rule.bound = libm::fabs(bound);
        self.state.integrator = within(self.state.integrator, self.rule.bound);
    }

    /// Forgets the signal (the controller starts again from `I = 0`) but keeps the bound.
    ///
    /// Always inlined, as are the other steps the pipeline's loop may take: a call would let the
    /// stage's state escape the loop's registers.
    #[inline(always)]
    pub fn restart(&mut self) {
        self.state = HdrState::start(&self.rule.config);
    }

    /// The configuration.
    pub fn config(&self) -> &HdrConfig {
        &self.rule.config
    }

    /// The drift estimate `-I` [rad/s].
    pub fn drift(&self) -> f64 {
        -self.state.integrator
    }

    /// The repetition counter `r` of the last step (eq 9); 0 before the first step.
    pub fn repetitions(&self) -> u32 {
        self.state.repetitions
    }

    /// Adds `I` to one sample whose interval is `dt` \[s\]: returns `w = rate + I` (eq 12), and
    /// updates `I` for the next step when the sample closes one.
    #[inline]
    pub fn step(&mut self, dt: f64, rate: f64) -> f64 {
        rate + self.observe(dt, rate)
    }

    /// Feeds one sample to the controller and returns the `I` that applies to it (the value
    /// before this sample's step closes). The pipeline adds it to the low-passed rate instead.
    #[inline(always)]
    pub fn observe(&mut self, dt: f64, rate: f64) -> f64 {
        self.state.observe(&self.rule, dt, rate)
    }

    /// The stage as a [`PrimedHdr`].
    #[inline(always)]
    pub(crate) fn primed(&self) -> PrimedHdr<'_> {
        PrimedHdr {
            rule: &self.rule,
            state: self.state.clone(),
        }
    }

    /// Takes over the state of a [`PrimedHdr`] made by [`Hdr::primed`].
    #[inline(always)]
    pub(crate) fn set_state(&mut self, state: HdrState) {
        self.state = state;
    }
}

impl HdrRule {
    /// `R(r)` of eq 10, from the table where it has it.
    #[inline]
    fn attenuation_at(&self, repetitions: u32) -> f64 {
        match repetitions
            .checked_sub(1)
            .and_then(|k| self.attenuation.get(k as usize))
        {
            Some(&a) => a,
            None => self.config.attenuation(repetitions),
        }
    }
}

impl HdrState {
    /// [`Hdr::observe`].
    #[inline(always)]
    fn observe(&mut self, rule: &HdrRule, dt: f64, rate: f64) -> f64 {
        let applied = self.integrator;
        if let Some((mean, duration)) = self.block.push(rule.config.interval, dt, rate) {
            self.decide(rule, mean, duration);
        }
        applied
    }

    /// One HDR step on the mean rate of the step just closed: eq 7 gives `w'_{i-1}`, then eq 8 (as
    /// the text states it), eq 9, eq 10 and eq 11 `I_i = I_{i-1} - SIGN(w_{i-1}) W_i R_i i_c`
    /// with `w_{i-1} = w'_{i-1} + I_{i-1}` (eq 12).
    ///
    /// Inlined although it runs once a step: a call would make the pipeline's state escape to
    /// memory, and every sample would then load and store it.
    #[inline(always)]
    fn decide(&mut self, rule: &HdrRule, mean: f64, duration: f64) {
        let filtered = self.filter.step(duration, mean);
        let s = sign(filtered + self.integrator);
        self.repetitions = match self.previous_sign {
            Some(p) if p == s => self.repetitions.saturating_add(1),
            _ => 1,
        };
        self.previous_sign = Some(s);
        let turning = libm::fabs(filtered) >= rule.config.turn_threshold;
        if !turning {
            let step = f64::from(s) * rule.attenuation_at(self.repetitions) * rule.config.increment;
            self.integrator = within(self.integrator - step, rule.bound);
        }
    }
}

/// A copy of an [`Hdr`]'s state that borrows the rest, for the pipeline's loop over a block: the
/// compiler keeps a local copy of scalars in registers, but not scalars that share a copy with a
/// table indexed by a variable (eq 10's), so a whole copy of the stage would load and store the
/// step's sums on every sample.
#[derive(Debug, Clone)]
pub(crate) struct PrimedHdr<'a> {
    rule: &'a HdrRule,
    state: HdrState,
}

impl PrimedHdr<'_> {
    /// [`Hdr::observe`].
    #[inline(always)]
    pub(crate) fn observe(&mut self, dt: f64, rate: f64) -> f64 {
        self.state.observe(self.rule, dt, rate)
    }

    /// The state, for [`Hdr::set_state`].
    #[inline(always)]
    pub(crate) fn into_state(self) -> HdrState {
        self.state
    }
}

interval_stage!(Hdr, state.clock, rule.config);
