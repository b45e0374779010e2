//! The whole chain in one pass: correction -> threshold -> low-pass -> HDR -> de-lag -> integrate.
//! No intermediate arrays: every enabled stage sees each sample once, in order.

mod memory;

use memory::{Feed, Memory, Off};

use crate::correction::{Correction, CorrectionConfig};
use crate::error::check_range;
use crate::hdr::{Hdr, HdrConfig};
use crate::input::{GapAction, InputPolicy, InputReport, NonFinite};
use crate::integrate::{Integrator, IntegratorConfig, PrimedIntegrator};
use crate::lowpass::{DeLag, LowPass, LowPassConfig};
use crate::rest::RestStatistics;
use crate::stage::{check_len, Clock};
use crate::threshold::{Threshold, ThresholdConfig};
use crate::validate::{check_block, check_lengths, finite_reading, interval_key, Checks};
use crate::Error;

/// Which stages run, and how. `None` disables a stage.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PipelineConfig {
    /// Bias, calibration and scale-factor correction (always runs; identity by default).
    pub correction: CorrectionConfig,
    /// Dead band (Hong eq 12).
    pub threshold: Option<ThresholdConfig>,
    /// Low-pass of the per-sample rate before HDR's `I` is added (HDR eq 7); HDR low-passes
    /// its step means with its own [`HdrConfig::tau`].
    pub lowpass: Option<LowPassConfig>,
    /// Undo the low-pass lag after HDR (HDR eq 13); needs `lowpass`.
    pub delag: bool,
    /// Heuristic Drift Reduction (HDR eq 4-12).
    pub hdr: Option<HdrConfig>,
    /// Integration rule and initial heading.
    pub integrator: IntegratorConfig,
    /// Non-finite readings and gaps.
    pub input: InputPolicy,
    /// Dead band and HDR bound scaled to the rest window's noise.
    pub noise_scaled: NoiseScaled,
}

/// The dead band and HDR's bound in units of what the rest window measured (see
/// [`crate::rest::RestStatistics`]), set once the window is over; until then, and when there is
/// no window (a fixed bias) or too little in it, `threshold` and `hdr.max_correction` apply.
///
/// Not in the papers. Hong and Park chose their 0.3 deg/s dead band for their sensor's noise; in
/// units of the noise one value fits every sensor and sample rate. HDR's `I` estimates what is
/// left of the bias after the static bias test, and that is, to first order, the test's own
/// error: a bound of a few standard errors keeps HDR from taking a gentle curve below its turn
/// switch for a larger drift. On a gyro whose rest reads without noise both become 0, and the
/// pipeline is plain integration of the bias-corrected rate, as it should be.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct NoiseScaled {
    /// Dead band in standard deviations of one reading's noise (replaces `threshold`), >= 0.
    pub threshold_sigmas: Option<f64>,
    /// Bound on HDR's `|I|` in standard errors of the static bias (replaces
    /// `hdr.max_correction`), >= 0.
    pub hdr_bound_sigmas: Option<f64>,
}

impl NoiseScaled {
    /// Checks both factors; the error names the first invalid one.
    pub fn validate(&self) -> Result<(), Error> {
        for (name, value) in [
            ("threshold_sigmas", self.threshold_sigmas),
            ("hdr_bound_sigmas", self.hdr_bound_sigmas),
        ] {
            if let Some(v) = value {
                check_range(name, v, 0.0, f64::MAX, "finite and >= 0")?;
            }
        }
        Ok(())
    }

    fn any(&self) -> bool {
        self.threshold_sigmas.is_some() || self.hdr_bound_sigmas.is_some()
    }
}

/// Named parameter sets. Every field can be changed after [`Preset::config`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Preset {
    /// Plain trapezoid integration of the raw rate.
    Raw,
    /// Static bias removal (HDR eq 2); set the bias or its rest window.
    StaticBias,
    /// Hong & Park: static bias, linear self-calibration (set `scale`/`offset` from a
    /// calibration) and the 0.3 deg/s threshold (Hong eq 3, 12).
    HongPark,
    /// Static bias and HDR with the paper's Table III (low-pass, HDR, de-lag).
    Hdr,
    /// Calibration, the 0.3 deg/s threshold and HDR with Table III.
    Combined,
    /// Static bias, low-pass, HDR and de-lag with parameters fitted by `gyrocore tune` (scipy) to
    /// minimise the mean NE_psi of eighteen simulated drives (HDR Table II and nine 3-minute town
    /// drives) under a do-no-harm limit; not fitted to any real log. HDR's bound is 14.3 standard
    /// errors of the static bias ([`NoiseScaled`]; 5e-5 rad/s without a rest window), no dead
    /// band; i_c 0.00213 deg/s, Theta_w 0.669 deg/s, tau 0.335 s, c1 0.0484, c2 0.905.
    Tuned,
}

