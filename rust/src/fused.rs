//! The pipeline with heading fixes: a [`Pipeline`] whose corrected rate feeds the heading-fix
//! filter [`Fusion`] (the recursive form of Hong eq 4-7), sample after sample, in one call.
//!
//! A block of samples comes with the fixes that fall in it or before it, sorted by time; the
//! pipeline runs first, then the filter takes its corrected rate with the fixes merged by time,
//! and the heading written is the filter's. Fixes after the block's last sample are not used: the
//! call returns how many it used, and the caller passes the rest again with the next block (no
//! fix is stored, so nothing allocates). A sample the pipeline skips (its input policy, its rate
//! then NaN) is left out of the filter and repeats the estimate before it. However the samples
//! and fixes are cut into blocks, the outputs are bit-identical.
//!
//! ```
//! use gyrocore::{Fix, FusedOutputs, FusedPipeline, FusionConfig, Preset, Samples};
//! let mut fused = FusedPipeline::new(Preset::Raw.config(), FusionConfig::default()).unwrap();
//! let t: Vec<f64> = (0..500).map(|i| i as f64 * 0.01).collect();
//! let rate = vec![0.1; t.len()]; // a steady turn of 0.1 rad/s
//! // a fix every second: the heading of that turn from 1.0 rad
//! let fixes: Vec<Fix> = (0..5)
//!     .map(|s| Fix { t: s as f64, heading: 1.0 + 0.1 * s as f64, sigma: 0.01 })
//!     .collect();
//! let mut cols = [vec![0.0; t.len()], vec![0.0; t.len()], vec![0.0; t.len()], vec![0.0; t.len()]];
//! let mut corrected = vec![0.0; t.len()];
//! let [heading, heading_sigma, bias, scale] = &mut cols;
//! let out = FusedOutputs {
//!     heading,
//!     heading_sigma: Some(&mut heading_sigma[..]), // None for an estimate not needed
//!     bias: Some(&mut bias[..]),
//!     scale: Some(&mut scale[..]),
//!     rate: &mut corrected,
//!     drift: None,
//! };
//! let used = fused.process_block(Samples::new(&t, &rate), &fixes, out).unwrap();
//! assert_eq!(used, 5); // every fix lies within the block
//! assert!((cols[0][499] - (1.0 + 0.1 * 4.99)).abs() < 0.02);
//! assert!(cols[1][499] < 0.05); // the filter's heading sigma [rad]
//! ```

use crate::fixes::{reachable, Fix, FixCounts, Fusion, FusionConfig, FusionError, FusionOutputs};
use crate::pipeline::{Outputs, Pipeline, PipelineConfig};
use crate::rest_tracker::Rest;
use crate::Error;

/// A block of gyro samples: times \[s\] and rates \[rad/s\], with the temperature \[degC\] where the
/// pipeline's temperature model needs it and the vehicle's speed [m/s] for its rest tracker.
#[derive(Debug, Clone, Copy)]
pub struct Samples<'a> {
    /// Times \[s\], strictly increasing (also across blocks).
    pub t: &'a [f64],
    /// Yaw rates [rad/s], counter-clockwise positive.
    pub rate: &'a [f64],
    /// Temperatures \[degC\] (see [`Pipeline::process_block`]).
    pub temperature: Option<&'a [f64]>,
    /// Speeds [m/s] (see [`Pipeline::process_block_with_speed`]).
    pub speed: Option<&'a [f64]>,
}

impl<'a> Samples<'a> {
    /// Times and rates alone.
    pub fn new(t: &'a [f64], rate: &'a [f64]) -> Self {
        Samples {
            t,
            rate,
            temperature: None,
            speed: None,
        }
    }
}

/// Where [`FusedPipeline::process_block`] writes, one value per sample (each slice as long as
/// the block); `None` for an estimate the caller does not need (it is then not computed: the
/// sigma takes a square root per sample, and each column a pass of stores).
#[derive(Debug)]
pub struct FusedOutputs<'a> {
    /// The filter's heading \[rad\], continuous.
    pub heading: &'a mut [f64],
    /// Its standard deviation \[rad\].
    pub heading_sigma: Option<&'a mut [f64]>,
    /// The bias of the corrected rate left to the filter [rad/s] (Hong eq 1's `b`).
    pub bias: Option<&'a mut [f64]>,
    /// The scale error of the corrected rate (Hong eq 1's `s`).
    pub scale: Option<&'a mut [f64]>,
    /// The pipeline's corrected rate, the filter's input [rad/s] (NaN where a sample was skipped).
    pub rate: &'a mut [f64],
    /// HDR's drift estimate [rad/s], if wanted.
    pub drift: Option<&'a mut [f64]>,
}

/// A [`Pipeline`] and a [`Fusion`] on its corrected rate; its state is `Clone` and serialisable
/// (a copy, restored, carries on bit-identically).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(remote = "Self")
)]
pub struct FusedPipeline {
    pipeline: Pipeline,
    fusion: Fusion,
}

