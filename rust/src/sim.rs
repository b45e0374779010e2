//! A simulated yaw-rate gyro: the error model of Hong & Park with the noise terms of an Allan
//! analysis, for reproducing the papers' experiments and testing every method where the truth is
//! known exactly.
//!
//! The reading is `r_m = (1 + s) r + b + d + w` (Hong eq 1, with the residual `d` of Hong eq 10):
//!
//! - `s`: scale error, `scale_error + scale_temperature (T - T_ref)`, plus half the cw/ccw
//!   asymmetry for counter-clockwise (positive) rates and minus half for clockwise ones;
//! - `b`: bias, `bias + bias_temperature (T - T_ref)` (the bias is what the gyro reads at rest);
//! - `d`: slow stochastic bias: bias instability (flicker noise, approximated by a sum of
//!   first-order Gauss-Markov processes whose correlation times span the configured decades) and
//!   rate random walk (Hong eq 11, `d' = n`);
//! - `w`: white rate noise, the angle random walk, with standard deviation `N sqrt(rate_hz)`,
//!   passed through the sensor's first-order low-pass of `bandwidth` Hz. The filter keeps the
//!   density `N` below its corner, so the Allan deviation above `1 / bandwidth` is unchanged, and
//!   makes consecutive samples correlated when the rate exceeds the bandwidth. The rate signal
//!   itself is taken to lie inside the bandwidth and is not filtered.
//!
//! The reading is then clipped to the measurement range and rounded to the resolution.
//!
//! **Continuous time.** The slow terms (`d`, and the temperature `T(t)`) are functions of time
//! fixed by the seed, not of the samples: `d` is generated on its own grid of `drift_step` seconds
//! from the first sample and interpolated linearly in between, so the same drive sampled at 10 Hz
//! or at 100 Hz sees the same drift. Only the white noise depends on the sampling, as it does for a
//! real gyro.
//!
//! **Sampling.** [`GyroModel::sampler`] gives the instants at which a logger receives samples:
//! the nominal grid of `rate_hz`, each instant (after the first) moved by a Gaussian jitter,
//! and samples dropped at random. The timestamps are the true instants of the samples.
//!
//! Random numbers come from xoshiro256++ seeded through SplitMix64, with one independent stream
//! per purpose (slow drift, white noise, sampling), and Gaussian deviates from the Box-Muller
//! transform; no allocation, no `std`.

use crate::error::{check_finite, check_positive, check_range};
use crate::stage::Stage;
use crate::Error;

/// Most first-order Gauss-Markov terms the flicker approximation may use.
pub const MAX_FLICKER_TERMS: usize = 16;

/// Gauss-Markov terms per decade of correlation time in the flicker approximation. Two per decade
/// keep the flat part of the Allan deviation within about 3 % of `0.664 B` (tested).
const FLICKER_TERMS_PER_DECADE: f64 = 2.0;

/// Stream numbers: each purpose draws from its own generator, so that changing how many samples are
/// taken (the rate, the drops) does not change the drift.
const STREAM_DRIFT: u64 = 1;
const STREAM_NOISE: u64 = 2;
const STREAM_SAMPLING: u64 = 3;

/// SplitMix64 (Steele, Lea & Flood 2014): a 64-bit generator used to seed [`Xoshiro256PlusPlus`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// The generator whose state starts at `seed`.
    pub fn new(seed: u64) -> Self {
        SplitMix64 { state: seed }
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

/// xoshiro256++ (Blackman & Vigna 2019): fast, 256 bits of state, passes BigCrush.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Xoshiro256PlusPlus {
    s: [u64; 4],
}

impl Xoshiro256PlusPlus {
    /// The generator with the given raw state (which must not be all zero).
    pub fn from_state(s: [u64; 4]) -> Self {
        Xoshiro256PlusPlus { s }
    }

    /// Stream `stream` of `seed`: the state is four SplitMix64 outputs of a seed that mixes both,
    /// so different streams of one seed are unrelated (and never all zero).
    pub fn from_seed(seed: u64, stream: u64) -> Self {
        let mut mix = SplitMix64::new(seed ^ stream.wrapping_mul(0xD1B5_4A32_D192_ED03));
        // One extra round so that seeds differing in a few bits start far apart.
        let mut sm = SplitMix64::new(mix.next_u64());
        Xoshiro256PlusPlus {
            s: [sm.next_u64(), sm.next_u64(), sm.next_u64(), sm.next_u64()],
        }
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        let s = &mut self.s;
        let result = s[0].wrapping_add(s[3]).rotate_left(23).wrapping_add(s[0]);
        let t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = s[3].rotate_left(45);
        result
    }