impl Preset {
    /// Every preset, in order of increasing processing.
    pub const ALL: [Preset; 6] = [
        Preset::Raw,
        Preset::StaticBias,
        Preset::HongPark,
        Preset::Hdr,
        Preset::Combined,
        Preset::Tuned,
    ];

    /// The preset the documentation recommends (`"recommended"`).
    pub const RECOMMENDED: Preset = Preset::Tuned;

    /// The preset's name as used by the Python API and the command line.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Raw => "raw",
            Preset::StaticBias => "static_bias",
            Preset::HongPark => "hong_park",
            Preset::Hdr => "hdr",
            Preset::Combined => "combined",
            Preset::Tuned => "tuned",
        }
    }

    /// Looks a preset up by name; `"recommended"` gives [`Preset::RECOMMENDED`].
    pub fn from_name(name: &str) -> Option<Preset> {
        if name == "recommended" {
            return Some(Preset::RECOMMENDED);
        }
        Preset::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The preset's configuration (static bias 0 until set).
    pub fn config(self) -> PipelineConfig {
        let threshold = Some(ThresholdConfig {
            threshold: 0.3_f64.to_radians(),
        });
        let hdr = PipelineConfig {
            lowpass: Some(LowPassConfig { tau: 0.75 }),
            delag: true,
            hdr: Some(HdrConfig::table_iii()),
            ..PipelineConfig::default()
        };
        match self {
            Preset::Raw | Preset::StaticBias => PipelineConfig::default(),
            Preset::HongPark => PipelineConfig {
                threshold,
                ..PipelineConfig::default()
            },
            Preset::Hdr => hdr,
            Preset::Combined => PipelineConfig { threshold, ..hdr },
            Preset::Tuned => {
                let tau = 0.335;
                PipelineConfig {
                    lowpass: Some(LowPassConfig { tau }),
                    delag: true,
                    hdr: Some(HdrConfig {
                        increment: 3.71e-5,
                        turn_threshold: 1.17e-2,
                        c1: 0.0484,
                        c2: 0.905,
                        interval: 1.0,
                        tau,
                        max_correction: 5e-5,
                    }),
                    noise_scaled: NoiseScaled {
                        threshold_sigmas: None,
                        hdr_bound_sigmas: Some(14.3),
                    },
                    ..PipelineConfig::default()
                }
            }
        }
    }

    /// Whether the preset subtracts a static bias (so a bias or rest window should be given).
    pub fn uses_static_bias(self) -> bool {
        self != Preset::Raw
    }
}

/// Per-sample output of the pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Output {
    /// Continuous heading \[rad\], counter-clockwise positive.
    pub heading: f64,
    /// Corrected (and de-lagged) rate that was integrated [rad/s].
    pub rate: f64,
    /// HDR's drift estimate `-I` applied to this sample [rad/s] (0 without HDR).
    pub drift: f64,
}

impl Output {
    /// The output before the first sample: the initial heading, nothing measured yet.
    fn at_rest(heading: f64) -> Self {
        Output {
            heading,
            rate: 0.0,
            drift: 0.0,
        }
    }
}

/// Output slices for [`Pipeline::process_block`], each as long as the input.
#[derive(Debug)]
pub struct Outputs<'a> {
    /// Receives [`Output::heading`].
    pub heading: &'a mut [f64],
    /// Receives [`Output::rate`].
    pub rate: &'a mut [f64],
    /// Receives [`Output::drift`].
    pub drift: &'a mut [f64],
}

/// The stages with memory, each `None` when disabled, and the integrator.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Memories {
    lowpass: Option<LowPass>,
    hdr: Option<Hdr>,
    delag: Option<DeLag>,
    integrator: Integrator,
}

/// Everything of the pipeline but the stages with memory and the integrator: the stages without
/// memory of the signal and the input bookkeeping. Kept apart from [`Memories`] so that a block
/// can borrow both at once (see [`Memory`]).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Chain {
    config: PipelineConfig,
    correction: Correction,
    /// The dead band; 0 when none is configured: `|r| < 0` holds for no rate, so every rate
    /// passes unchanged, and the loops carry no test of whether there is one.
    threshold: Threshold,
    clock: Clock,
    /// The last finite (rate, temperature) reading, for [`NonFinite::Hold`].
    last_reading: Option<(f64, Option<f64>)>,
    /// The last output, repeated (with a NaN rate) for a skipped sample.
    last_output: Output,
    report: InputReport,
    /// True until the [`NoiseScaled`] values are set from the rest window.
    scaling_pending: bool,
}

/// The composed pipeline; see the module doc for the order of the stages.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Pipeline {
    chain: Chain,
    memories: Memories,
}

