//! Sensor-error correction: static bias (HDR eq 2), linear calibration (Hong eq 3),
//! direction-dependent scale factors (FOG eq 2-4) and a temperature-linear scale factor (FOG eq 5-6).
//!
//! Order, as the papers apply them: the static bias measured at rest is subtracted first
//! (`r_m - eps0`), the linear calibration `s_bar * (.) + b_bar` follows, and the scale factors
//! multiply the result. The bias is what the gyro reads at rest (corrected = measured - bias).

use crate::error::{check_finite, check_positive, check_range};
use crate::rest::{RestNoise, RestStatistics};
use crate::stage::{Clock, Stage};
use crate::Error;

/// Where the static bias `eps0` comes from (HDR eq 1-2, FOG section 2).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum StaticBias {
    /// A known bias [rad/s], e.g. from an earlier static bias test.
    Fixed(f64),
    /// The mean reading over the rest window `start <= t <= end` [s, same clock as the samples].
    Window {
        /// Window start \[s\].
        start: f64,
        /// Window end \[s\].
        end: f64,
    },
    /// The mean reading over the first `duration` seconds of the stream (`T_bias`, HDR section 2).
    Leading {
        /// Averaging time `T_bias` \[s\].
        duration: f64,
    },
}

impl Default for StaticBias {
    fn default() -> Self {
        StaticBias::Fixed(0.0)
    }
}

/// Temperature-linear scale factor (FOG eq 5-6), written per turn fraction:
/// the turn error is `e(T) = slope * T + offset` (FOG's `E_T / 360 deg`), and the correction factor
/// is `C_T = 1 / |1 + e(T)|` (FOG eq 6). The paper's fit `E_T = -0.52 T + 19.23` deg is
/// `slope = -0.52/360` per deg C, `offset = 19.23/360`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TemperatureScale {
    /// Change of the turn error per degree Celsius [1/degC].
    pub slope: f64,
    /// Turn error at 0 degC \[dimensionless\].
    pub offset: f64,
}

impl TemperatureScale {
    /// Correction factor `C_T` at temperature `celsius` (FOG eq 6).
    #[inline]
    pub fn factor(&self, celsius: f64) -> f64 {
        1.0 / libm::fabs(1.0 + self.slope * celsius + self.offset)
    }
}

/// Configuration of the [`Correction`] stage. Identity by default.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CorrectionConfig {
    /// Static bias `eps0` (HDR eq 2) or how to measure it.
    pub bias: StaticBias,
    /// Calibration scale `s_bar = 1/(1+s)` of Hong eq 3 \[dimensionless\].
    pub scale: f64,
    /// Calibration offset `b_bar = -b/(1+s)` of Hong eq 3 [rad/s].
    pub offset: f64,
    /// Correction factor for clockwise (negative) rates, `C_cw` of FOG eq 2a \[dimensionless\].
    pub c_cw: f64,
    /// Correction factor for counter-clockwise (positive) rates, `C_ccw` of FOG eq 2b.
    pub c_ccw: f64,
    /// Temperature-linear scale factor (FOG eq 5-6); needs a temperature per sample.
    pub temperature: Option<TemperatureScale>,
}

impl Default for CorrectionConfig {
    fn default() -> Self {
        CorrectionConfig {
            bias: StaticBias::default(),
            scale: 1.0,
            offset: 0.0,
            c_cw: 1.0,
            c_ccw: 1.0,
            temperature: None,
        }
    }
}

impl CorrectionConfig {
    /// Checks every field; the error names the first invalid one.
    pub fn validate(&self) -> Result<(), Error> {
        match self.bias {
            StaticBias::Fixed(b) => check_finite("bias", b)?,
            StaticBias::Window { start, end } => {
                check_finite("bias_window.start", start)?;
                check_finite("bias_window.end", end)?;
                check_range(
                    "bias_window.end",
                    end,
                    start,
                    f64::INFINITY,
                    "finite and >= start",
                )?;
            }
            StaticBias::Leading { duration } => check_positive("bias_duration", duration)?,
        }
        check_positive("scale", self.scale)?;
        check_finite("offset", self.offset)?;
        check_positive("c_cw", self.c_cw)?;
        check_positive("c_ccw", self.c_ccw)?;
        if let Some(m) = self.temperature {
            check_finite("temperature.slope", m.slope)?;
            check_finite("temperature.offset", m.offset)?;
        }
        Ok(())
    }
}

/// Time-weighted mean of the readings inside the rest window (the static bias test).
///
/// Each reading stands for the interval since the previous one (the rectangle rule of HDR eq 3),
/// so an irregular logger's bursts do not outweigh its pauses, and a record averaged to a lower
/// rate (second eq 14) gives the same bias. The first reading in the window has no interval
/// inside it: it is the estimate until the second arrives, then carries no weight.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct BiasEstimate {
    /// The bias in use now [rad/s].
    value: f64,
    /// Integral of the readings over the window so far [rad].
    integral: f64,
    /// Time covered so far [s].
    duration: f64,
    count: u64,
    /// `(start, end)` once known; `None` for a leading window before the first sample.
    window: Option<(f64, f64)>,
    /// False once the stream has passed the window's end: the bias is frozen.
    learning: bool,
    /// The window's noise, for [`Correction::rest_statistics`].
    noise: RestNoise,
    clock: Clock,
}

