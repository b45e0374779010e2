//! What the rest window says about the sensor besides its bias: the noise of one reading and how
//! uncertain the measured bias is. They scale the dead band and bound HDR's correction to the
//! sensor at hand (see [`crate::pipeline::NoiseScaled`]): a gyro whose rest shows no noise and an
//! exact bias gets neither, because there is nothing for them to remove.

use crate::correction::StaticBias;
use crate::validate::check_block_while;
use crate::Error;

/// Number of equal parts of the rest window whose means give the bias's standard error.
const BATCHES: usize = 8;

/// Noise statistics of a measured rest window.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RestStatistics {
    /// Standard deviation of one reading's noise [rad/s], from the differences of successive
    /// readings (`sqrt(mean(d^2) / 2)`): a slow drift or smooth motion cancels in them.
    pub noise: f64,
    /// Standard error of the static bias [rad/s]: the spread of the means of the window's
    /// eight equal parts over `sqrt(parts)` (the batch-means estimate, which stays right
    /// when the noise of neighbouring readings is correlated, where `noise / sqrt(n)` would not).
    pub bias_std_error: f64,
}

/// Accumulates [`RestStatistics`] over a rest window, one reading at a time.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct RestNoise {
    previous: Option<f64>,
    squared_differences: f64,
    differences: u64,
    /// Integral of the readings [rad] and time covered [s] in each part of the window.
    batch_integral: [f64; BATCHES],
    batch_duration: [f64; BATCHES],
}

impl RestNoise {
    /// Takes a reading at `position` in the window (0 at its start, 1 at its end) that stands
    /// for the interval `dt` before it (the rectangle rule of the bias itself).
    #[inline]
    pub(crate) fn push(&mut self, position: f64, dt: f64, rate: f64) {
        if let Some(p) = self.previous {
            self.squared_differences += (rate - p) * (rate - p);
            self.differences = self.differences.saturating_add(1);
        }
        self.previous = Some(rate);
        // Truncation picks the part; the end of the window belongs to the last one.
        let part = ((position * BATCHES as f64) as usize).min(BATCHES - 1);
        self.batch_integral[part] += rate * dt;
        self.batch_duration[part] += dt;
    }

    /// Checks the sums read back (`serde` feature) against what readings within
    /// [`MAX_READING`](crate::MAX_READING) leave: the last reading one of them, the squared
    /// differences within `(2^21)^2` each, every part's time within 0 and 2^41 s and its
    /// integral's mean within +-2^21 rad/s (room for rounding). A part's time of 1e-300 under
    /// its integral gave an infinite standard error of the bias, and the rest tracker's headings
    /// NaN; squared differences of -1 a NaN noise.
    #[cfg(feature = "serde")]
    fn check(&self) -> Result<(), Error> {
        use crate::error::{check_integral, check_range, check_usable};
        use crate::{MAX_READING, MAX_TIME};
        if let Some(p) = self.previous {
            check_usable("rest window last reading", p)?;
        }
        let most = 2.0 * (2.0 * MAX_READING) * (2.0 * MAX_READING) * self.differences as f64;
        let valid = ">= 0 and at most (2^21)^2 per difference, the largest two readings make";
        check_range(
            "rest window squared differences",
            self.squared_differences,
            0.0,
            most,
            valid,
        )?;
        for (&integral, &duration) in self.batch_integral.iter().zip(&self.batch_duration) {
            let valid = "within 0 and 2^41 s";
            check_range(
                "rest window part duration",
                duration,
                0.0,
                2.0 * MAX_TIME,
                valid,
            )?;
            check_integral("rest window part integral", integral, duration)?;
        }
        Ok(())
    }

    /// The statistics, or `None` while fewer than two parts or two readings have been seen.
    pub(crate) fn statistics(&self) -> Option<RestStatistics> {
        if self.differences == 0 {
            return None;
        }
        let mut means = [0.0; BATCHES];
        let mut parts = 0;
        for (integral, duration) in self.batch_integral.iter().zip(&self.batch_duration) {
            if *duration > 0.0 {
                means[parts] = integral / duration;
                parts += 1;
            }
        }
        if parts < 2 {
            return None;
        }
        let means = &means[..parts];
        let k = parts as f64;
        let mean = means.iter().sum::<f64>() / k;
        let spread = means.iter().map(|m| (m - mean) * (m - mean)).sum::<f64>() / (k - 1.0);
        Some(RestStatistics {
            noise: libm::sqrt(self.squared_differences / (2.0 * self.differences as f64)),
            bias_std_error: libm::sqrt(spread / k),
        })
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
pub(crate) struct BiasEstimate {
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
    /// The window's noise, for [`crate::Correction::rest_statistics`].
    noise: RestNoise,
    /// The first timestamp seen, for the error of a window that holds no sample.
    first: Option<f64>,
}

impl BiasEstimate {
    pub(crate) fn new(source: StaticBias) -> Self {
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
            first: None,
        }
    }

    /// Takes the reading into the mean while `t` is inside the window (HDR eq 2's `eps0`), and
    /// ends the measurement once `t` is past it; `dt` is the interval since the previous reading
    /// \[s\] (0 for the first).
    pub(crate) fn learn(&mut self, source: StaticBias, t: f64, dt: f64, rate: f64) {
        self.first.get_or_insert(t);
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
            self.count = self.count.saturating_add(1);
            self.value = if self.duration > 0.0 {
                self.integral / self.duration
            } else {
                rate
            };
        }
    }
}

