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

use crate::stage::Stage;
use crate::Error;

mod config;
mod random;
mod slow;

pub use config::{GyroModelConfig, TemperatureProfile};
pub use random::{Gaussian, SplitMix64, Xoshiro256PlusPlus};
use slow::{SlowBias, SlowTerms};

/// Most first-order Gauss-Markov terms the flicker approximation may use.
pub const MAX_FLICKER_TERMS: usize = 16;

/// Gauss-Markov terms per decade of correlation time in the flicker approximation. Two per decade
/// keep the flat part of the Allan deviation within about 3 % of `0.664 B` (tested).
const FLICKER_TERMS_PER_DECADE: f64 = 2.0;

/// The largest fraction of samples a logger may lose ([`GyroModelConfig::drop_probability`]).
const MAX_DROP_PROBABILITY: f64 = 0.99;

/// Stream numbers: each purpose draws from its own generator, so that changing how many samples are
/// taken (the rate, the drops) does not change the drift.
const STREAM_DRIFT: u64 = 1;
const STREAM_NOISE: u64 = 2;
const STREAM_SAMPLING: u64 = 3;

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

/// A simulated gyro: feed it the true rate at each sample time, get the reading (see the module doc).
///
/// The first sample's time is the model's time origin (for the temperature profile and the drift
/// grid). Same configuration and seed, same readings.
///
/// Read back (`serde` feature), its configuration is checked as [`GyroModel::new`] checks it,
/// and what it derives from it (the flicker terms, the noise's scale and pole) is derived again.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(remote = "Self")
)]
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
            noise_pole: libm::exp(-config.noise_pole_decay()),
            noise: Gaussian::new(seed, STREAM_NOISE),
            noise_state: None,
            slow: SlowBias::start(seed, &terms),
            origin: None,
        })
    }

    /// A model read back: its configuration checked, and what [`GyroModel::new`] derives from it
    /// derived again (a count of flicker terms beyond [`MAX_FLICKER_TERMS`] panicked on a slice
    /// index; a float written without `serde_json`'s `float_roundtrip` may differ in its last
    /// digit).
    #[cfg(feature = "serde")]
    pub(crate) fn restored(self) -> Result<Self, Error> {
        let built = GyroModel::new(self.config, self.seed)?;
        Ok(GyroModel {
            terms: built.terms,
            noise_sd: built.noise_sd,
            noise_pole: built.noise_pole,
            ..self
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

    /// The sampling instants of this model's seed, from `start` \[s\] (see [`Sampler`]). They
    /// increase strictly while a tenth of the period (what jitter leaves between two) exceeds
    /// float64's step at the time reached (`0.1 / rate_hz > f64::EPSILON * t`: up to about
    /// 2.6e5 Hz at t = 1.7e9 s); beyond, rounding makes instants repeat.
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
        let reading = quantise(
            clip((1.0 + scale) * rate + bias + white, c.range),
            c.resolution,
        );
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

/// `x` rounded to a multiple of `resolution` (0: none). A resolution so fine that `x` holds more
/// than 2^1024 of its steps (a subnormal one: `x / resolution` overflowed, and an infinite
/// reading came out) lies far below the float spacing of `x`, which is then the rounded value.
#[inline]
fn quantise(x: f64, resolution: f64) -> f64 {
    let steps = libm::round(x / resolution);
    if resolution > 0.0 && steps.is_finite() {
        steps * resolution
    } else {
        x
    }
}

/// `x` clipped to `[-bound, bound]`, a NaN staying NaN; a bound that is not >= 0 (a state read
/// back without validation) clips nothing, where `f64::clamp` would panic.
#[inline]
fn clip(x: f64, bound: f64) -> f64 {
    if bound >= 0.0 {
        x.clamp(-bound, bound)
    } else {
        x
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
            // saturating: a sampler read back may hold any index (u64::MAX overflowed)
            self.index = k.saturating_add(1);
            let mut t = self.start + k as f64 * self.period;
            if k > 0 && self.jitter > 0.0 {
                let limit = 0.45 * self.period;
                t += clip(self.jitter * self.rng.sample(), limit);
            }
            // The first sample is always kept: it fixes the model's time origin. The probability
            // is capped as `validate` caps it: a sampler read back with 1 or more (or NaN) kept
            // nothing, and `next` never returned.
            let drop = self.drop_probability.min(MAX_DROP_PROBABILITY);
            if k == 0 || drop == 0.0 || self.rng.uniform() >= drop {
                return Some(t);
            }
        }
    }
}