    /// A uniform deviate in `[0, 1)` with 53 random bits.
    #[inline]
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// Standard normal deviates by the Box-Muller transform; the second deviate of each pair is kept
/// for the next call.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Gaussian {
    rng: Xoshiro256PlusPlus,
    spare: Option<f64>,
}

impl Gaussian {
    /// Standard normal deviates from stream `stream` of `seed`.
    pub fn new(seed: u64, stream: u64) -> Self {
        Gaussian {
            rng: Xoshiro256PlusPlus::from_seed(seed, stream),
            spare: None,
        }
    }

    /// The next deviate (mean 0, variance 1).
    #[inline]
    pub fn sample(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        // 1 - u lies in (0, 1], so the logarithm is finite.
        let radius = libm::sqrt(-2.0 * libm::log(1.0 - self.rng.uniform()));
        let angle = core::f64::consts::TAU * self.rng.uniform();
        self.spare = Some(radius * libm::sin(angle));
        radius * libm::cos(angle)
    }

    /// A uniform deviate in `[0, 1)` from the same stream.
    #[inline]
    pub fn uniform(&mut self) -> f64 {
        self.rng.uniform()
    }
}

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

    /// The temperature `elapsed` seconds after the first sample \[degC\].
    #[inline]
    pub fn at(&self, elapsed: f64) -> f64 {
        self.end + (self.start - self.end) * libm::exp(-elapsed / self.time_constant)
    }
}

/// Configuration of [`GyroModel`]; SI units (s, rad/s, degC). [`GyroModelConfig::ideal`] is a
/// perfect gyro to start from.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GyroModelConfig {
    /// Output data rate \[Hz\], > 0: the nominal sampling grid, and the bandwidth of the white noise.
    pub rate_hz: f64,
    /// Standard deviation of each sampling instant about the nominal grid \[s\], in
    /// `[0, 0.25 / rate_hz]`; deviations are clipped to 0.45 of a period so instants keep their order.
    pub jitter: f64,
    /// Probability that a sample is lost before it reaches the log, in `[0, 1)`.
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
        check_positive("rate_hz", self.rate_hz)?;
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
            1.0 - f64::EPSILON,
            "in [0, 1)",
        )?;
        check_range(
            "scale_error",
            self.scale_error,
            -1.0 + f64::EPSILON,
            f64::MAX,
            "finite and > -1",
        )?;
        check_finite("scale_asymmetry", self.scale_asymmetry)?;
        check_finite("scale_temperature", self.scale_temperature)?;
        check_finite("bias", self.bias)?;
        check_finite("bias_temperature", self.bias_temperature)?;
        for (name, value) in [
            ("arw", self.arw),
            ("bias_instability", self.bias_instability),
            ("rrw", self.rrw),
            ("resolution", self.resolution),
        ] {
            check_range(name, value, 0.0, f64::MAX, "finite and >= 0")?;
        }
        check_range(
            "bandwidth",
            self.bandwidth,
            f64::MIN_POSITIVE,
            f64::INFINITY,
            "> 0 (infinity: no filter)",
        )?;
        check_positive("flicker_min", self.flicker_min)?;
        check_range(
            "flicker_max",
            self.flicker_max,
            self.flicker_min,
            self.flicker_min * 1.0e7,
            "between flicker_min and 1e7 times flicker_min",
        )?;
        check_positive("drift_step", self.drift_step)?;
        if self.bias_instability > 0.0 {
            check_range(
                "drift_step",
                self.drift_step,
                0.0,
                self.flicker_min,
                "at most flicker_min (the grid must resolve the fastest flicker term)",
            )?;
        }
        let t = self.temperature;
        check_finite("temperature.start", t.start)?;
        check_finite("temperature.end", t.end)?;
        check_positive("temperature.time_constant", t.time_constant)?;
        check_finite("reference_temperature", self.reference_temperature)?;
        check_range(
            "range",
            self.range,
            f64::MIN_POSITIVE,
            f64::INFINITY,
            "> 0 (infinity: no clipping)",
        )
    }

    /// Number of Gauss-Markov terms of the flicker approximation (0 without bias instability).
    pub fn flicker_terms(&self) -> usize {
        if self.bias_instability <= 0.0 {
            return 0;
        }
        let decades = libm::log10(self.flicker_max / self.flicker_min);
        let n = libm::ceil(decades * FLICKER_TERMS_PER_DECADE - 1e-9).max(0.0) as usize + 1;
        n.min(MAX_FLICKER_TERMS)
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
    /// `N^2 / tau` (angle random walk) + the Gauss-Markov terms + `K^2 tau / 3` (rate random walk)
    /// (IEEE Std 952, Annex C). A Gauss-Markov process of variance `q^2` and correlation time `T`
    /// contributes `q^2 (T / tau)^2 (2 tau/T - 3 + 4 e^(-tau/T) - e^(-2 tau/T))`. Quantisation,
    /// temperature and the interpolation between drift-grid points are not included.
    pub fn allan_variance(&self, tau: f64) -> f64 {
        let mut avar = self.arw * self.arw / tau + self.rrw * self.rrw * tau / 3.0;
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
}

/// One simulated reading and the truth about its errors.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GyroSample {
    /// The reading `r_m` [rad/s] (after clipping and quantisation).
    pub rate: f64,
    /// Sensor temperature \[degC\].
    pub temperature: f64,
    /// Everything the gyro would read at rest apart from white noise: `b + d` [rad/s].
    pub bias: f64,
    /// The scale error `s` applied to this reading \[1\].
    pub scale: f64,
}