impl Pipeline {
    /// Validates every stage's configuration and builds the pipeline.
    pub fn new(config: PipelineConfig) -> Result<Self, Error> {
        if config.delag && config.lowpass.is_none() {
            return Err(Error::InvalidParameter {
                name: "delag",
                value: 1.0,
                valid: "false unless a low-pass is configured (de-lag inverts the low-pass)",
            });
        }
        let delag = match (config.delag, config.lowpass) {
            (true, Some(lp)) => Some(DeLag::new(lp)?),
            _ => None,
        };
        config.input.validate()?;
        config.noise_scaled.validate()?;
        Ok(Pipeline {
            chain: Chain {
                config,
                correction: Correction::new(config.correction)?,
                threshold: Threshold::new(
                    config
                        .threshold
                        .unwrap_or(ThresholdConfig { threshold: 0.0 }),
                )?,
                clock: Clock::default(),
                last_reading: None,
                last_output: Output::at_rest(config.integrator.initial_heading),
                report: InputReport::default(),
                scaling_pending: config.noise_scaled.any(),
            },
            memories: Memories {
                lowpass: config.lowpass.map(LowPass::new).transpose()?,
                hdr: config.hdr.map(Hdr::new).transpose()?,
                delag,
                integrator: Integrator::new(config.integrator)?,
            },
        })
    }

    /// The configuration.
    pub fn config(&self) -> &PipelineConfig {
        &self.chain.config
    }

    /// The static bias in use now [rad/s] and how many readings it averages.
    pub fn bias(&self) -> (f64, u64) {
        let c = &self.chain.correction;
        (c.bias(), c.bias_sample_count())
    }

    /// True while a rest window is still being measured.
    pub fn bias_learning(&self) -> bool {
        self.chain.correction.bias_learning()
    }

    /// The last timestamp processed, if any.
    pub fn last_time(&self) -> Option<f64> {
        self.chain.clock.last()
    }

    /// What the input policy has done so far (held, skipped samples; gaps).
    pub fn report(&self) -> InputReport {
        self.chain.report
    }

    /// Returns every stage to its initial state (same as a new pipeline with the same config).
    pub fn reset(&mut self) {
        // The configuration was validated when the pipeline was built.
        if let Ok(fresh) = Pipeline::new(self.chain.config) {
            *self = fresh;
        }
    }

    /// The rest window's noise and the standard error of the bias measured in it, once the
    /// window is over (see [`Correction::rest_statistics`]).
    pub fn rest_statistics(&self) -> Option<RestStatistics> {
        self.chain.correction.rest_statistics()
    }

    /// Feeds one sample (`t` \[s\], `rate` [rad/s]) without a temperature.
    #[inline]
    pub fn update(&mut self, t: f64, rate: f64) -> Output {
        self.update_with_temperature(t, rate, None)
    }

    /// Feeds one sample with the sensor temperature \[degC\] for the temperature scale model.
    ///
    /// Infallible and allocation-free. A sample whose timestamp does not move forward is skipped,
    /// and so is a non-finite reading unless the policy holds the last one: a skipped sample leaves
    /// every stage untouched and gets the last heading and drift with a NaN rate (counted in
    /// [`Pipeline::report`]). Use [`Pipeline::process_block`] to have bad input rejected instead.
    #[inline]
    pub fn update_with_temperature(
        &mut self,
        t: f64,
        rate: f64,
        temperature: Option<f64>,
    ) -> Output {
        let m = &mut self.memories;
        let mut memories = (&mut m.lowpass, &mut m.hdr, &mut m.delag, &mut m.integrator);
        self.chain
            .update::<false, true, _, _, _>(&mut memories, t, rate, temperature)
    }

    /// Checks a block (lengths; finite, strictly increasing time, also after the previous block;
    /// finite readings unless the policy holds or skips them) and, only if it is valid, feeds it
    /// through the pipeline. On an error the pipeline is as it was (the outputs are not).
    ///
    /// One pass over memory: the block runs through a copy of the pipeline that checks every
    /// sample on the way, and the copy replaces the pipeline only if all were valid, where a
    /// separate check first would read the whole block once more. Only a block with a bad sample
    /// is checked again, to name the first one (an error), or fed sample by sample when the
    /// policy holds or skips non-finite readings.
    pub fn process_block(
        &mut self,
        t: &[f64],
        rate: &[f64],
        temperature: Option<&[f64]>,
        mut out: Outputs<'_>,
    ) -> Result<(), Error> {
        let c = &self.chain;
        if c.config.correction.temperature.is_some() && temperature.is_none() {
            return Err(Error::MissingTemperature);
        }
        check_lengths(t, rate, temperature)?;
        check_len("heading", out.heading.len(), t.len())?;
        check_len("rate out", out.rate.len(), t.len())?;
        check_len("drift", out.drift.len(), t.len())?;
        let mut trial = self.clone();
        if trial.feed_fast(t, rate, temperature, &mut out) {
            *self = trial;
            return Ok(());
        }
        let readings_must_be_finite = self.chain.config.input.non_finite == NonFinite::Error;
        let last = self.chain.clock.last();
        check_block(t, rate, temperature, last, readings_must_be_finite)?;
        self.feed::<false>(t, rate, temperature, &mut out);
        Ok(())
    }

