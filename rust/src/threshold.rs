//! Threshold (dead-band) filter of Hong & Park (Hong eq 12).

use crate::error::check_range;
use crate::stage::Stage;
use crate::Error;

/// Dead band of Hong & Park: rates below the threshold are set to zero (Hong eq 12).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ThresholdConfig {
    /// `r_thres` [rad/s], >= 0 (0 disables). The paper uses 0.3 deg/s.
    pub threshold: f64,
}

/// Threshold (dead-band) filter, Hong eq 12: `if |r| < r_thres then r = 0`.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Threshold {
    config: ThresholdConfig,
}

impl Threshold {
    /// Validates `config` and builds the stage.
    pub fn new(config: ThresholdConfig) -> Result<Self, Error> {
        check_range(
            "threshold",
            config.threshold,
            0.0,
            f64::MAX,
            "finite and >= 0",
        )?;
        Ok(Self::start(config))
    }

    /// The stage for a threshold known to be valid (finite, >= 0).
    pub(crate) fn start(config: ThresholdConfig) -> Self {
        Threshold { config }
    }

    /// Applies Hong eq 12 to one rate.
    #[inline]
    pub fn apply(&self, rate: f64) -> f64 {
        if libm::fabs(rate) < self.config.threshold {
            0.0
        } else {
            rate
        }
    }
}

impl Stage for Threshold {
    type Output = f64;

    #[inline]
    fn update(&mut self, _t: f64, rate: f64) -> f64 {
        self.apply(rate)
    }

    /// Stateless: nothing to reset.
    fn reset(&mut self) {}
}