impl BiasEstimate {
    /// The bias in use now [rad/s].
    pub(crate) fn value(&self) -> f64 {
        self.value
    }

    /// How many readings the measured bias averages (0 for a fixed bias).
    pub(crate) fn count(&self) -> u64 {
        self.count
    }

    /// True while the rest window is still being measured.
    pub(crate) fn learning(&self) -> bool {
        self.learning
    }

    /// The rest window \[s\], once known.
    pub(crate) fn window(&self) -> Option<(f64, f64)> {
        self.window
    }

    /// The error for a window the samples up to `last` \[s\] passed without a reading inside.
    pub(crate) fn missed(&self, last: f64) -> Option<Error> {
        let (start, end) = self.window.filter(|_| self.count == 0)?;
        Some(Error::EmptyRestWindow {
            start,
            end,
            first: self.first.unwrap_or(last),
            last,
        })
    }

    /// Checks an estimate read back (`serde` feature) for `source` (the configuration's) and
    /// `last`, the last time its clock took, and `restarted`, true once that clock was
    /// restarted (after the window: its times then say nothing of it): the bias a reading, the time measured within the
    /// window's longest, the integral's mean over it a reading too (the bias learned from it is
    /// that mean), the window's bounds within +-2^41 s, and its noise's sums
    /// ([`RestNoise::check`]). Then the estimate against its source: a fixed bias is the
    /// configured one and learns nothing; a window is the configured one, or for a leading
    /// window of the configured duration from the first sample; the measurement is over only
    /// once a time past the window's end was taken, and going on only until then; no time or
    /// integral is measured before a second reading. A stored integral of 1e308 gave an infinite
    /// bias at the next reading, a NaN window never ended, a window not the configured one
    /// refused the next block, and one marked over before it ran left the bias at 0 unreported.
    #[cfg(feature = "serde")]
    pub(crate) fn check(
        &self,
        source: StaticBias,
        last: Option<f64>,
        restarted: bool,
    ) -> Result<(), Error> {
        use crate::error::{check_mean, check_range, check_reading};
        use crate::MAX_TIME;
        check_reading("bias", self.value)?;
        let longest = 2.0 * MAX_TIME;
        check_range(
            "bias duration",
            self.duration,
            0.0,
            longest,
            "within 0 and 2^41 s",
        )?;
        // The mean is the bias learned from it, which the next read-back checks as a reading.
        check_mean("bias integral", self.integral, self.duration)?;
        for bound in self.window.iter().flat_map(|&(start, end)| [start, end]) {
            check_range("bias_window", bound, -longest, longest, "within +-2^41 s")?;
        }
        self.noise.check()?;
        self.check_source(source, last, restarted)
    }

    /// The part of [`BiasEstimate::check`] that compares the estimate with its source and clock.
    #[cfg(feature = "serde")]
    fn check_source(
        &self,
        source: StaticBias,
        last: Option<f64>,
        restarted: bool,
    ) -> Result<(), Error> {
        let refuse = |name: &'static str, value: f64, valid: &'static str| {
            Err(Error::InvalidParameter { name, value, valid })
        };
        let as_f64 = |b: bool| if b { 1.0 } else { 0.0 };
        let window = match source {
            StaticBias::Fixed(b) => {
                if self.value != b {
                    return refuse("bias", self.value, "the configured fixed bias");
                }
                if self.learning || self.count > 0 || self.duration > 0.0 || self.window.is_some() {
                    let valid = "false for a fixed bias, which measures no window";
                    return refuse("bias learning", as_f64(self.learning), valid);
                }
                return Ok(());
            }
            StaticBias::Window { start, end } => {
                if self.window != Some((start, end)) {
                    let valid = "the configured window";
                    let value = self.window.map_or(f64::NAN, |w| w.0);
                    return refuse("bias_window", value, valid);
                }
                (start, end)
            }
            StaticBias::Leading { duration } => match (self.window, self.first) {
                (None, None) if last.is_none() => {
                    if !self.learning {
                        let valid = "true until a time past the window's end was taken";
                        return refuse("bias learning", 0.0, valid);
                    }
                    return self.check_empty();
                }
                (Some((start, end)), Some(first)) => {
                    // The end is the first time plus the duration, rounded (and maybe read
                    // back without exact floats).
                    let off = libm::fabs(end - (start + duration));
                    let ulps = 4.0 * f64::EPSILON * (libm::fabs(start) + duration);
                    if start != first || off > ulps {
                        let valid = "the configured duration from the first sample";
                        return refuse("bias_window", end, valid);
                    }
                    (start, end)
                }
                _ => {
                    let valid = "set at the first sample";
                    return refuse("bias_window", f64::NAN, valid);
                }
            },
        };
        // `learn` ends the measurement at the first time past the window's end, and only there.
        let passed = restarted || last.is_some_and(|t| t > window.1);
        if self.learning == passed {
            let valid = "true until a time past the window's end was taken, false from then on";
            return refuse("bias learning", as_f64(self.learning), valid);
        }
        if self.count == 0 {
            return self.check_empty();
        }
        if self.count == 1 && (self.duration != 0.0 || self.integral != 0.0) {
            let valid = "0 until the window's second reading (the first has no interval in it)";
            return refuse("bias duration", self.duration, valid);
        }
        if self.duration > 0.0 {
            // The bias is the integral's mean, within the rounding of floats read back inexactly.
            let mean = self.integral / self.duration;
            if libm::fabs(self.value - mean) > crate::error::ROUNDING * libm::fabs(mean) {
                let valid = "the bias integral's mean over the bias duration";
                return refuse("bias", self.value, valid);
            }
        }
        Ok(())
    }