    /// The FAST [`Pipeline::feed`], compiled a second time for AVX-512 and chosen at run time
    /// where the CPU has it (with `std`, which detects it).
    ///
    /// Its 32 registers hold the loop's running values (heading, filter memories, HDR sums),
    /// where with 16 the compiler keeps some on the stack, and its three-operand instructions
    /// need no register copies. It changes no result:
    /// the operations are the same IEEE ones, one by one (no fused multiply-add is formed).
    fn feed_fast(
        &mut self,
        t: &[f64],
        rate: &[f64],
        temperature: Option<&[f64]>,
        out: &mut Outputs<'_>,
    ) -> bool {
        #[cfg(all(feature = "std", target_arch = "x86_64"))]
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU has the feature the function is compiled for.
            #[allow(unsafe_code)]
            return unsafe { self.feed_fast_avx512(t, rate, temperature, out) };
        }
        self.feed::<true>(t, rate, temperature, out)
    }

    /// [`Pipeline::feed_fast`] for CPUs with AVX-512.
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    #[target_feature(enable = "avx512f")]
    fn feed_fast_avx512(
        &mut self,
        t: &[f64],
        rate: &[f64],
        temperature: Option<&[f64]>,
        out: &mut Outputs<'_>,
    ) -> bool {
        self.feed::<true>(t, rate, temperature, out)
    }

    /// [`Chain::feed`] with the stages with memory: compiled for the concrete stages when all are
    /// on or all off (see [`Memory`], [`Off`]), for `Option`s otherwise.
    #[inline(always)]
    fn feed<const FAST: bool>(
        &mut self,
        t: &[f64],
        rate: &[f64],
        temperature: Option<&[f64]>,
        out: &mut Outputs<'_>,
    ) -> bool {
        let Pipeline { chain, memories } = self;
        match memories {
            Memories {
                lowpass: Some(l),
                hdr: Some(h),
                delag: Some(d),
                integrator,
            } => chain.feed::<FAST, _, _, _>(&mut (l, h, d, integrator), t, rate, temperature, out),
            Memories {
                lowpass: None,
                hdr: None,
                delag: None,
                integrator,
            } => {
                let m = &mut (
                    Off::<LowPass>::OFF,
                    Off::<Hdr>::OFF,
                    Off::<DeLag>::OFF,
                    integrator,
                );
                chain.feed::<FAST, _, _, _>(m, t, rate, temperature, out)
            }
            Memories {
                lowpass,
                hdr,
                delag,
                integrator,
            } => {
                let m = &mut (lowpass, hdr, delag, integrator);
                chain.feed::<FAST, _, _, _>(m, t, rate, temperature, out)
            }
        }
    }
}

impl Chain {
    /// Restarts the stages whose state is a memory of the recent signal (the dead band has
    /// none).
    #[inline(always)]
    fn restart<L: Memory, H: Memory, D: Memory>(memories: &mut (L, H, D, &mut Integrator)) {
        memories.0.restart();
        memories.1.restart();
        memories.2.restart();
    }

    /// The interval and the reading to use for a sample under the input policy (the clock then
    /// moves to `t`), or `None` to skip the sample and leave everything as it was.
    #[inline]
    fn admit(
        &mut self,
        t: f64,
        rate: f64,
        temperature: Option<f64>,
    ) -> Option<(f64, f64, Option<f64>)> {
        let dt = self.clock.interval(t)?;
        let reading = if finite_reading(rate, temperature) {
            self.last_reading = Some((rate, temperature));
            (rate, temperature)
        } else {
            match (self.config.input.non_finite, self.last_reading) {
                (NonFinite::Hold, Some(held)) => {
                    self.report.held += 1;
                    held
                }
                _ => return None,
            }
        };
        self.clock.set(t);
        Some((dt, reading.0, reading.1))
    }

    /// [`Pipeline::update_with_temperature`] with the stages with memory borrowed apart (see
    /// [`Chain::step`] for `SETTLED` and `SPLIT`).
    #[inline(always)]
    fn update<const SETTLED: bool, const SPLIT: bool, L: Memory, H: Memory, D: Memory>(
        &mut self,
        memories: &mut (L, H, D, &mut Integrator),
        t: f64,
        rate: f64,
        temperature: Option<f64>,
    ) -> Output {
        let Some((dt, rate, temperature)) = self.admit(t, rate, temperature) else {
            self.report.skipped += 1;
            return Output {
                rate: f64::NAN,
                ..self.last_output
            };
        };
        self.last_output = self.step::<SETTLED, SPLIT, L, H, D>(memories, t, dt, rate, temperature);
        self.last_output
    }

    /// True once the rest window is over and what it measured is applied ([`NoiseScaled`]):
    /// nothing about the bias changes after that.
    #[inline(always)]
    fn settled(&self) -> bool {
        !self.scaling_pending && !self.correction.bias_learning()
    }