impl FusedPipeline {
    /// Validates both configurations and builds the pipeline and its filter (the filter's
    /// initial heading is its own, [`FusionConfig::initial_heading`]).
    pub fn new(pipeline: PipelineConfig, fusion: FusionConfig) -> Result<Self, Error> {
        Ok(FusedPipeline {
            fusion: Fusion::new(fusion)?,
            pipeline: Pipeline::new(pipeline)?,
        })
    }

    /// Checks a state read back (`serde` feature; the pipeline and the filter have each been
    /// checked as they were read): the filter stands at the pipeline's last time, the last
    /// sample both took. One behind took the next block's first interval as rate over the whole
    /// time between, one ahead refused the next valid fix.
    #[cfg(feature = "serde")]
    pub(crate) fn check_restored(&self) -> Result<(), Error> {
        if self.pipeline.clock_restart_pending() != self.fusion.restart_pending() {
            return Err(Error::InvalidParameter {
                name: "filter restarted",
                value: f64::from(u8::from(self.fusion.restart_pending())),
                valid: "the pipeline's (both restart their clock at once)",
            });
        }
        let (pipeline, fusion) = (self.pipeline.last_time(), self.fusion.last_time());
        if pipeline == fusion {
            return Ok(());
        }
        Err(Error::InvalidParameter {
            name: "filter time",
            value: fusion.unwrap_or(f64::NAN),
            valid: "the pipeline's last time (the filter takes every sample the pipeline takes)",
        })
    }

    /// The pipeline (its bias, rest tracker, input report).
    pub fn pipeline(&self) -> &Pipeline {
        &self.pipeline
    }

    /// The filter (its estimate now, its configuration).
    pub fn fusion(&self) -> &Fusion {
        &self.fusion
    }

    /// How the fixes were used so far.
    pub fn counts(&self) -> FixCounts {
        self.fusion.counts()
    }

    /// Returns both to their state before the first sample.
    pub fn reset(&mut self) {
        self.pipeline.reset();
        self.fusion.reset();
    }

    /// Restarts the clock of both (see [`Pipeline::restart_clock`] and [`Fusion::restart_clock`]):
    /// the next sample may come at any time, and starts a new time base; the heading, bias,
    /// scale and every estimate are kept, nothing is integrated across the jump. The fixes not
    /// used yet (the caller's `&fixes[used..]`) are on the old clock: drop them, and give only
    /// fixes on the new one. Refused while the pipeline measures its rest window, nothing changed.
    pub fn restart_clock(&mut self) -> Result<(), Error> {
        self.pipeline.restart_clock()?;
        self.fusion.restart_clock();
        Ok(())
    }

    /// Processes a block of samples with the fixes up to its last sample (sorted by time; any
    /// after it are left for the next call). Returns how many fixes it used: pass
    /// `&fixes[used..]` again, ahead of any new ones, with the next block.
    ///
    /// A bad fix ([`FusionError::Fix`], its index in `fixes`; the block checks those it reaches,
    /// see [`reachable`]) or a bad sample ([`FusionError::Gyro`], its index in the block) leaves
    /// the state as it was before the call (the outputs are not).
    pub fn process_block(
        &mut self,
        samples: Samples<'_>,
        fixes: &[Fix],
        out: FusedOutputs<'_>,
    ) -> Result<usize, FusionError> {
        self.process_block_reporting(samples, fixes, out, &mut |_| {})
    }

    /// [`FusedPipeline::process_block`] that hands `on_rest` every rest the pipeline's tracker
    /// finds (see [`Pipeline::process_block_reporting`]).
    pub fn process_block_reporting(
        &mut self,
        samples: Samples<'_>,
        fixes: &[Fix],
        out: FusedOutputs<'_>,
        on_rest: &mut dyn FnMut(Rest),
    ) -> Result<usize, FusionError> {
        let n = samples.t.len();
        let FusedOutputs {
            heading,
            heading_sigma,
            bias,
            scale,
            rate,
            drift,
        } = out;
        let mut estimates = FusionOutputs {
            heading,
            heading_sigma,
            bias,
            scale,
        };
        estimates.check(n)?;
        // Checked before the pipeline runs, so that a bad fix changes nothing.
        self.fusion
            .check_fixes(reachable(fixes, samples.t.last().copied()))?;
        let outputs = Outputs {
            heading: None,
            rate: Some(&mut *rate),
            drift,
        };
        // On an error the pipeline restores itself, and the filter has not moved.
        self.pipeline.process_block_reporting(
            samples.t,
            samples.rate,
            samples.temperature,
            samples.speed,
            outputs,
            on_rest,
        )?;
        // The pipeline accepted every timestamp (finite, strictly increasing), and its corrected
        // rate is finite wherever it took a sample: the filter takes those one by one, as
        // `Fusion::process_block` would, and leaves out the ones the pipeline skipped: the
        // state stands still over those, so the estimate written for one repeats the row before.
        Ok(self
            .fusion
            .run(samples.t, rate, fixes, &mut estimates, &mut |_| {}))
    }
}
