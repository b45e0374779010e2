//! The rest tracker's settings and the rules between them.

use crate::error::{check_duration, check_magnitude, check_positive, check_range};
use crate::Error;

/// Settings of the rest tracker (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RestTrackerConfig {
    /// Length of a detection block \[s\], > 0.
    pub block: f64,
    /// Shortest rest that counts, after its first and last block are dropped \[s\]; at least two
    /// blocks (the standard error needs two block means).
    pub min_duration: f64,
    /// Without speed: a still block's reading noise is at most this many times the noise at
    /// rest, >= 1.
    pub noise_ratio: f64,
    /// A still block's mean is within this many standard errors (from its own noise) of the
    /// previous block's, > 0 (`inf`: no such test).
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_float"))]
    pub change_sigmas: f64,
    /// Speed below which the vehicle is at rest [m/s], > 0 (its magnitude: reversing counts).
    pub speed_threshold: f64,
    /// Random-walk intensity `q` of the bias [rad^2/s^3], >= 0.
    pub bias_walk: f64,
    /// A rest whose mean is further than this many standard deviations of the innovation from
    /// the filtered bias is refused (`inf`: none), > 0.
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_float"))]
    pub gate_sigmas: f64,
    /// The reading noise at rest [rad/s] when known beforehand (Allan's `N / sqrt(dt)`); `None`
    /// takes it from the rest window or the first rest found with speed. Until it is known, rests
    /// are found from speed only.
    pub noise: Option<f64>,
}

/// The grid point with the lowest mean E_psi ratio to static-bias removal over the 18 real logs,
/// also the choice of most leave-one-log-out folds (docs/rest_tracking.md).
impl Default for RestTrackerConfig {
    fn default() -> Self {
        RestTrackerConfig {
            block: 0.5,
            min_duration: 1.0,
            noise_ratio: 1.5,
            change_sigmas: 4.0,
            speed_threshold: 0.05,
            bias_walk: 1e-9,
            gate_sigmas: 3.0,
            noise: None,
        }
    }
}

impl RestTrackerConfig {
    /// Checks every field; the error names the first invalid one (as `rest_<field>`).
    pub fn validate(&self) -> Result<(), Error> {
        check_duration("rest_block", self.block)?;
        check_range(
            "rest_min_duration",
            self.min_duration,
            2.0 * self.block,
            f64::MAX,
            "finite and at least two blocks (2 * rest_block): a rest's standard error needs two \
             block means",
        )?;
        check_range(
            "rest_noise_ratio",
            self.noise_ratio,
            1.0,
            f64::MAX,
            "finite and >= 1",
        )?;
        check_range(
            "rest_change_sigmas",
            self.change_sigmas,
            f64::MIN_POSITIVE,
            f64::INFINITY,
            "> 0 (inf: no test)",
        )?;
        check_positive("rest_speed_threshold", self.speed_threshold)?;
        check_magnitude("rest_bias_walk", self.bias_walk)?;
        check_range(
            "rest_gate_sigmas",
            self.gate_sigmas,
            f64::MIN_POSITIVE,
            f64::INFINITY,
            "> 0 (inf: no gate)",
        )?;
        if let Some(noise) = self.noise {
            check_magnitude("rest_noise", noise)?;
        }
        Ok(())
    }
}