    /// Sets the [`NoiseScaled`] dead band and HDR bound from the rest window that just ended.
    #[cold]
    fn scale_to_rest<H: Memory>(&mut self, hdr: &mut H) {
        self.scaling_pending = false;
        let Some(rest) = self.correction.rest_statistics() else {
            return;
        };
        let scaled = self.config.noise_scaled;
        if let Some(k) = scaled.threshold_sigmas {
            self.threshold = Threshold::start(ThresholdConfig {
                threshold: k * rest.noise,
            });
        }
        if let Some(k) = scaled.hdr_bound_sigmas {
            hdr.bound(k * rest.bias_std_error);
        }
    }

    /// The stages, in order, for one admitted sample with interval `dt`.
    ///
    /// `SETTLED`: the pipeline is [`Chain::settled`], so the sample need not check for the end of
    /// the rest window. The block loops run settled samples separately: that check, with the
    /// dead band and HDR bound it may change, costs the loop about a third of its speed. `SPLIT`:
    /// see [`Correction::apply_directed`].
    #[inline(always)]
    fn step<const SETTLED: bool, const SPLIT: bool, L: Memory, H: Memory, D: Memory>(
        &mut self,
        memories: &mut (L, H, D, &mut Integrator),
        t: f64,
        dt: f64,
        rate: f64,
        temperature: Option<f64>,
    ) -> Output {
        if dt > self.config.input.gap_limit {
            self.report.gap(dt);
            if self.config.input.gap_action == GapAction::Reset {
                Self::restart(memories);
            }
        }
        let r = self
            .correction
            .apply_directed::<SPLIT>(t, rate, temperature);
        let learning = !SETTLED && self.correction.bias_learning();
        if !SETTLED && self.scaling_pending && !learning {
            self.scale_to_rest(&mut memories.1);
        }
        self.filter(memories, dt, r, learning)
    }

    /// The stages after the correction, in order, for one sample with interval `dt` and
    /// corrected rate `r`: dead band, low-pass, HDR (not while the bias is `learning`), de-lag,
    /// integration.
    #[inline(always)]
    fn filter<L: Feed, H: Feed, D: Feed, I: Feed>(
        &self,
        stages: &mut (L, H, D, I),
        dt: f64,
        r: f64,
        learning: bool,
    ) -> Output {
        let (lowpass, hdr, delag, integrator) = stages;
        let corrected = self.threshold.apply(r);
        let mut r = lowpass.feed(dt, corrected);
        // HDR decides on its own low-passed step means of the corrected rate (see `Hdr`) and its
        // `I` is added to the per-sample low-passed rate, which the de-lag then restores. It starts
        // once the static bias is known: during the rest window it would only chase the running
        // estimate of the bias (the papers measure the bias before the drive, then run HDR).
        let mut drift = 0.0;
        if !learning {
            let integrator = hdr.feed(dt, corrected);
            drift = -integrator;
            r += integrator;
        }
        let r = delag.feed(dt, r);
        let heading = integrator.feed(dt, r);
        Output {
            heading,
            rate: r,
            drift,
        }
    }

    /// The loops of [`Pipeline::process_block`], with or without temperature (a closure, so the
    /// loop without temperature carries no lookups), and compiled for a single direction factor
    /// when the two are equal (see [`Correction::apply_directed`]). See [`Chain::run`] for `FAST`.
    #[inline(always)]
    fn feed<const FAST: bool, L: Memory, H: Memory, D: Memory>(
        &mut self,
        memories: &mut (L, H, D, &mut Integrator),
        t: &[f64],
        rate: &[f64],
        temperature: Option<&[f64]>,
        out: &mut Outputs<'_>,
    ) -> bool {
        let m = memories;
        match (temperature, self.correction.direction_split()) {
            (Some(temp), true) => {
                self.run::<FAST, true, _, _, _>(m, t, rate, |i| Some(temp[i]), out)
            }
            (Some(temp), false) => {
                self.run::<FAST, false, _, _, _>(m, t, rate, |i| Some(temp[i]), out)
            }
            (None, true) => self.run::<FAST, true, _, _, _>(m, t, rate, |_| None, out),
            (None, false) => self.run::<FAST, false, _, _, _>(m, t, rate, |_| None, out),
        }
    }

