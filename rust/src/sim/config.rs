//! The simulated gyro's configuration ([`GyroModelConfig`], Hong eq 1 and 10-11 with the Allan
//! noise terms) and its temperature profile.

use super::{FLICKER_TERMS_PER_DECADE, MAX_DROP_PROBABILITY, MAX_FLICKER_TERMS};
use crate::error::{check_duration, check_magnitude, check_positive, check_range};
use crate::{Error, MAX_READING};

/// Sensor temperature over time: an exponential approach from `start` to `end`, as after power-up
/// (FOG Figure 2) or when a car's cabin warms up (HDR section 5.2). Constant when `start == end`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TemperatureProfile {
    /// Temperature at the first sample \[degC\].
    pub start: f64,
    /// Temperature reached in the end \[degC\].
    pub end: f64,
    /// Time constant of the approach \[s\], > 0.
    pub time_constant: f64,
}

impl TemperatureProfile {
    /// A constant temperature \[degC\].
    pub fn constant(celsius: f64) -> Self {
        TemperatureProfile {
            start: celsius,
            end: celsius,
            time_constant: 1.0,
        }
    }

    /// The temperature `elapsed` seconds after the first sample \[degC\] (`start` before it:
    /// the approach begins at the first sample, and `exp` of a large positive power overflows).
    #[inline]
    pub fn at(&self, elapsed: f64) -> f64 {
        self.end + (self.start - self.end) * libm::exp(-elapsed.max(0.0) / self.time_constant)
    }
}

/// Configuration of [`GyroModel`](super::GyroModel); SI units (s, rad/s, degC).
/// [`GyroModelConfig::ideal`] is a perfect gyro to start from.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GyroModelConfig {
    /// Output data rate \[Hz\], > 0: the nominal sampling grid, and the bandwidth of the white noise.
    pub rate_hz: f64,
    /// Standard deviation of each sampling instant about the nominal grid \[s\], in
    /// `[0, 0.25 / rate_hz]`; deviations are clipped to 0.45 of a period so instants keep their order.
    pub jitter: f64,
    /// Probability that a sample is lost before it reaches the log, in `[0, 0.99]`.
    pub drop_probability: f64,
    /// Scale error `s` of Hong eq 1 at the reference temperature \[1\], > -1 (e.g. -0.1 reads 10 % low).
    pub scale_error: f64,
    /// Scale error of counter-clockwise minus that of clockwise rates \[1\] (FOG's cw/ccw factors).
    pub scale_asymmetry: f64,
    /// Change of the scale error per degree [1/degC] (FOG eq 5 divided by 360 deg).
    pub scale_temperature: f64,
    /// Bias `b` of Hong eq 1 at the reference temperature [rad/s] (what the gyro reads at rest).
    pub bias: f64,
    /// Change of the bias per degree [rad/s/degC] (FOG Figure 2, Hong Figure 4).
    pub bias_temperature: f64,
    /// Angle random walk `N` [rad/sqrt(s)], >= 0: white rate noise with Allan deviation `N / sqrt(tau)`.
    pub arw: f64,
    /// Corner frequency of the sensor's first-order low-pass on the white noise \[Hz\], > 0
    /// (infinity: none).
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_float"))]
    pub bandwidth: f64,
    /// Bias instability `B` [rad/s], >= 0: flicker noise whose Allan deviation is flat at
    /// `sqrt(2 ln 2 / pi) B = 0.664 B` between the correlation times below.
    pub bias_instability: f64,
    /// Shortest correlation time of the flicker approximation \[s\], > 0.
    pub flicker_min: f64,
    /// Longest correlation time of the flicker approximation \[s\], >= `flicker_min`, at most seven
    /// decades above it.
    pub flicker_max: f64,
    /// Rate random walk `K` [rad/s/sqrt(s)], >= 0: the bias random walk of Hong eq 11, with Allan
    /// deviation `K sqrt(tau / 3)`.
    pub rrw: f64,
    /// Grid on which the slow bias is generated and between which it is interpolated \[s\], > 0 and at
    /// most `flicker_min` (when there is flicker noise).
    pub drift_step: f64,
    /// Sensor temperature over time.
    pub temperature: TemperatureProfile,
    /// Temperature at which `scale_error` and `bias` hold \[degC\].
    pub reference_temperature: f64,
    /// Resolution (one least significant bit) [rad/s], >= 0 (0: no quantisation).
    pub resolution: f64,
    /// Measurement range: readings are clipped to `[-range, range]` [rad/s], > 0 (infinity: none).
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_float"))]
    pub range: f64,
}

