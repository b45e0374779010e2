//! Sensor-error correction: static bias (HDR eq 2), linear calibration (Hong eq 3),
//! direction-dependent scale factors (FOG eq 2-4) and a temperature-linear scale factor (FOG eq 5-6).
//!
//! Order, as the papers apply them: the static bias measured at rest is subtracted first
//! (`r_m - eps0`), the linear calibration `s_bar * (.) + b_bar` follows, and the scale factors
//! multiply the result. The bias is what the gyro reads at rest (corrected = measured - bias).

use crate::error::{check_duration, check_factor, check_range, check_reading};
use crate::kernel::{Kernel, Measured, Signal};
use crate::rest::{BiasEstimate, RestStatistics};
use crate::stage::{Clock, Stage};
use crate::{Error, MAX_READING, MAX_TIME};

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
    /// Correction factor `C_T` at temperature `celsius` (FOG eq 6), at most
    /// [`MAX_READING`]: where the model's turn error reaches -100 % (a zero
    /// denominator) no factor is right, and a bounded one keeps the heading finite. NaN for a
    /// NaN temperature (none measured).
    #[inline]
    pub fn factor(&self, celsius: f64) -> f64 {
        let denominator = libm::fabs(1.0 + self.slope * celsius + self.offset);
        if denominator.is_nan() {
            // A missing temperature: fmax would take the bound for it, a factor of 2^20.
            return f64::NAN;
        }
        1.0 / libm::fmax(denominator, 1.0 / MAX_READING)
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
            StaticBias::Fixed(b) => check_reading("bias", b)?,
            StaticBias::Window { start, end } => {
                // No timestamp lies beyond +-2^40 s: a window past it was measured for ever, the
                // whole drive averaged into the "static" bias (a window in ns, read as s).
                let valid = "within +-2^40 s, the limit of a timestamp (epoch nanoseconds read as seconds lie beyond it)";
                check_range("bias_window.start", start, -MAX_TIME, MAX_TIME, valid)?;
                check_range("bias_window.end", end, -MAX_TIME, MAX_TIME, valid)?;
                check_range(
                    "bias_window.end",
                    end,
                    start,
                    f64::INFINITY,
                    "finite and >= start",
                )?;
            }
            StaticBias::Leading { duration } => check_duration("bias_duration", duration)?,
        }
        check_factor("scale", self.scale)?;
        check_reading("offset", self.offset)?;
        check_factor("c_cw", self.c_cw)?;
        check_factor("c_ccw", self.c_ccw)?;
        if let Some(m) = self.temperature {
            check_reading("temperature.slope", m.slope)?;
            check_reading("temperature.offset", m.offset)?;
        }
        Ok(())
    }
}

/// The correction as the kernels read it: the settings with the bias in force [rad/s].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Calibration {
    /// The static bias in use [rad/s]: fixed, or measured in the rest window so far.
    pub bias: f64,
    /// The settings.
    pub config: CorrectionConfig,
}

impl Calibration {
    /// The settings with the bias they start with (0 until a rest window is measured).
    pub(crate) fn new(config: CorrectionConfig) -> Self {
        let bias = match config.bias {
            StaticBias::Fixed(b) => b,
            _ => 0.0,
        };
        Calibration { bias, config }
    }

    /// `s_bar * (r_m - eps0) + b_bar` (HDR eq 2, Hong eq 3).
    #[inline(always)]
    fn linear(&self, rate: f64) -> f64 {
        self.config.scale * (rate - self.bias) + self.config.offset
    }
}

/// Implements [`Kernel`] for a correction: `$correct` (of the calibration `$c` and the signal
/// `$x`) gives the corrected rate; the pipeline hands it the bias as it is measured.
macro_rules! correction_kernel {
    ($ty:ty, |$c:ident, $x:ident| $correct:expr) => {
        impl Kernel for $ty {
            type Config = Calibration;
            type State = ();

            fn start(_config: &Calibration) {}

            #[inline(always)]
            fn first(config: &Calibration, state: &mut (), x: Signal) -> Signal {
                Self::step(config, state, 0.0, x)
            }

            #[inline(always)]
            fn step($c: &Calibration, _state: &mut (), _dt: f64, $x: Signal) -> Signal {
                let r = $correct;
                Signal {
                    rate: r,
                    corrected: r,
                    ..$x
                }
            }

            fn measured(config: &mut Calibration, _state: &mut (), m: &Measured) {
                if let Some(bias) = m.bias {
                    config.bias = bias;
                }
            }

            fn in_force(config: &Calibration) -> Measured {
                Measured {
                    bias: Some(config.bias),
                    ..Measured::default()
                }
            }
        }
    };
}

/// The whole correction (see the module doc): `r = (s_bar (r_m - eps0) + b_bar) C_dir C_T`
/// (HDR eq 2, Hong eq 3, FOG eq 3-4 and 6), the factors chosen per sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CorrectionKernel;

