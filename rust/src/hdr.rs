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
use crate::error::{check_duration, check_magnitude, check_positive, check_range};
use crate::kernel::{Kernel, Measured, Signal, Streaming, Validated};
use crate::lowpass::{check_tau, LowPassKernel};
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
    /// Bound on the correction `|I|` [rad/s], >= 0 (0: no correction); infinity (the paper's HDR)
    /// leaves it free.
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
        check_magnitude("hdr_increment", self.increment)?;
        check_range(
            "hdr_turn_threshold",
            self.turn_threshold,
            f64::MIN_POSITIVE,
            f64::INFINITY,
            "> 0 (infinity disables the turn switch)",
        )?;
        check_range("hdr_c1", self.c1, 0.0, f64::MAX, "finite and >= 0")?;
        check_positive("hdr_c2", self.c2)?;
        check_duration("hdr_interval", self.interval)?;
        // 0 is what a rest of exactly constant readings measures (a bias known without error),
        // as the bound a measured rest sets turns HDR off there (NoiseScaled)
        check_range(
            "hdr_max_correction",
            self.max_correction,
            0.0,
            f64::INFINITY,
            ">= 0 (0: no correction; infinity: no bound)",
        )?;
        // named as the rule between the two names it (lowpass_tau may hold a valid one)
        check_tau("hdr.tau", self.tau)
    }

    /// Repetition attenuator `R = (1 + c_1) / (1 + c_1 r^c_2)` (HDR eq 10).
    pub fn attenuation(&self, repetitions: u32) -> f64 {
        if self.c1 == 0.0 {
            // R = 1 for every r; the formula would give 0 * inf = NaN once r^c2 overflows.
            return 1.0;
        }
        (1.0 + self.c1) / (1.0 + self.c1 * libm::pow(repetitions as f64, self.c2))
    }
}

/// `x` limited to `[-bound, bound]`; a NaN bound leaves `x` as it is, where `f64::clamp` would
/// panic.
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

/// What HDR remembers between samples.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct HdrState {
    /// The integrator `I` [rad/s]; `-I` is the drift estimate.
    integrator: f64,
    block: BlockMean,
    /// Eq 7 on the step means: the last `w'` that the controller saw, once there is one.
    filtered: Option<f64>,
    /// `SIGN(w)` of the previous step, for the repetition counter (eq 9).
    previous_sign: Option<i8>,
    /// Repetition counter `r` (eq 9).
    repetitions: u32,
}

/// HDR's configuration as the kernel reads it: the settings, eq 10's attenuation table and the
/// bound on `|I|` in force.
///
/// Serialised without the table, which is rebuilt from the settings when read back: a float
/// read back may differ from the one written in its last digit (`serde_json` without its
/// `float_roundtrip` feature), and the table read back would then not be the one its settings
/// give, which a restored [`Pipeline`](crate::Pipeline) refuses.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(from = "StoredRule", into = "StoredRule")
)]
pub struct HdrRule {
    config: HdrConfig,
    /// `R(r)` for `r = 1..=ATTENUATION_TABLE`: eq 10 costs a `pow`, and `r` is a small integer.
    attenuation: [f64; ATTENUATION_TABLE],
    /// The bound on `|I|` in force: [`HdrConfig::max_correction`], or the one a measured rest
    /// window sets (see [`crate::NoiseScaled`]). A property of the sensor: a restart keeps it.
    bound: f64,
}

/// What an [`HdrRule`] stores: its settings and the bound in force.
#[cfg(feature = "serde")]
#[derive(serde::Serialize, serde::Deserialize)]
struct StoredRule {
    config: HdrConfig,
    #[serde(with = "crate::serde_float")]
    bound: f64,
}

#[cfg(feature = "serde")]
impl From<StoredRule> for HdrRule {
    fn from(stored: StoredRule) -> Self {
        HdrRule {
            bound: stored.bound,
            ..HdrRule::new(stored.config)
        }
    }
}

#[cfg(feature = "serde")]
impl From<HdrRule> for StoredRule {
    fn from(rule: HdrRule) -> Self {
        StoredRule {
            config: rule.config,
            bound: rule.bound,
        }
    }
}