/// The slow bias `d` on its grid: the value at the grid points on either side of the current time.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct SlowBias {
    rng: Gaussian,
    /// Gauss-Markov states at grid point `index + 1` [rad/s].
    flicker: [f64; MAX_FLICKER_TERMS],
    /// Rate random walk state at grid point `index + 1` [rad/s].
    walk: f64,
    /// Grid point at or before the current time.
    index: u64,
    /// `d` at grid points `index` and `index + 1` [rad/s].
    before: f64,
    after: f64,
}

/// Per-term constants of the slow bias, derived from the configuration once.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct SlowTerms {
    count: usize,
    /// `exp(-drift_step / T_k)`.
    decay: [f64; MAX_FLICKER_TERMS],
    /// Standard deviation of each term's innovation per grid step: `q_k sqrt(1 - decay^2)`.
    innovation: [f64; MAX_FLICKER_TERMS],
    /// Stationary standard deviation `q_k` (the state at the first grid point).
    stationary: [f64; MAX_FLICKER_TERMS],
    /// Standard deviation of the random walk's step: `K sqrt(drift_step)`.
    walk_step: f64,
}

impl SlowTerms {
    fn new(config: &GyroModelConfig) -> Self {
        let mut terms = SlowTerms {
            count: config.flicker_terms(),
            decay: [0.0; MAX_FLICKER_TERMS],
            innovation: [0.0; MAX_FLICKER_TERMS],
            stationary: [0.0; MAX_FLICKER_TERMS],
            walk_step: config.rrw * libm::sqrt(config.drift_step),
        };
        for k in 0..terms.count {
            let (correlation, sd) = config.flicker_term(k);
            // Exact discretisation of dx/dt = -x/T + noise over one grid step.
            let decay = libm::exp(-config.drift_step / correlation);
            terms.decay[k] = decay;
            terms.innovation[k] = sd * libm::sqrt(1.0 - decay * decay);
            terms.stationary[k] = sd;
        }
        terms
    }
}

impl SlowBias {
    /// Grid points 0 and 1, the Gauss-Markov terms drawn from their stationary distribution and the
    /// random walk starting at 0 (its start is part of the bias).
    fn start(seed: u64, terms: &SlowTerms) -> Self {
        let mut slow = SlowBias {
            rng: Gaussian::new(seed, STREAM_DRIFT),
            flicker: [0.0; MAX_FLICKER_TERMS],
            walk: 0.0,
            index: 0,
            before: 0.0,
            after: 0.0,
        };
        for k in 0..terms.count {
            slow.flicker[k] = terms.stationary[k] * slow.rng.sample();
        }
        // `advance` moves `after` to `before`: start with grid point 0 there.
        slow.after = slow.sum(terms);
        slow.advance(terms);
        slow.index = 0;
        slow
    }