impl GyroModelConfig {
    /// A perfect gyro sampled at `rate_hz`: every error term zero, constant 25 degC.
    pub fn ideal(rate_hz: f64) -> Self {
        GyroModelConfig {
            rate_hz,
            jitter: 0.0,
            drop_probability: 0.0,
            scale_error: 0.0,
            scale_asymmetry: 0.0,
            scale_temperature: 0.0,
            bias: 0.0,
            bias_temperature: 0.0,
            arw: 0.0,
            bandwidth: f64::INFINITY,
            bias_instability: 0.0,
            flicker_min: 1.0,
            flicker_max: 1.0e4,
            rrw: 0.0,
            drift_step: 0.1,
            temperature: TemperatureProfile::constant(25.0),
            reference_temperature: 25.0,
            resolution: 0.0,
            range: f64::INFINITY,
        }
    }

    /// Checks every field; the error names the first invalid one.
    pub fn validate(&self) -> Result<(), Error> {
        check_range("rate_hz", self.rate_hz, 1e-6, 1e9, "in [1e-6, 1e9] Hz")?;
        check_range(
            "jitter",
            self.jitter,
            0.0,
            0.25 / self.rate_hz,
            "in [0, 0.25 / rate_hz] s",
        )?;
        check_range(
            "drop_probability",
            self.drop_probability,
            0.0,
            MAX_DROP_PROBABILITY,
            "in [0, 0.99] (a logger that loses more keeps next to nothing)",
        )?;
        check_range(
            "scale_error",
            self.scale_error,
            -1.0 + f64::EPSILON,
            MAX_READING,
            "> -1 and at most 2^20",
        )?;
        let t = self.temperature;
        for (name, value) in [
            ("scale_asymmetry", self.scale_asymmetry),
            ("scale_temperature", self.scale_temperature),
            ("bias", self.bias),
            ("bias_temperature", self.bias_temperature),
            ("temperature.start", t.start),
            ("temperature.end", t.end),
            ("reference_temperature", self.reference_temperature),
        ] {
            check_range(name, value, -MAX_READING, MAX_READING, "within +-2^20")?;
        }
        for (name, value) in [
            ("arw", self.arw),
            ("bias_instability", self.bias_instability),
            ("rrw", self.rrw),
            ("resolution", self.resolution),
        ] {
            // at most 2^20, as a reading: a reading made of them stays finite
            check_magnitude(name, value)?;
        }
        check_range(
            "bandwidth",
            self.bandwidth,
            f64::MIN_POSITIVE,
            f64::INFINITY,
            "> 0 (infinity: no filter)",
        )?;
        check_duration("flicker_min", self.flicker_min)?;
        check_range(
            "flicker_max",
            self.flicker_max,
            self.flicker_min,
            self.flicker_min * 1.0e7,
            "between flicker_min and 1e7 times flicker_min",
        )?;
        check_duration("drift_step", self.drift_step)?;
        if self.bias_instability > 0.0 {
            check_range(
                "drift_step",
                self.drift_step,
                0.0,
                self.flicker_min,
                "at most flicker_min (the grid must resolve the fastest flicker term)",
            )?;
        }
        check_positive("temperature.time_constant", t.time_constant)?;
        check_range(
            "gain",
            self.lowest_gain(),
            f64::MIN_POSITIVE,
            f64::INFINITY,
            "> 0 at every temperature of the profile and for both turn directions: 1 + \
             scale_error + scale_temperature (T - reference_temperature) +- scale_asymmetry / 2 \
             (a gain of 0 or less reads no turn, or every turn backwards)",
        )?;
        check_range(
            "range",
            self.range,
            f64::MIN_POSITIVE,
            f64::INFINITY,
            "> 0 (infinity: no clipping)",
        )
    }

    /// The lowest gain `1 + s` of the model's scale error `s` (the module doc of
    /// [`crate::sim`]): `s` is affine in the temperature, which moves monotonically from the
    /// profile's start to its end, so its extremes are there, each with the asymmetry's half of
    /// either sign.
    fn lowest_gain(&self) -> f64 {
        let t = self.temperature;
        let at_ends = [t.start, t.end]
            .map(|celsius| self.scale_temperature * (celsius - self.reference_temperature));
        1.0 + self.scale_error + at_ends[0].min(at_ends[1]) - 0.5 * self.scale_asymmetry.abs()
    }

    /// Number of Gauss-Markov terms of the flicker approximation (0 without bias instability).
    pub fn flicker_terms(&self) -> usize {
        if self.bias_instability <= 0.0 {
            return 0;
        }
        let decades = libm::log10(self.flicker_max / self.flicker_min);
        // Saturating: a config not validated may span infinitely many decades (1e-300 to 1e308
        // s), whose count converts to usize::MAX.
        let n = libm::ceil(decades * FLICKER_TERMS_PER_DECADE - 1e-9).max(0.0) as usize;
        n.saturating_add(1).min(MAX_FLICKER_TERMS)
    }