    /// One loop over a block whose slices have equal lengths; `temperature_at(i)` gives the
    /// temperature of sample `i`.
    ///
    /// `FAST`: every sample is taken as admissible (the interval comes straight from the
    /// timestamps, the input policy's memories are updated once, at the end) and checked on the
    /// way; returns false if any was not (a timestamp not after the one before, a non-finite
    /// one or reading), and the state is then meaningless. Otherwise each sample is admitted
    /// as [`Chain::update`] does (timestamps must have been checked) and the result is true.
    ///
    /// A FAST loop does not check the readings of settled samples one by one: a non-finite
    /// reading makes the heading non-finite from that sample on, and the heading is checked at
    /// the end. Every stage on the way carries it: the correction, dead band (`|NaN| < x` is
    /// false), low-pass and de-lag (weights > 0 for intervals > 0, and `0 * inf` is NaN) and the
    /// integrator, which no gap restarts, so a non-finite heading stays so. HDR's `I` is only
    /// added and stays bounded. A finite block whose heading overflows is only checked again.
    #[inline(always)]
    fn run<const FAST: bool, const SPLIT: bool, L: Memory, H: Memory, D: Memory>(
        &mut self,
        memories: &mut (L, H, D, &mut Integrator),
        t: &[f64],
        rate: &[f64],
        temperature_at: impl Fn(usize) -> Option<f64>,
        out: &mut Outputs<'_>,
    ) -> bool {
        let n = t.len();
        let block = &mut Block {
            t,
            rate,
            temperature_at: &temperature_at,
            out,
        };
        let mut cursor = Cursor {
            previous: self.clock.last().unwrap_or(0.0),
            next: 0,
            checks: Checks::default(),
            output: self.last_output,
        };
        // The first sample of a stream has no interval (0, as `Clock` gives it): it is checked
        // on its own, and every later one by its interval from the one before.
        if let (None, Some(&first), true) = (self.clock.last(), t.first(), FAST) {
            cursor.checks.finite(first);
            cursor.checks.reading(rate[0], temperature_at(0));
            cursor.output = self.step::<false, SPLIT, L, H, D>(
                memories,
                first,
                0.0,
                rate[0],
                temperature_at(0),
            );
            block.out.set(0, cursor.output);
            (cursor.previous, cursor.next) = (first, 1);
        }
        if !self.settled() {
            self.span::<FAST, false, SPLIT, L, H, D>(memories, block, &mut cursor, n);
        }
        // The settled samples: all they can through primed copies of the stages, the others
        // (a gap, a bad interval, a reading the policy holds or skips, and any before every stage
        // has had a sample) one at a time through `step`.
        while cursor.next < n {
            if memories.3.trapezoid() {
                self.primed_stretch::<FAST, SPLIT, true, L, H, D>(memories, block, &mut cursor);
            } else {
                self.primed_stretch::<FAST, SPLIT, false, L, H, D>(memories, block, &mut cursor);
            }
            if cursor.next < n {
                if FAST && !cursor.checks.passed() {
                    return false;
                }
                let next = cursor.next + 1;
                self.span::<FAST, true, SPLIT, L, H, D>(memories, block, &mut cursor, next);
            }
        }
        if FAST && n > 0 {
            self.took(
                t[n - 1],
                (rate[n - 1], temperature_at(n - 1)),
                cursor.output,
            );
        }
        !FAST || (cursor.checks.passed() && memories.3.heading().is_finite())
    }

    /// What [`Chain::update`] leaves of a sample at `t` with a finite `reading` (rate,
    /// temperature) and its `output`, for a loop that takes samples without it: the clock, the
    /// reading [`NonFinite::Hold`] would hold, and the last output.
    #[inline(always)]
    fn took(&mut self, t: f64, reading: (f64, Option<f64>), output: Output) {
        self.clock.set(t);
        self.last_reading = Some(reading);
        self.last_output = output;
    }

    /// The samples of [`Chain::run`] from `cursor.next` on that [`Chain::primed_span`] takes,
    /// through primed copies of `memories` whose state is then taken back (none while a stage
    /// has yet to see a sample). `TRAPEZOID` is the integration rule's
    /// ([`Integrator::trapezoid`]), a compile-time choice for the loop.
    #[inline(always)]
    fn primed_stretch<
        const FAST: bool,
        const SPLIT: bool,
        const TRAPEZOID: bool,
        L: Memory,
        H: Memory,
        D: Memory,
    >(
        &mut self,
        memories: &mut (L, H, D, &mut Integrator),
        block: &mut Block<'_, '_, impl Fn(usize) -> Option<f64>>,
        cursor: &mut Cursor,
    ) {
        // The copies borrow `memories`, which takes their state back once they are gone.
        let states = {
            let Some(mut primed) = primed::<TRAPEZOID, L, H, D>(memories) else {
                return;
            };
            self.primed_span::<FAST, SPLIT, TRAPEZOID, _, _, _>(&mut primed, block, cursor);
            let (lowpass, hdr, delag, integrator) = primed;
            (
                L::state(lowpass),
                H::state(hdr),
                D::state(delag),
                integrator,
            )
        };
        memories.0.set_state(states.0);
        memories.1.set_state(states.1);
        memories.2.set_state(states.2);
        memories.3.set_primed(states.3);
    }

