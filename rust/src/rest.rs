//! What the rest window says about the sensor besides its bias: the noise of one reading and how
//! uncertain the measured bias is. They scale the dead band and bound HDR's correction to the
//! sensor at hand (see [`crate::pipeline::NoiseScaled`]): a gyro whose rest shows no noise and an
//! exact bias gets neither, because there is nothing for them to remove.

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
            self.differences += 1;
        }
        self.previous = Some(rate);
        // Truncation picks the part; the end of the window belongs to the last one.
        let part = ((position * BATCHES as f64) as usize).min(BATCHES - 1);
        self.batch_integral[part] += rate * dt;
        self.batch_duration[part] += dt;
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