impl BiasEstimate {
    fn new(source: StaticBias) -> Self {
        let (value, window, learning) = match source {
            StaticBias::Fixed(b) => (b, None, false),
            StaticBias::Window { start, end } => (0.0, Some((start, end)), true),
            StaticBias::Leading { .. } => (0.0, None, true),
        };
        BiasEstimate {
            value,
            integral: 0.0,
            duration: 0.0,
            count: 0,
            window,
            learning,
            noise: RestNoise::default(),
            clock: Clock::default(),
        }
    }

    /// Takes the reading into the mean while `t` is inside the window (HDR eq 2's `eps0`).
    ///
    /// Out of line: it runs only during the rest window, and inlined into the pipeline's loop it
    /// slows every later sample by about a fifth (`benches/pipeline.rs`).
    #[inline(never)]
    fn learn(&mut self, source: StaticBias, t: f64, rate: f64) {
        let dt = self.clock.tick(t);
        let (start, end) = match (self.window, source) {
            (Some(w), _) => w,
            (None, StaticBias::Leading { duration }) => {
                let w = (t, t + duration);
                self.window = Some(w);
                w
            }
            _ => return,
        };
        if t > end {
            self.learning = false;
        } else if t >= start {
            if self.count > 0 {
                self.integral += rate * dt;
                self.duration += dt;
            }
            let length = end - start;
            let position = if length > 0.0 {
                (t - start) / length
            } else {
                1.0
            };
            self.noise.push(position, dt, rate);
            self.count += 1;
            self.value = if self.duration > 0.0 {
                self.integral / self.duration
            } else {
                rate
            };
        }
    }
}

/// Corrects raw readings for bias, scale and direction (see the module doc for the order).
///
/// While a rest window is being measured, the running mean so far is used as the bias, so the
/// stage is causal and streams; after the window the bias is frozen.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Correction {
    config: CorrectionConfig,
    bias: BiasEstimate,
}

impl Correction {
    /// Validates `config` and builds the stage.
    pub fn new(config: CorrectionConfig) -> Result<Self, Error> {
        config.validate()?;
        Ok(Correction {
            config,
            bias: BiasEstimate::new(config.bias),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &CorrectionConfig {
        &self.config
    }

    /// The static bias in use now [rad/s] (what the gyro reads at rest).
    pub fn bias(&self) -> f64 {
        self.bias.value
    }

    /// How many readings the measured bias averages (0 for a fixed bias).
    pub fn bias_sample_count(&self) -> u64 {
        self.bias.count
    }

    /// True while the rest window is still being measured.
    pub fn bias_learning(&self) -> bool {
        self.bias.learning
    }

    /// The rest window's noise and the standard error of the bias measured in it, once the
    /// window is over; `None` for a fixed bias, while measuring, or from fewer than two readings
    /// in two parts of the window.
    pub fn rest_statistics(&self) -> Option<RestStatistics> {
        if self.bias.learning || self.bias.window.is_none() {
            return None;
        }
        self.bias.noise.statistics()
    }

    /// Corrects one reading; `temperature` \[degC\] feeds the temperature model when configured.
    ///
    /// `r = (s_bar * (r_m - eps0) + b_bar) * C_dir * C_T` (HDR eq 2, Hong eq 3, FOG eq 3-4 and 6).
    #[inline]
    pub fn apply(&mut self, t: f64, rate: f64, temperature: Option<f64>) -> f64 {
        self.apply_directed::<true>(t, rate, temperature)
    }

    /// True if clockwise and counter-clockwise rates take different factors (FOG eq 3-4).
    pub(crate) fn direction_split(&self) -> bool {
        self.config.c_cw != self.config.c_ccw
    }

    /// [`Correction::apply`], compiled for a single direction factor unless `SPLIT`; without
    /// `SPLIT` the factors must be equal (not [`Correction::direction_split`]).
    ///
    /// Choosing the factor by the sign of the rate puts a load that waits for the rate on every
    /// sample's path; with one factor for both directions (the default: no FOG correction) the
    /// `combined` pipeline took 4.48 instead of 4.82 ns/sample (`benches/pipeline.rs`).
    #[inline(always)]
    pub(crate) fn apply_directed<const SPLIT: bool>(
        &mut self,
        t: f64,
        rate: f64,
        temperature: Option<f64>,
    ) -> f64 {
        if self.bias.learning {
            self.bias.learn(self.config.bias, t, rate);
        }
        self.settled::<SPLIT>(rate, temperature)
    }

    /// [`Correction::apply_directed`] once the bias is known (not [`Correction::bias_learning`]).
    #[inline(always)]
    pub(crate) fn settled<const SPLIT: bool>(&self, rate: f64, temperature: Option<f64>) -> f64 {
        let c = &self.config;
        let r = c.scale * (rate - self.bias.value) + c.offset;
        // Counter-clockwise is positive (REP-103), so negative rates are clockwise turns.
        let r = r * if SPLIT && r < 0.0 { c.c_cw } else { c.c_ccw };
        match (c.temperature, temperature) {
            (Some(model), Some(celsius)) => r * model.factor(celsius),
            _ => r,
        }
    }
}

impl Stage for Correction {
    type Output = f64;

    /// Corrects one reading without a temperature (the temperature model, if any, is skipped).
    #[inline]
    fn update(&mut self, t: f64, rate: f64) -> f64 {
        self.apply(t, rate, None)
    }

    fn reset(&mut self) {
        self.bias = BiasEstimate::new(self.config.bias);
    }
}
