//! The whole chain in one pass: correction -> threshold -> low-pass -> HDR -> de-lag -> integrate.
//! No intermediate arrays: every enabled stage sees each sample once, in order.

use crate::correction::{Correction, CorrectionConfig};
use crate::hdr::{Hdr, HdrConfig};
use crate::input::{GapAction, InputPolicy, InputReport, NonFinite};
use crate::integrate::{Integrator, IntegratorConfig};
use crate::lowpass::{DeLag, LowPass, LowPassConfig};
use crate::stage::{check_len, Clock};
use crate::threshold::{Threshold, ThresholdConfig};
use crate::validate::{all_finite, check_block};
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
    /// `Combined` with parameters fitted by `gyrocore tune` (scipy) to minimise the mean NE_psi of
    /// nine simulated Table II drives, under a do-no-harm limit on six perfect-gyro drives; not
    /// fitted to any real log. A much smaller increment than Table III (0.00187 deg/s), threshold
    /// 0.171 deg/s, turn threshold 0.402 deg/s, tau 0.072 s, c1 0.203, c2 0.285.
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
                let tau = 0.072;
                PipelineConfig {
                    threshold: Some(ThresholdConfig { threshold: 2.98e-3 }),
                    lowpass: Some(LowPassConfig { tau }),
                    delag: true,
                    hdr: Some(HdrConfig {
                        increment: 3.26e-5,
                        turn_threshold: 7.02e-3,
                        c1: 0.203,
                        c2: 0.285,
                        interval: 1.0,
                        tau,
                    }),
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
    /// Continuous heading [rad], counter-clockwise positive.
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

/// The composed pipeline; see the module doc for the order of the stages.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Pipeline {
    config: PipelineConfig,
    correction: Correction,
    threshold: Option<Threshold>,
    lowpass: Option<LowPass>,
    hdr: Option<Hdr>,
    delag: Option<DeLag>,
    integrator: Integrator,
    clock: Clock,
    /// The last finite (rate, temperature) reading, for [`NonFinite::Hold`].
    last_reading: Option<(f64, Option<f64>)>,
    /// The last output, repeated (with a NaN rate) for a skipped sample.
    last_output: Output,
    report: InputReport,
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
        Ok(Pipeline {
            config,
            correction: Correction::new(config.correction)?,
            threshold: config.threshold.map(Threshold::new).transpose()?,
            lowpass: config.lowpass.map(LowPass::new).transpose()?,
            hdr: config.hdr.map(Hdr::new).transpose()?,
            delag,
            integrator: Integrator::new(config.integrator)?,
            clock: Clock::default(),
            last_reading: None,
            last_output: Output::at_rest(config.integrator.initial_heading),
            report: InputReport::default(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &PipelineConfig {
        &self.config
    }

    /// The static bias in use now [rad/s] and how many readings it averages.
    pub fn bias(&self) -> (f64, u64) {
        (self.correction.bias(), self.correction.bias_sample_count())
    }

    /// True while a rest window is still being measured.
    pub fn bias_learning(&self) -> bool {
        self.correction.bias_learning()
    }

    /// The last timestamp processed, if any.
    pub fn last_time(&self) -> Option<f64> {
        self.clock.last()
    }

    /// What the input policy has done so far (held, skipped samples; gaps).
    pub fn report(&self) -> InputReport {
        self.report
    }

    /// Returns every stage to its initial state (same as a new pipeline with the same config).
    pub fn reset(&mut self) {
        use crate::stage::Stage;
        self.correction.reset();
        self.reset_memory();
        self.integrator.reset();
        self.clock = Clock::default();
        self.last_reading = None;
        self.last_output = Output::at_rest(self.config.integrator.initial_heading);
        self.report = InputReport::default();
    }

    /// Restarts the stages whose state is a memory of the recent signal (HDR, low-pass, de-lag).
    #[inline(always)]
    fn reset_memory(&mut self) {
        use crate::stage::Stage;
        if let Some(s) = &mut self.threshold {
            s.reset();
        }
        if let Some(s) = &mut self.lowpass {
            s.reset();
        }
        if let Some(s) = &mut self.hdr {
            s.reset();
        }
        if let Some(s) = &mut self.delag {
            s.reset();
        }
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
        let reading = if rate.is_finite() && temperature.is_none_or(f64::is_finite) {
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

    /// Feeds one sample (`t` [s], `rate` [rad/s]) without a temperature.
    #[inline]
    pub fn update(&mut self, t: f64, rate: f64) -> Output {
        self.update_with_temperature(t, rate, None)
    }

    /// Feeds one sample with the sensor temperature [degC] for the temperature scale model.
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
        let Some((dt, rate, temperature)) = self.admit(t, rate, temperature) else {
            self.report.skipped += 1;
            return Output {
                rate: f64::NAN,
                ..self.last_output
            };
        };
        self.last_output = self.step(t, dt, rate, temperature);
        self.last_output
    }

    /// The stages, in order, for one admitted sample with interval `dt`.
    #[inline(always)]
    fn step(&mut self, t: f64, dt: f64, rate: f64, temperature: Option<f64>) -> Output {
        if dt > self.config.input.gap_limit {
            self.report.gaps += 1;
            self.report.longest_gap = self.report.longest_gap.max(dt);
            if self.config.input.gap_action == GapAction::Reset {
                self.reset_memory();
            }
        }
        let corrected = {
            let r = self.correction.apply(t, rate, temperature);
            self.threshold.as_ref().map_or(r, |s| s.apply(r))
        };
        let mut r = match &mut self.lowpass {
            Some(s) => s.step(dt, corrected),
            None => corrected,
        };
        // HDR decides on its own low-passed step means of the corrected rate (see `Hdr`) and its
        // `I` is added to the per-sample low-passed rate, which the de-lag then restores. It starts
        // once the static bias is known: during the rest window it would only chase the running
        // estimate of the bias (the papers measure the bias before the drive, then run HDR).
        let mut drift = 0.0;
        if let (Some(s), false) = (&mut self.hdr, self.correction.bias_learning()) {
            let integrator = s.observe(dt, corrected);
            drift = -integrator;
            r += integrator;
        }
        if let Some(s) = &mut self.delag {
            r = s.step(dt, r);
        }
        let heading = self.integrator.step(dt, r);
        Output {
            heading,
            rate: r,
            drift,
        }
    }

    /// Checks a block (lengths; finite, strictly increasing time, also after the previous block;
    /// finite readings unless the policy holds or skips them) and, only if it is valid, feeds it
    /// through the pipeline.
    pub fn process_block(
        &mut self,
        t: &[f64],
        rate: &[f64],
        temperature: Option<&[f64]>,
        out: Outputs<'_>,
    ) -> Result<(), Error> {
        if self.config.correction.temperature.is_some() && temperature.is_none() {
            return Err(Error::MissingTemperature);
        }
        let readings_must_be_finite = self.config.input.non_finite == NonFinite::Error;
        check_block(
            t,
            rate,
            temperature,
            self.clock.last(),
            readings_must_be_finite,
        )?;
        check_len("heading", out.heading.len(), t.len())?;
        check_len("rate out", out.rate.len(), t.len())?;
        check_len("drift", out.drift.len(), t.len())?;
        // Checked blocks of finite readings (the common case) skip the per-sample admission.
        let readings_finite =
            readings_must_be_finite || (all_finite(rate) && temperature.is_none_or(all_finite));
        match (temperature, readings_finite) {
            (Some(temp), true) => self.feed::<true>(t, rate, |i| Some(temp[i]), out),
            (None, true) => self.feed::<true>(t, rate, |_| None, out),
            (Some(temp), false) => self.feed::<false>(t, rate, |i| Some(temp[i]), out),
            (None, false) => self.feed::<false>(t, rate, |_| None, out),
        }
        Ok(())
    }

    /// The loop of [`Pipeline::process_block`] over checked slices; `temperature_at(i)` gives the
    /// temperature of sample `i` (a closure, so the loop without temperature carries no lookups).
    ///
    /// With `FINITE` (every reading is known to be finite) every sample is admitted, so the
    /// interval comes straight from the timestamps and the memories of the input policy are updated
    /// once, at the end; otherwise each sample goes through [`Pipeline::update_with_temperature`].
    #[inline(always)]
    fn feed<const FINITE: bool>(
        &mut self,
        t: &[f64],
        rate: &[f64],
        temperature_at: impl Fn(usize) -> Option<f64>,
        out: Outputs<'_>,
    ) {
        let n = t.len();
        let (rate, heading, rate_out, drift) = (
            &rate[..n],
            &mut out.heading[..n],
            &mut out.rate[..n],
            &mut out.drift[..n],
        );
        let mut previous = self.clock.last().or(t.first().copied()).unwrap_or(0.0);
        let mut o = self.last_output;
        for i in 0..n {
            o = if FINITE {
                let dt = t[i] - previous;
                previous = t[i];
                self.step(t[i], dt, rate[i], temperature_at(i))
            } else {
                self.update_with_temperature(t[i], rate[i], temperature_at(i))
            };
            heading[i] = o.heading;
            rate_out[i] = o.rate;
            drift[i] = o.drift;
        }
        if FINITE && n > 0 {
            self.clock.set(t[n - 1]);
            self.last_reading = Some((rate[n - 1], temperature_at(n - 1)));
            self.last_output = o;
        }
    }
}