correction_kernel!(CorrectionKernel, |c, x| {
    let r = c.linear(x.rate);
    // Counter-clockwise is positive (REP-103), so negative rates are clockwise turns.
    let r = r * if r < 0.0 {
        c.config.c_cw
    } else {
        c.config.c_ccw
    };
    match c.config.temperature {
        Some(model) => r * model.factor(x.temperature),
        None => r,
    }
});

/// The correction with one factor for both directions and no temperature model (the common
/// case), composed when that is known: choosing the factor by the sign of the rate puts a
/// load that waits for the rate on every sample's path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SingleFactorKernel;

correction_kernel!(SingleFactorKernel, |c, x| c.linear(x.rate) * c.config.c_ccw);

/// Corrects raw readings for bias, scale and direction (see the module doc for the order), as a
/// stand-alone stage.
///
/// While a rest window is being measured, the running mean so far is used as the bias, so the
/// stage is causal and streams; after the window the bias is frozen.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(remote = "Self")
)]
pub struct Correction {
    calibration: Calibration,
    bias: BiasEstimate,
    clock: Clock,
}

impl Correction {
    /// Validates `config` and builds the stage.
    pub fn new(config: CorrectionConfig) -> Result<Self, Error> {
        config.validate()?;
        Ok(Correction {
            calibration: Calibration::new(config),
            bias: BiasEstimate::new(config.bias),
            clock: Clock::default(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &CorrectionConfig {
        &self.calibration.config
    }

    /// The checks of a stage read back (`serde` feature): its configuration, its bias estimate
    /// as a pipeline's, the bias in force (a reading, as a pipeline's: one of 1e308 gave
    /// infinite corrected rates) and its clock within +-2^40 s.
    #[cfg(feature = "serde")]
    pub(crate) fn check_restored(&self) -> Result<(), Error> {
        self.config().validate()?;
        self.bias
            .check(self.calibration.config.bias, self.clock.last(), false)?;
        check_reading("bias", self.calibration.bias)?;
        // The bias corrected with is the estimate's: a copy of it that differed ran unseen.
        if self.calibration.bias != self.bias.value() {
            let valid = "the bias measured or configured (the static bias test's)";
            return Err(Error::InvalidParameter {
                name: "calibration bias",
                value: self.calibration.bias,
                valid,
            });
        }
        self.clock.check_restored()
    }

    /// The static bias in use now [rad/s] (what the gyro reads at rest).
    pub fn bias(&self) -> f64 {
        self.bias.value()
    }

    /// How many readings the measured bias averages (0 for a fixed bias).
    pub fn bias_sample_count(&self) -> u64 {
        self.bias.count()
    }

    /// True while the rest window is still being measured.
    pub fn bias_learning(&self) -> bool {
        self.bias.learning()
    }

    /// The rest window's noise and the standard error of the bias measured in it, once the
    /// window is over; `None` for a fixed bias, while measuring, or from fewer than two readings
    /// in two parts of the window.
    pub fn rest_statistics(&self) -> Option<RestStatistics> {
        self.bias.rest_statistics()
    }

    /// Corrects one reading; `temperature` \[degC\] feeds the temperature model when configured
    /// (without it, such a model gives NaN: the reading cannot be corrected).
    ///
    /// `r = (s_bar * (r_m - eps0) + b_bar) * C_dir * C_T` (HDR eq 2, Hong eq 3, FOG eq 3-4 and 6).
    #[inline]
    pub fn apply(&mut self, t: f64, rate: f64, temperature: Option<f64>) -> f64 {
        // A time the clock refuses, or a reading beyond the limits, is corrected as any other but
        // left out of the bias, as if absent (the next interval spans it): a NaN first time made
        // the window (NaN, NaN), never learned, and one NaN reading in it made every output NaN.
        let usable = |clock: &Clock| libm::fabs(rate) < MAX_READING && clock.interval(t).is_some();
        if self.bias.learning() && usable(&self.clock) {
            let dt = self.clock.tick(t);
            self.bias.learn(self.calibration.config.bias, t, dt, rate);
            self.calibration.bias = self.bias.value();
        }
        let x = Signal::reading(rate, temperature.unwrap_or(f64::NAN));
        CorrectionKernel::step(&self.calibration, &mut (), 0.0, x).rate
    }
}

impl Stage for Correction {
    type Output = f64;

    /// Corrects one reading without a temperature (see [`Correction::apply`]).
    #[inline]
    fn update(&mut self, t: f64, rate: f64) -> f64 {
        self.apply(t, rate, None)
    }

    fn reset(&mut self) {
        self.bias = BiasEstimate::new(self.calibration.config.bias);
        self.calibration = Calibration::new(self.calibration.config);
        self.clock = Clock::default();
    }
}