    /// Correlation time \[s\] and standard deviation [rad/s] of flicker term `k` (`k <` [`Self::flicker_terms`]).
    ///
    /// The correlation times are spaced evenly in logarithm, `Delta = ln(max/min) / (n - 1)` apart
    /// (one term at `flicker_min` when the band is a single time). A Gauss-Markov process of
    /// variance `q^2` and correlation time `T` has the two-sided spectrum `2 q^2 T / (1 + (2 pi f T)^2)`;
    /// summed over terms `Delta` apart in `ln T`, the spectrum is `q^2 / (2 Delta f)` between the
    /// band's corners. Flicker noise of bias instability `B` has `B^2 / (2 pi f)` (IEEE Std 952,
    /// Annex C), so `q^2 = B^2 Delta / pi`. A single term gets the weight of two terms per decade.
    pub fn flicker_term(&self, k: usize) -> (f64, f64) {
        let n = self.flicker_terms();
        let ratio = self.flicker_max / self.flicker_min;
        let (correlation, delta) = if n > 1 {
            let delta = libm::log(ratio) / (n - 1) as f64;
            (self.flicker_min * libm::exp(delta * k as f64), delta)
        } else {
            (
                self.flicker_min,
                core::f64::consts::LN_10 / FLICKER_TERMS_PER_DECADE,
            )
        };
        let sd = self.bias_instability * libm::sqrt(delta / core::f64::consts::PI);
        (correlation, sd)
    }

    /// Closed-form Allan variance of the noise terms at averaging time `tau` \[s\] [(rad/s)^2]:
    /// the sum of the angle random walk's (`N^2 / tau` through the noise's low-pass:
    /// [`Self::white_allan_variance`]), the Gauss-Markov terms' and the rate random walk's,
    /// `K^2 tau / 3` (IEEE Std 952, Annex C). A Gauss-Markov process of variance `q^2` and
    /// correlation time `T` contributes `q^2 (T / tau)^2 (2 tau/T - 3 + 4 e^(-tau/T) - e^(-2 tau/T))`.
    /// Quantisation, temperature and the interpolation between drift-grid points are not included.
    pub fn allan_variance(&self, tau: f64) -> f64 {
        let mut avar = self.white_allan_variance(tau) + self.rrw * self.rrw * tau / 3.0;
        for k in 0..self.flicker_terms() {
            let (correlation, sd) = self.flicker_term(k);
            let x = tau / correlation;
            let shape = if x < 1e-4 {
                // The bracket cancels to 2x^3/3 - x^4/2 + ...; evaluate the series to avoid rounding.
                x * x * x * (2.0 / 3.0 - x / 2.0)
            } else {
                2.0 * x - 3.0 + 4.0 * libm::exp(-x) - libm::exp(-2.0 * x)
            };
            avar += sd * sd * shape / (x * x);
        }
        avar
    }

    /// `c` of the white noise's low-pass pole `a = e^-c` per sample: `c = 2 pi bandwidth / rate_hz`
    /// (infinite without a low-pass: `a = 0`), one value for the model's filter and its closed-form
    /// Allan variance.
    pub(crate) fn noise_pole_decay(&self) -> f64 {
        core::f64::consts::TAU * self.bandwidth / self.rate_hz
    }

    /// Allan variance of the white noise at `tau` \[s\] [(rad/s)^2]: `N^2 / tau` without a low-pass;
    /// through the sensor's (`y_k = a y_(k-1) + (1 - a) x_k`, `a = exp(-2 pi bandwidth / rate_hz)`),
    /// over `m = tau rate_hz` samples,
    /// `N^2 / tau (1 - a (1 - a^m) (3 - a^m) / (m (1 - a^2)))`: from the autocovariance
    /// `var a^|k|`, the variance of an `m`-sample mean less the covariance of two consecutive ones.
    /// `N^2 / tau` alone overstated the XV3500's Allan deviation at `tau` = 1 sample by 1.6 times;
    /// it holds far above `1 / bandwidth`.
    pub fn white_allan_variance(&self, tau: f64) -> f64 {
        let white = self.arw * self.arw / tau;
        let c = self.noise_pole_decay();
        let m = tau * self.rate_hz;
        let a = libm::exp(-c);
        let am = libm::exp(-m * c);
        // 1 - a^m and 1 - a^2 by expm1: a pole near 1 (a narrow band) loses them to rounding otherwise
        let removed = a * -libm::expm1(-m * c) * (3.0 - am) / (m * -libm::expm1(-2.0 * c));
        (white * (1.0 - removed)).max(0.0)
    }
}