impl HdrRule {
    /// The rule of valid settings.
    pub(crate) fn new(config: HdrConfig) -> Self {
        let mut attenuation = [0.0; ATTENUATION_TABLE];
        for (r, a) in (1u32..).zip(attenuation.iter_mut()) {
            *a = config.attenuation(r);
        }
        HdrRule {
            config,
            attenuation,
            bound: config.max_correction,
        }
    }

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

/// Heuristic Drift Reduction as a [`Kernel`]: adds `I` to the (low-passed) rate (eq 12) and
/// decides on `I` once per step from the corrected rate's step means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HdrKernel;

impl HdrState {
    /// One HDR step on the mean rate of the step just closed: eq 7 gives `w'_{i-1}`, then eq 8 (as
    /// the text states it), eq 9, eq 10 and eq 11 `I_i = I_{i-1} - SIGN(w_{i-1}) W_i R_i i_c`
    /// with `w_{i-1} = w'_{i-1} + I_{i-1}` (eq 12).
    ///
    /// Inlined although it runs once a step: a call would make the pipeline's state escape to
    /// memory, and every sample would then load and store it.
    #[inline(always)]
    fn decide(&mut self, rule: &HdrRule, mean: f64, duration: f64) {
        let filtered = match self.filtered {
            Some(previous) => LowPassKernel::filter(rule.config.tau, previous, duration, mean),
            None => mean,
        };
        self.filtered = Some(filtered);
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

impl Kernel for HdrKernel {
    type Config = HdrRule;
    type State = HdrState;
    const REMEMBERS: bool = true;
    const WAITS_FOR_BIAS: bool = true;

    fn start(_rule: &HdrRule) -> HdrState {
        HdrState::default()
    }

    #[inline(always)]
    fn first(rule: &HdrRule, state: &mut HdrState, x: Signal) -> Signal {
        Self::step(rule, state, 0.0, x)
    }

    /// Adds the `I` in force to the sample's rate and closes the step when the sample ends it.
    #[inline(always)]
    fn step(rule: &HdrRule, state: &mut HdrState, dt: f64, x: Signal) -> Signal {
        let applied = state.integrator;
        if let Some((mean, duration)) = state.block.push(rule.config.interval, dt, x.corrected) {
            state.decide(rule, mean, duration);
        }
        Signal {
            rate: x.rate + applied,
            drift: -applied,
            ..x
        }
    }

    /// After a gap HDR starts afresh, and the gap's sample opens its first step.
    #[inline(always)]
    fn restarted(rule: &HdrRule, state: &mut HdrState, dt: f64, x: Signal) -> Signal {
        Self::step(rule, state, dt, x)
    }

    fn measured(rule: &mut HdrRule, state: &mut HdrState, m: &Measured) {
        if let Some(bound) = m.hdr_bound {
            rule.bound = libm::fabs(bound);
            state.integrator = within(state.integrator, rule.bound);
        }
    }

    fn in_force(rule: &HdrRule) -> Measured {
        Measured {
            hdr_bound: Some(rule.bound),
            ..Measured::default()
        }
    }

    /// `|I|` of eq 11 within the bound in force (`max_correction`), and within about 2^101 rad/s
    /// (the largest `|I|` valid input reaches) without one: a stored `I` of 1e308 gave infinite
    /// headings.
    #[cfg(feature = "serde")]
    fn check_state(rule: &HdrRule, state: &HdrState) -> Result<(), Error> {
        let bound = rule.bound.min(MAX_INTEGRATOR);
        let valid = "within the bound on |I| in force (and about 2^101 rad/s without one)";
        check_range("hdr integrator", state.integrator, -bound, bound, valid)
    }
}

/// The largest `|I|` \[rad/s\] valid input reaches without a bound on it (about 2^101): one
/// increment (at most 2^20 rad/s) a sample, samples at least
/// [`MIN_INTERVAL`](crate::MIN_INTERVAL) apart within +-[`MAX_TIME`](crate::MAX_TIME).
#[cfg(feature = "serde")]
pub(crate) const MAX_INTEGRATOR: f64 =
    crate::MAX_READING * (2.0 * crate::MAX_TIME / crate::MIN_INTERVAL);

impl Validated for HdrKernel {
    type Settings = HdrConfig;

    fn configure(config: HdrConfig) -> Result<HdrRule, Error> {
        config.validate()?;
        Ok(HdrRule::new(config))
    }

    fn check(rule: &HdrRule) -> Result<(), Error> {
        rule.config.validate()?;
        let valid = ">= 0 (inf: no bound)";
        check_range("hdr_max_correction", rule.bound, 0.0, f64::INFINITY, valid)
    }
}

/// HDR as a stand-alone stage: its output is the input rate plus `I` (eq 12).
pub type Hdr = Streaming<HdrKernel>;

impl Hdr {
    /// The settings.
    pub fn settings(&self) -> &HdrConfig {
        &self.parts().0.config
    }

    /// The drift estimate `-I` [rad/s].
    pub fn drift(&self) -> f64 {
        -self.parts().1.integrator
    }

    /// The repetition counter `r` of the last step (eq 9); 0 before the first step.
    pub fn repetitions(&self) -> u32 {
        self.parts().1.repetitions
    }

    /// Replaces [`HdrConfig::max_correction`] as the bound on `|I|` by `bound` [rad/s] (its
    /// magnitude; infinity: no bound); `I` is clamped to it at once. A bound of 0 turns HDR off.
    /// A NaN bound is no bound to set, and leaves the one in force (it lifted every bound).
    pub fn bound_correction(&mut self, bound: f64) {
        if bound.is_nan() {
            return;
        }
        let (rule, state) = self.parts_mut();
        HdrKernel::measured(
            rule,
            state,
            &Measured {
                hdr_bound: Some(bound),
                ..Measured::default()
            },
        );
    }
}