    fn sum(&self, terms: &SlowTerms) -> f64 {
        self.flicker[..terms.count].iter().sum::<f64>() + self.walk
    }

    /// Moves the state one grid step on.
    fn advance(&mut self, terms: &SlowTerms) {
        for k in 0..terms.count {
            self.flicker[k] =
                terms.decay[k] * self.flicker[k] + terms.innovation[k] * self.rng.sample();
        }
        if terms.walk_step > 0.0 {
            self.walk += terms.walk_step * self.rng.sample();
        }
        self.before = self.after;
        self.after = self.sum(terms);
        self.index += 1;
    }

    /// Longest stretch of grid steps taken one by one.
    const JUMP: u64 = 1 << 22;

    /// Moves the state `steps` grid steps on with one draw per term (exact in distribution: decay
    /// `a^steps`, innovation `q sqrt(1 - a^(2 steps))`, walk step `K sqrt(steps h)`). Used only
    /// across gaps of more than [`SlowBias::JUMP`] steps, so a far-off timestamp cannot stall the
    /// model; the realisation after such a gap depends on the gap.
    fn jump(&mut self, terms: &SlowTerms, steps: u64) {
        let m = steps as f64;
        for k in 0..terms.count {
            let decay = libm::pow(terms.decay[k], m);
            let sd = terms.stationary[k] * libm::sqrt(1.0 - decay * decay);
            self.flicker[k] = decay * self.flicker[k] + sd * self.rng.sample();
        }
        if terms.walk_step > 0.0 {
            self.walk += terms.walk_step * libm::sqrt(m) * self.rng.sample();
        }
        self.after = self.sum(terms);
        self.index += steps;
    }

    /// `d` at `elapsed` seconds after the first sample, interpolated between grid points.
    ///
    /// Time only moves forward here: an earlier time than the last one gets the value of the
    /// current grid interval's start.
    fn at(&mut self, terms: &SlowTerms, step: f64, elapsed: f64) -> f64 {
        if terms.count == 0 && terms.walk_step == 0.0 {
            return 0.0;
        }
        let target = libm::floor(elapsed / step);
        if target > (self.index + Self::JUMP) as f64 && target < 1e18 {
            // A gap of days: land one step short of the target, then step as usual.
            self.jump(terms, target as u64 - 1 - self.index);
        }
        while elapsed >= (self.index + 1) as f64 * step && elapsed < 1e18 * step {
            self.advance(terms);
        }
        let fraction = (elapsed / step - self.index as f64).clamp(0.0, 1.0);
        self.before + fraction * (self.after - self.before)
    }
}

/// A simulated gyro: feed it the true rate at each sample time, get the reading (see the module doc).
///
/// The first sample's time is the model's time origin (for the temperature profile and the drift
/// grid). Same configuration and seed, same readings.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GyroModel {
    config: GyroModelConfig,
    seed: u64,
    terms: SlowTerms,
    /// White-noise standard deviation per sample before the low-pass: `N sqrt(rate_hz)` [rad/s].
    noise_sd: f64,
    /// Pole of the discrete low-pass on the noise, `exp(-2 pi bandwidth / rate_hz)` (0: none).
    noise_pole: f64,
    noise: Gaussian,
    /// The low-passed noise of the previous sample [rad/s] (None before the first).
    noise_state: Option<f64>,
    slow: SlowBias,
    origin: Option<f64>,
}

