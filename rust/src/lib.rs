//! # gyrocore
//!
//! A drift-free heading from a yaw-rate gyro. The core crate holds the per-sample streaming
//! stages of three papers and composes them into one [`Pipeline`]:
//!
//! ```text
//! samples -> Correction -> Threshold -> LowPass -> Hdr -> DeLag -> Integrator -> heading
//! ```
//!
//! Every stage is a validated `Copy` config plus private state with `new`, `update`, `reset` and
//! block processing; the state serialises with the `serde` feature. `update` never allocates and
//! never panics. Units are SI (s, rad, rad/s), counter-clockwise positive (ROS REP-103); the bias
//! is what the gyro reads at rest (corrected = measured - bias). The crate is `no_std` without its
//! default `std` feature.
//!
//! | equation | where |
//! |---|---|
//! | HDR eq 1-2, static bias `eps0` | [`correction::StaticBias`], [`Correction`] |
//! | HDR eq 3 and 14, heading | [`integrate::Method::Rectangle`], [`Integrator`] |
//! | HDR eq 4, 8-12, binary I-controller, turn switch, repetition attenuator | [`Hdr`] |
//! | HDR eq 7, low-pass | [`LowPass`] |
//! | HDR eq 13, de-lag | [`DeLag`] |
//! | HDR second eq 14, block down-sampling | [`Downsample`] |
//! | Hong eq 3, linear calibration `s_bar r_m + b_bar` | [`CorrectionConfig::scale`], [`CorrectionConfig::offset`] |
//! | Hong eq 12, threshold | [`Threshold`] |
//! | FOG eq 2-4, cw/ccw correction factors | [`CorrectionConfig::c_cw`], [`CorrectionConfig::c_ccw`] |
//! | FOG eq 5-6, temperature-linear scale factor | [`correction::TemperatureScale`] |
//! | Hong eq 3-7, recursive least squares of scale and bias with heading fixes (a Kalman filter), and its smoother | [`Fusion`], [`smooth`], on the pipeline's rate: [`FusedPipeline`] |
//! | Allan, overlapping, modified and Hadamard variances (IEEE 952, Hong section 2.1) | [`allan`] |
//!
//! ```
//! use gyrocore::{Pipeline, Preset};
//! let mut config = Preset::Hdr.config();
//! config.correction.bias = gyrocore::StaticBias::Leading { duration: 20.0 };
//! let mut pipeline = Pipeline::new(config).unwrap();
//! for i in 0..100 {
//!     let out = pipeline.update(i as f64 * 0.01, 0.001);
//!     assert!(out.heading.is_finite());
//! }
//! ```
//!
//! Where to go from there:
//!
//! - **Sample by sample** ([`Pipeline::update`], and `_with_temperature`, `_with_speed`): never
//!   fails; a sample it cannot use (time not moving forward, a NaN or out-of-range reading, a
//!   missing temperature the model needs) is skipped and counted in [`Pipeline::report`]
//!   ([`InputReport`]); a rest window the stream passed without a reading is
//!   [`Pipeline::rest_window_missed`].
//! - **Block by block** ([`Pipeline::process_block`] with [`Outputs`]): a bad block is an
//!   [`Error`] naming the first bad sample by its index, and leaves the pipeline as it was.
//! - **Rests while driving**: [`Preset::Tracked`], with a speed per sample where there is one;
//!   [`Pipeline::rest_tracker`] and [`Pipeline::process_block_reporting`] give the rests found.
//! - **Heading fixes** (GNSS course, landmarks): [`FusedPipeline`], or [`Fusion`] on a rate of
//!   your own; a bad fix is a [`FusionError`] naming it.
//! - **Stop and resume** (`serde` feature): every state serialises and reads back bit for bit
//!   (with `serde_json`, enable its `float_roundtrip` feature; a binary format without
//!   `deserialize_any`, such as postcard on a small target, works as it is); a [`Pipeline`] or
//!   [`Fusion`] read back is checked as `new` checks a configuration, and its state against what
//!   valid input reaches.
//! - **One stage alone** ([`Integrator`], [`LowPass`], [`Hdr`], ...: the [`Stage`] trait) or a
//!   stage of your own ([`Kernel`], `tests/custom_stage.rs`).
#![cfg_attr(not(feature = "std"), no_std)]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod allan;
pub mod axis;
pub mod bias_walk;
mod block;
pub mod correction;
mod error;
pub mod fixes;
mod fixes_config;
mod fixes_covariance;
mod fixes_drift;
mod fixes_error;
mod fixes_output;
mod fixes_segment;
pub mod fixes_smooth;
pub mod fused;
pub mod hdr;
pub mod input;
pub mod integrate;
pub mod kernel;
mod lag_free;
pub mod lowpass;
pub mod pipeline;
pub mod rest;
pub mod rest_tracker;
#[cfg(feature = "serde")]
mod serde_checked;
#[cfg(feature = "serde")]
mod serde_float;
pub mod sim;
mod stage;
pub mod threshold;
mod validate;

pub use allan::Variance;
pub use axis::Up;
pub use block::{Downsample, DownsampleConfig};
pub use correction::{Correction, CorrectionConfig, StaticBias, TemperatureScale};
pub use error::Error;
pub use fixes::{
    Estimate, Fix, FixCounts, FixProblem, Fusion, FusionConfig, FusionError, FusionOutputs,
};
pub use fixes_smooth::{smooth, Knot};
pub use fused::{FusedOutputs, FusedPipeline, Samples};
pub use hdr::{Hdr, HdrConfig};
pub use input::{GapAction, InputPolicy, InputReport, NonFinite};
pub use integrate::{Integrator, IntegratorConfig, Method};
pub use kernel::{Kernel, Signal, Streaming};
pub use lowpass::{DeLag, LowPass, LowPassConfig};
pub use pipeline::{NoiseScaled, Output, Outputs, Pipeline, PipelineConfig, Preset};
#[cfg(feature = "std")]
pub use rest::static_bias_test_stoppable;
pub use rest::{static_bias_test, RestStatistics, StaticBiasTest};
pub use rest_tracker::{Rest, RestTracker, RestTrackerConfig};
pub use sim::{GyroModel, GyroModelConfig, GyroSample, TemperatureProfile};
pub use stage::{Clock, Stage};
pub use threshold::{Threshold, ThresholdConfig};
pub use validate::{check_block, MAX_READING, MAX_TIME, MIN_INTERVAL};

// The Rust examples of the README and of the docs' pages that hold them (engine.md, fixes_rust.md)
// compile and run with the doctests, one struct per page.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
struct ReadmeExamples;

#[cfg(doctest)]
#[doc = include_str!("../../docs/engine.md")]
struct EngineDocExamples;

#[cfg(doctest)]
#[doc = include_str!("../../docs/fixes_rust.md")]
struct FixesRustDocExamples;
