//! Threshold (dead-band) filter of Hong & Park (Hong eq 12).

use crate::error::check_range;
use crate::kernel::{settings_are_config, Kernel, Measured, Signal, Streaming};
use crate::Error;

/// Dead band of Hong & Park: rates below the threshold are set to zero (Hong eq 12).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ThresholdConfig {
    /// `r_thres` [rad/s], >= 0 (0 disables). The paper uses 0.3 deg/s.
    pub threshold: f64,
}

impl ThresholdConfig {
    /// Checks the threshold.
    pub fn validate(&self) -> Result<(), Error> {
        check_range(
            "threshold",
            self.threshold,
            0.0,
            f64::MAX,
            "finite and >= 0",
        )
    }
}

/// The dead band as a [`Kernel`]: Hong eq 12, `if |r| < r_thres then r = 0`, on both the rate and
/// the corrected rate that HDR decides on. A threshold of 0 passes every rate (`|r| < 0` holds
/// for none), so the pipeline keeps this stage in every chain at the cost of one comparison.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ThresholdKernel;

impl Kernel for ThresholdKernel {
    type Config = ThresholdConfig;
    type State = ();

    fn start(_config: &ThresholdConfig) {}

    #[inline(always)]
    fn first(config: &ThresholdConfig, state: &mut (), x: Signal) -> Signal {
        Self::step(config, state, 0.0, x)
    }

    #[inline(always)]
    fn step(config: &ThresholdConfig, _state: &mut (), _dt: f64, x: Signal) -> Signal {
        let r = if libm::fabs(x.rate) < config.threshold {
            0.0
        } else {
            x.rate
        };
        Signal {
            rate: r,
            corrected: r,
            ..x
        }
    }

    fn measured(config: &mut ThresholdConfig, _state: &mut (), m: &Measured) {
        if let Some(threshold) = m.threshold {
            config.threshold = threshold;
        }
    }

    fn in_force(config: &ThresholdConfig) -> Measured {
        Measured {
            threshold: Some(config.threshold),
            ..Measured::default()
        }
    }
}

settings_are_config!(ThresholdKernel);

/// The dead band as a stand-alone stage.
pub type Threshold = Streaming<ThresholdKernel>;

impl Threshold {
    /// Applies Hong eq 12 to one rate.
    #[inline]
    pub fn apply(&self, rate: f64) -> f64 {
        ThresholdKernel::step(self.parts().0, &mut (), 0.0, Signal::corrected(rate)).rate
    }
}