    /// The samples of [`Chain::run`] from `cursor.next` to `end`; unless `SETTLED`, only until
    /// the pipeline is settled (see [`Chain::step`]).
    #[inline(always)]
    fn span<
        const FAST: bool,
        const SETTLED: bool,
        const SPLIT: bool,
        L: Memory,
        H: Memory,
        D: Memory,
    >(
        &mut self,
        memories: &mut (L, H, D, &mut Integrator),
        block: &mut Block<'_, '_, impl Fn(usize) -> Option<f64>>,
        cursor: &mut Cursor,
        end: usize,
    ) {
        let Block {
            t,
            rate,
            temperature_at,
            out,
        } = block;
        // A local copy, so that the loop keeps it in registers.
        let mut c = *cursor;
        while c.next < end {
            let i = c.next;
            c.output = if FAST {
                let dt = t[i] - c.previous;
                c.previous = t[i];
                c.checks.interval(dt);
                c.checks.reading(rate[i], temperature_at(i));
                self.step::<SETTLED, SPLIT, L, H, D>(memories, t[i], dt, rate[i], temperature_at(i))
            } else {
                let o = self.update::<SETTLED, SPLIT, L, H, D>(
                    memories,
                    t[i],
                    rate[i],
                    temperature_at(i),
                );
                c.previous = self.clock.last().unwrap_or(c.previous);
                o
            };
            out.set(i, c.output);
            c.next += 1;
            if !SETTLED && self.settled() {
                break;
            }
        }
        *cursor = c;
    }

    /// One settled sample through `primed` stages: its correction and the stages after it.
    #[inline(always)]
    fn primed_sample<const SPLIT: bool, const TRAPEZOID: bool, L: Feed, H: Feed, D: Feed>(
        &self,
        primed: &mut (L, H, D, PrimedIntegrator<TRAPEZOID>),
        dt: f64,
        rate: f64,
        temperature: Option<f64>,
    ) -> Output {
        let r = self.correction.settled::<SPLIT>(rate, temperature);
        self.filter(primed, dt, r, false)
    }

    /// The settled samples of [`Chain::run`] from `cursor.next` on, through `primed` stages (see
    /// [`Memory::primed`]).
    ///
    /// A FAST loop that bridges gaps (the default) takes every sample: a bad interval is noted
    /// in the checks, and gaps are counted after the loop, only if the longest interval is one.
    /// Any other loop stops at a sample that needs
    /// [`Chain::step`]: one whose interval is not in (0, gap limit] (a gap to restart at, or a
    /// timestamp not after the one before) or, unless `FAST`, a non-finite reading, which the
    /// input policy holds or skips.
    ///
    /// Primed stages have no first-sample case to check, a FAST loop leaves the readings to the
    /// heading check (see [`Chain::run`]), and the copies are local, so the compiler keeps their
    /// state in registers from one sample to the next. Against the loop through [`Chain::step`]
    /// on copies of the stages (`benches/pipeline.rs`, ns/sample): `combined` 4.49 -> 4.09,
    /// `tuned` 4.04 -> 3.71, and with [`Off`] `raw` 2.09 -> 1.11. A loop without an exit keeps
    /// more of it there: `combined` 3.96 -> 3.61, `tuned` 3.61 -> 3.34, `hdr` 3.61 -> 3.28, for
    /// `raw` 1.10 -> 1.14 and `hong_park` 1.29 -> 1.37 (two alternating runs of each).
    #[inline(always)]
    fn primed_span<
        const FAST: bool,
        const SPLIT: bool,
        const TRAPEZOID: bool,
        L: Feed,
        H: Feed,
        D: Feed,
    >(
        &mut self,
        primed: &mut (L, H, D, PrimedIntegrator<TRAPEZOID>),
        block: &mut Block<'_, '_, impl Fn(usize) -> Option<f64>>,
        cursor: &mut Cursor,
    ) {
        let Block {
            t,
            rate,
            temperature_at,
            out,
        } = block;
        let n = t.len();
        // Slices of one length, so the loop carries no bounds checks.
        let rate = &rate[..n];
        let mut out = Outputs {
            heading: &mut out.heading[..n],
            rate: &mut out.rate[..n],
            drift: &mut out.drift[..n],
        };
        // A local copy, so that the loop keeps it in registers.
        let mut c = *cursor;
        let limit = self.config.input.gap_limit;
        if FAST && self.config.input.gap_action == GapAction::Bridge {
            for i in c.next..n {
                let dt = t[i] - c.previous;
                c.previous = t[i];
                c.checks.interval(dt);
                let temperature = temperature_at(i);
                c.checks.temperature(temperature);
                c.output = self.primed_sample::<SPLIT, TRAPEZOID, _, _, _>(
                    primed,
                    dt,
                    rate[i],
                    temperature,
                );
                out.set(i, c.output);
            }
            c.next = n;
            // The checks have the longest interval. Only if it is a gap are the gaps counted, in
            // a pass over the timestamps: the loop carries nothing for them. (If an interval was
            // not valid, the block is taken again and nothing counted here is kept.)
            if let Some(longest) = c.checks.longest_interval().filter(|&dt| dt > limit) {
                let gaps = intervals_over(cursor.previous, &t[cursor.next..], limit);
                self.report.gaps_up_to(gaps, longest);
            }
        } else {
            let longest = interval_key(limit.min(f64::MAX));
            while c.next < n {
                let i = c.next;
                let dt = t[i] - c.previous;
                if interval_key(dt) > longest {
                    break;
                }
                let temperature = temperature_at(i);
                if FAST {
                    c.checks.temperature(temperature);
                } else if !finite_reading(rate[i], temperature) {
                    break;
                }
                c.previous = t[i];
                c.output = self.primed_sample::<SPLIT, TRAPEZOID, _, _, _>(
                    primed,
                    dt,
                    rate[i],
                    temperature,
                );
                out.set(i, c.output);
                c.next += 1;
            }
        }
        if !FAST && c.next > cursor.next {
            let last = c.next - 1;
            self.took(t[last], (rate[last], temperature_at(last)), c.output);
        }
        *cursor = c;
    }
}