    /// An estimate that took no reading in its window: nothing measured, a bias of 0.
    #[cfg(feature = "serde")]
    fn check_empty(&self) -> Result<(), Error> {
        if self.duration != 0.0 || self.integral != 0.0 || self.value != 0.0 {
            let valid = "0 before the window's first reading";
            return Err(Error::InvalidParameter {
                name: "bias",
                value: self.value,
                valid,
            });
        }
        Ok(())
    }

    /// See [`crate::Correction::rest_statistics`].
    pub(crate) fn rest_statistics(&self) -> Option<RestStatistics> {
        if self.learning || self.window.is_none() {
            return None;
        }
        self.noise.statistics()
    }
}

/// What the static bias test measured in a rest window (HDR eq 1-2's `eps0`, FOG section 2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticBiasTest {
    /// The time-weighted mean reading in the window [rad/s] (what the gyro reads at rest).
    pub bias: f64,
    /// How many readings lie in the window.
    pub count: u64,
    /// The window's noise and the bias's standard error (`None` from too few readings).
    pub statistics: Option<RestStatistics>,
}

/// The static bias test over the readings `rate` at `t` inside `[start, end]`: exactly what a
/// pipeline with this rest window ends with (the same estimator, sample by sample).
///
/// Fails for a bad block (see [`check_block`](crate::check_block)), an invalid window, or one
/// that holds no reading.
pub fn static_bias_test(
    t: &[f64],
    rate: &[f64],
    start: f64,
    end: f64,
) -> Result<StaticBiasTest, Error> {
    match bias_test_while(t, rate, (start, end), || true)? {
        Some(test) => Ok(test),
        None => unreachable!("a test that always goes on ends"),
    }
}

/// [`static_bias_test`] that gives up (`Ok(None)`) once `stop` is set (by another thread: a
/// Ctrl-C of a long log), looking at it every 2^16 samples; the same result otherwise.
///
/// Errors: as [`static_bias_test`].
#[cfg(feature = "std")]
pub fn static_bias_test_stoppable(
    t: &[f64],
    rate: &[f64],
    start: f64,
    end: f64,
    stop: &std::sync::atomic::AtomicBool,
) -> Result<Option<StaticBiasTest>, Error> {
    use std::sync::atomic::Ordering;
    bias_test_while(t, rate, (start, end), || !stop.load(Ordering::Relaxed))
}

/// [`static_bias_test`] as long as `go_on()`: `None` once it says no.
fn bias_test_while(
    t: &[f64],
    rate: &[f64],
    (start, end): (f64, f64),
    go_on: impl Fn() -> bool,
) -> Result<Option<StaticBiasTest>, Error> {
    let window = StaticBias::Window { start, end };
    crate::CorrectionConfig {
        bias: window,
        ..crate::CorrectionConfig::default()
    }
    .validate()?;
    if !check_block_while(t, rate, &go_on)? {
        return Ok(None);
    }
    let mut estimate = BiasEstimate::new(window);
    let mut previous = None;
    for (i, (&ti, &ri)) in t.iter().zip(rate).enumerate() {
        if ti > end {
            break;
        }
        if i % (1 << 16) == 0 && !go_on() {
            return Ok(None);
        }
        let dt = previous.map_or(0.0, |p| ti - p);
        estimate.learn(window, ti, dt, ri);
        previous = Some(ti);
    }
    if let Some(e) = estimate.missed(t.last().copied().unwrap_or(end)) {
        return Err(e);
    }
    Ok(Some(StaticBiasTest {
        bias: estimate.value(),
        count: estimate.count(),
        statistics: estimate.noise.statistics(),
    }))
}
