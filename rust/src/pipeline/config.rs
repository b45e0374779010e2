//! What the pipeline runs: [`PipelineConfig`] with every rule between its parameters in
//! [`PipelineConfig::validate`], and the named [`Preset`]s.

use crate::correction::CorrectionConfig;
use crate::error::check_range;
use crate::hdr::HdrConfig;
use crate::input::InputPolicy;
use crate::integrate::IntegratorConfig;
use crate::lowpass::LowPassConfig;
use crate::rest_tracker::RestTrackerConfig;
use crate::threshold::ThresholdConfig;
use crate::{Error, MAX_READING};

/// Which stages run, and how. `None` disables a stage.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PipelineConfig {
    /// Bias, calibration and scale-factor correction (always runs; identity by default).
    pub correction: CorrectionConfig,
    /// Dead band (Hong eq 12).
    pub threshold: Option<ThresholdConfig>,
    /// Low-pass of the per-sample rate before HDR's `I` is added (HDR eq 7); HDR low-passes
    /// its step means with the same time constant ([`HdrConfig::tau`] must equal it; set both
    /// with [`PipelineConfig::set_lowpass_tau`]).
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
    /// Rests found while driving re-measure the bias (see [`crate::rest_tracker`]); `None`: the
    /// bias is the one given or measured in the rest window, for the whole stream.
    pub rest_tracker: Option<RestTrackerConfig>,
}

impl PipelineConfig {
    /// Checks every stage's settings and the rules between them; the error names the first
    /// parameter at fault (the Python API and the command line report the same text).
    ///
    /// The rules: de-lag needs a low-pass (it inverts one); HDR low-passes its step means with
    /// the low-pass's time constant (one `tau`, as in the paper's eq 7); a threshold of 0 is no
    /// dead band (`|r| < 0` holds for no rate).
    pub fn validate(&self) -> Result<(), Error> {
        self.correction.validate()?;
        if let Some(t) = self.threshold {
            t.validate()?;
        }
        if let Some(l) = self.lowpass {
            l.validate()?;
        }
        if self.delag && self.lowpass.is_none() {
            return Err(Error::InvalidParameter {
                name: "delag",
                value: 1.0,
                valid: "false unless a low-pass is configured (de-lag inverts the low-pass): \
                        set lowpass_tau > 0 or turn delag off",
            });
        }
        if let Some(h) = self.hdr {
            h.validate()?;
            let tau = self.lowpass.map_or(0.0, |l| l.tau);
            if h.tau != tau {
                return Err(Error::InvalidParameter {
                    name: "hdr.tau",
                    value: h.tau,
                    valid: "equal to lowpass_tau (0 without a low-pass): one time constant \
                            smooths the samples and HDR's step means (HDR eq 7); \
                            PipelineConfig::set_lowpass_tau sets both",
                });
            }
        }
        self.integrator.validate()?;
        self.input.validate()?;
        self.noise_scaled.validate()?;
        match self.rest_tracker {
            Some(r) => r.validate(),
            None => Ok(()),
        }
    }

    /// Sets the low-pass time constant `tau` \[s\] of HDR eq 7 for the samples and for HDR's
    /// step means alike; 0 removes the low-pass.
    pub fn set_lowpass_tau(&mut self, tau: f64) {
        self.lowpass = (tau != 0.0).then_some(LowPassConfig { tau });
        if let Some(h) = &mut self.hdr {
            h.tau = tau;
        }
    }

    /// Turns HDR on with Table III's parameters (and this configuration's `tau`), or off.
    pub fn set_hdr(&mut self, on: bool) {
        self.hdr = on.then(|| HdrConfig {
            tau: self.lowpass.map_or(0.0, |l| l.tau),
            ..self.hdr.unwrap_or_else(HdrConfig::table_iii)
        });
    }
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
    /// Checks both factors (>= 0 and at most 2^20); the error names the first invalid one.
    ///
    /// Bounded so that a factor times the rest's noise (itself below 2^21 rad/s) stays finite: a
    /// factor of 1e308 over a noisy rest made the dead band infinite, every rate 0, and a
    /// pipeline state that `serde_json` writes but cannot read back (infinity as `null`).
    pub fn validate(&self) -> Result<(), Error> {
        for (name, value) in [
            ("threshold_sigmas", self.threshold_sigmas),
            ("hdr_bound_sigmas", self.hdr_bound_sigmas),
        ] {
            if let Some(v) = value {
                check_range(name, v, 0.0, MAX_READING, "finite, >= 0 and at most 2^20")?;
            }
        }
        Ok(())
    }

    pub(crate) fn any(&self) -> bool {
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
    /// minimise the mean log ratio of E_psi to static-bias removal's over the 18 real logs (in
    /// whole mode) and nine simulated 3-minute town drives, under a do-no-harm limit of 0.5 deg on
    /// 18 simulated gyros without bias (perfect and noisy); the README gives the command and the
    /// leave-one-log-out figures. Three parameters were fitted, the rest are Table III's (tau
    /// 0.75 s, c1 0.16, c2 1.80): i_c 0.00686 deg/s, Theta_w 3.65 deg/s, and HDR's bound, 0.211
    /// standard errors of the static bias ([`NoiseScaled`]; 5e-5 rad/s without a rest); no dead
    /// band.
    Tuned,
    /// [`Preset::Tuned`] with the bias re-measured at every rest it finds while driving
    /// ([`crate::rest_tracker`]). Give it a speed where there is one: from the rate alone, a long
    /// steady turn can pass for a rest (the README's figures show what that costs).
    Tracked,
}

impl Preset {
    /// Every preset, in order of increasing processing.
    pub const ALL: [Preset; 7] = [
        Preset::Raw,
        Preset::StaticBias,
        Preset::HongPark,
        Preset::Hdr,
        Preset::Combined,
        Preset::Tuned,
        Preset::Tracked,
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
            Preset::Tracked => "tracked",
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
            Preset::Tuned => PipelineConfig {
                hdr: Some(HdrConfig {
                    increment: 1.20e-4,
                    turn_threshold: 6.37e-2,
                    max_correction: 5e-5,
                    ..HdrConfig::table_iii()
                }),
                noise_scaled: NoiseScaled {
                    threshold_sigmas: None,
                    hdr_bound_sigmas: Some(0.211),
                },
                ..hdr
            },
            Preset::Tracked => PipelineConfig {
                rest_tracker: Some(RestTrackerConfig::default()),
                ..Preset::Tuned.config()
            },
        }
    }

    /// Whether the preset subtracts a static bias (so a bias or rest window should be given).
    pub fn uses_static_bias(self) -> bool {
        self != Preset::Raw
    }
}