/// Primed copies of the stages with memory and of the integrator (see [`Memory::primed`]), or
/// `None` while one has yet to see a sample.
#[inline(always)]
#[allow(clippy::type_complexity)]
fn primed<'a, const TRAPEZOID: bool, L: Memory, H: Memory, D: Memory>(
    memories: &'a (L, H, D, &mut Integrator),
) -> Option<(
    L::Primed<'a>,
    H::Primed<'a>,
    D::Primed<'a>,
    PrimedIntegrator<TRAPEZOID>,
)> {
    Some((
        memories.0.primed()?,
        memories.1.primed()?,
        memories.2.primed()?,
        memories.3.primed()?,
    ))
}

/// How many of the intervals from `start` to `t[0]` and between the timestamps `t` are longer
/// than `limit`.
fn intervals_over(start: f64, t: &[f64], limit: f64) -> u64 {
    let previous = core::iter::once(start).chain(t.iter().copied());
    previous
        .zip(t)
        .map(|(a, &b)| u64::from(b - a > limit))
        .sum()
}

/// A block's samples and outputs, as [`Chain::run`]'s loops share them; `temperature_at(i)`
/// gives the temperature of sample `i`.
struct Block<'a, 'o, T> {
    t: &'a [f64],
    rate: &'a [f64],
    temperature_at: &'a T,
    out: &'a mut Outputs<'o>,
}

/// Where a block's loop stands, carried from one of [`Chain::run`]'s loops to the next.
#[derive(Clone, Copy)]
struct Cursor {
    previous: f64,
    next: usize,
    checks: Checks,
    output: Output,
}

impl Outputs<'_> {
    /// Writes sample `i`'s output.
    #[inline(always)]
    fn set(&mut self, i: usize, o: Output) {
        self.heading[i] = o.heading;
        self.rate[i] = o.rate;
        self.drift[i] = o.drift;
    }
}

#[cfg(all(test, feature = "std", target_arch = "x86_64"))]
mod tests {
    use super::*;
    use crate::integrate::Method;

    /// Runs a block of `n` samples through `p` with `feed`; the outputs as bits, and the pipeline.
    fn outputs(
        mut p: Pipeline,
        n: usize,
        feed: impl Fn(&mut Pipeline, &mut Outputs<'_>) -> bool,
    ) -> (Vec<u64>, Pipeline) {
        let (mut h, mut r, mut d) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let mut out = Outputs {
            heading: &mut h,
            rate: &mut r,
            drift: &mut d,
        };
        assert!(feed(&mut p, &mut out));
        let bits = h.iter().chain(&r).chain(&d).map(|x| x.to_bits()).collect();
        (bits, p)
    }

    /// The loop compiled for AVX-512 gives, bit for bit, what the portable loop gives: every
    /// preset, both integration rules, a rest window, turns and a gap.
    #[test]
    fn the_avx512_loop_gives_what_the_portable_loop_gives() {
        if !std::arch::is_x86_feature_detected!("avx512f") {
            eprintln!("this CPU has no AVX-512: only the portable loop runs");
            return;
        }
        let n = 20_000;
        let t: Vec<f64> = (0..n)
            .map(|i| 1.7e9 + i as f64 * 0.01 + if i > 12_000 { 5.0 } else { 0.0 })
            .collect();
        let rate: Vec<f64> = (0..n)
            .map(|i| {
                let s = i as f64 * 0.01;
                let turn = if s > 40.0 {
                    0.4 * (s * 0.2).sin().powi(9)
                } else {
                    0.0
                };
                0.003 + turn + 0.002 * (s * 37.0).sin()
            })
            .collect();
        for preset in Preset::ALL {
            for method in [Method::Trapezoid, Method::Rectangle] {
                let mut config = preset.config();
                config.integrator.method = method;
                let p = Pipeline::new(config).unwrap();
                let portable = outputs(p.clone(), n, |p, out| p.feed::<true>(&t, &rate, None, out));
                // SAFETY: the CPU has AVX-512 (checked above).
                #[allow(unsafe_code)]
                let avx512 = outputs(p, n, |p, out| unsafe {
                    p.feed_fast_avx512(&t, &rate, None, out)
                });
                assert!(portable == avx512, "{preset:?} {method:?}");
            }
        }
    }
}
