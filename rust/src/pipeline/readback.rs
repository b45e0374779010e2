//! The checks of a [`Pipeline`] read back (`serde` feature): its configuration, clock, held
//! reading, repeated output and input report, and its stages against the ones the configuration
//! builds with what the rest of the state says they were handed.

use super::Pipeline;
use crate::kernel::Measured;
use crate::Error;

impl Pipeline {
    /// The checks of a pipeline read back (see the type's doc): its configuration, its clock,
    /// the reading it holds and the output it repeats, and its stages against the ones the
    /// configuration builds.
    pub(crate) fn check_restored(&self) -> Result<(), Error> {
        self.config.validate()?;
        self.clock.check_restored()?;
        let restarted = self.clock_restarts > 0;
        self.bias
            .check(self.config.correction.bias, self.clock.last(), restarted)?;
        // A restart is pending only after one, and only with a sample before it.
        if self.clock_restarted && (!restarted || self.clock.last().is_none()) {
            return Err(Error::InvalidParameter {
                name: "clock_restarted",
                value: 1.0,
                valid: "false before the first sample and without a restart counted",
            });
        }
        // The reading the policy holds is one it took: a stored one of 1e308 was held into
        // infinite headings. The output a skipped sample repeats is one the chain gave.
        if let Some((rate, temperature)) = self.last_reading {
            crate::error::check_usable("last rate", rate)?;
            if let Some(temperature) = temperature {
                crate::error::check_usable("last temperature", temperature)?;
            }
        }
        crate::error::check_heading("last heading", self.last_output.heading)?;
        crate::error::check_stored("last output rate", self.last_output.rate)?;
        crate::error::check_stored("last drift", self.last_output.drift)?;
        self.report.check_restored()?;
        let pending = (self.config.noise_scaled.any() || self.config.rest_tracker.is_some())
            && (self.clock.last().is_none() || self.bias.learning());
        if self.scaling_pending != pending {
            let valid = "true until the first sample past the rest window (noise-scaled bounds or \
                         a rest tracker), false from then on";
            let value = if self.scaling_pending { 1.0 } else { 0.0 };
            return Err(Error::InvalidParameter {
                name: "scaling_pending",
                value,
                valid,
            });
        }
        let handed = self.handed()?;
        self.engine.check_restored(&self.config, &handed)
    }

    /// What the stages were handed, as the rest of the state says (see
    /// [`Engine::check_restored`]): the configuration's values wherever nothing may change them.
    /// The rest tracker's chain takes the values it set where the configuration lets it (its
    /// bias is checked against the tracker's); any other chain the bias of the static bias test
    /// and the noise-scaled bounds its rest window gives, which the stored ones must be.
    fn handed(&self) -> Result<Measured, Error> {
        let stored = self.engine.in_force();
        let scaled = self.config.noise_scaled;
        if self.engine.is_tracked() {
            return Ok(Measured {
                bias: stored.bias,
                threshold: stored
                    .threshold
                    .filter(|_| scaled.threshold_sigmas.is_some()),
                hdr_bound: stored
                    .hdr_bound
                    .filter(|_| scaled.hdr_bound_sigmas.is_some()),
                rest: None,
            });
        }
        let rest = self
            .bias
            .rest_statistics()
            .filter(|_| !self.scaling_pending);
        // The scaled values are computed again from the window's sums, which a state written
        // without exact floats carries rounded: they must agree within that rounding, relative
        // to the readings' size too (the parts' means cancel in the bias's standard error).
        let size = libm::fabs(self.bias.value());
        let learned = |name: &'static str, value: Option<f64>, k: Option<f64>, of: f64| {
            let (Some(value), Some(k)) = (value, k) else {
                return Ok(None);
            };
            let expected = k * of;
            let most = crate::error::ROUNDING * (libm::fabs(expected) + k * size);
            if libm::fabs(value - expected) <= most {
                Ok(Some(value))
            } else {
                let valid = "the noise-scaled value the rest window's statistics give";
                Err(Error::InvalidParameter { name, value, valid })
            }
        };
        let Some(rest) = rest else {
            return Ok(Measured {
                bias: Some(self.bias.value()),
                ..Measured::default()
            });
        };
        Ok(Measured {
            bias: Some(self.bias.value()),
            threshold: learned(
                "threshold",
                stored.threshold,
                scaled.threshold_sigmas,
                rest.noise,
            )?,
            hdr_bound: learned(
                "hdr_max_correction",
                stored.hdr_bound,
                scaled.hdr_bound_sigmas,
                rest.bias_std_error,
            )?,
            rest: None,
        })
    }
}