impl GyroModel {
    /// Validates `config` and builds the model with random stream `seed`.
    pub fn new(config: GyroModelConfig, seed: u64) -> Result<Self, Error> {
        config.validate()?;
        let terms = SlowTerms::new(&config);
        Ok(GyroModel {
            config,
            seed,
            terms,
            noise_sd: config.arw * libm::sqrt(config.rate_hz),
            noise_pole: libm::exp(-core::f64::consts::TAU * config.bandwidth / config.rate_hz),
            noise: Gaussian::new(seed, STREAM_NOISE),
            noise_state: None,
            slow: SlowBias::start(seed, &terms),
            origin: None,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &GyroModelConfig {
        &self.config
    }

    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The sampling instants of this model's seed, from `start` \[s\] (see [`Sampler`]).
    pub fn sampler(&self, start: f64) -> Sampler {
        Sampler::new(&self.config, self.seed, start)
    }

    /// The reading for true rate `rate` [rad/s] at time `t` \[s\] (Hong eq 1 with the terms of the
    /// module doc). Times are expected to increase; no allocation, no panic.
    #[inline]
    pub fn measure(&mut self, t: f64, rate: f64) -> GyroSample {
        let c = self.config;
        let origin = *self.origin.get_or_insert(t);
        let elapsed = t - origin;
        let temperature = c.temperature.at(elapsed);
        let warm = temperature - c.reference_temperature;
        let direction = if rate > 0.0 {
            0.5
        } else if rate < 0.0 {
            -0.5
        } else {
            0.0
        };
        let scale = c.scale_error + c.scale_temperature * warm + direction * c.scale_asymmetry;
        let bias =
            c.bias + c.bias_temperature * warm + self.slow.at(&self.terms, c.drift_step, elapsed);
        let white = if self.noise_sd > 0.0 {
            self.filtered_noise()
        } else {
            0.0
        };
        let mut reading = ((1.0 + scale) * rate + bias + white).clamp(-c.range, c.range);
        if c.resolution > 0.0 {
            reading = libm::round(reading / c.resolution) * c.resolution;
        }
        GyroSample {
            rate: reading,
            temperature,
            bias,
            scale,
        }
    }

    /// The next sample of white noise `x_k` (standard deviation `N sqrt(rate_hz)`) through the
    /// low-pass `y_k = a y_(k-1) + (1 - a) x_k`.
    ///
    /// The filter's gain at 0 Hz is 1, so the low frequencies keep the density `N` and the Allan
    /// deviation stays `N / sqrt(tau)` for `tau` well above `1 / bandwidth`; the output's variance
    /// is `N^2 rate_hz (1 - a) / (1 + a)`. The first sample is drawn from that stationary
    /// distribution.
    #[inline]
    fn filtered_noise(&mut self) -> f64 {
        let a = self.noise_pole;
        let x = self.noise_sd * self.noise.sample();
        let y = match self.noise_state {
            _ if a == 0.0 => x,
            Some(previous) => a * previous + (1.0 - a) * x,
            None => x * libm::sqrt((1.0 - a) / (1.0 + a)),
        };
        self.noise_state = Some(y);
        y
    }
}

impl Stage for GyroModel {
    type Output = GyroSample;

    #[inline]
    fn update(&mut self, t: f64, rate: f64) -> GyroSample {
        self.measure(t, rate)
    }

    fn reset(&mut self) {
        self.noise = Gaussian::new(self.seed, STREAM_NOISE);
        self.noise_state = None;
        self.slow = SlowBias::start(self.seed, &self.terms);
        self.origin = None;
    }
}

/// Sampling instants of a logger: the nominal grid `start + k / rate_hz`, each instant after the
/// first moved by a Gaussian jitter (clipped to 0.45 of a period, so the order holds), and each
/// sample lost with `drop_probability`. An endless iterator of the kept instants \[s\].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Sampler {
    start: f64,
    period: f64,
    jitter: f64,
    drop_probability: f64,
    rng: Gaussian,
    index: u64,
}

impl Sampler {
    fn new(config: &GyroModelConfig, seed: u64, start: f64) -> Self {
        Sampler {
            start,
            period: 1.0 / config.rate_hz,
            jitter: config.jitter,
            drop_probability: config.drop_probability,
            rng: Gaussian::new(seed, STREAM_SAMPLING),
            index: 0,
        }
    }
}

impl Iterator for Sampler {
    type Item = f64;

    fn next(&mut self) -> Option<f64> {
        loop {
            let k = self.index;
            self.index += 1;
            let mut t = self.start + k as f64 * self.period;
            if k > 0 && self.jitter > 0.0 {
                let limit = 0.45 * self.period;
                t += (self.jitter * self.rng.sample()).clamp(-limit, limit);
            }
            // The first sample is always kept: it fixes the model's time origin.
            if k == 0 || self.drop_probability == 0.0 || self.rng.uniform() >= self.drop_probability
            {
                return Some(t);
            }
        }
    }
}
