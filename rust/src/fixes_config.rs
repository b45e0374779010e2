//! The settings of the heading-fix filter ([`Fusion`](crate::Fusion)): the gyro's noise (from
//! its Allan parameters), the uncertainty before the first fix, and the outlier gate.

use core::f64::consts::PI;

use crate::error::{check_magnitude, check_range};
use crate::integrate::check_initial_heading;
use crate::{Error, MAX_READING};

/// Noise settings and initial uncertainty of the filter.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FusionConfig {
    /// Angle random walk `N` \[rad/sqrt(s)\] (Allan deviation at 1 s of the rate), >= 0.
    pub arw: f64,
    /// Rate random walk `K` of the bias \[rad/s/sqrt(s)\], >= 0.
    pub bias_walk: f64,
    /// Random walk of the scale error \[1/sqrt(s)\], >= 0.
    pub scale_walk: f64,
    /// Heading before the first fix \[rad\], finite and within +-2^20 (the pipeline's limit,
    /// [`IntegratorConfig::validate`](crate::IntegratorConfig::validate)).
    pub initial_heading: f64,
    /// Its standard deviation \[rad\], > 0 (pi: unknown).
    pub initial_heading_sigma: f64,
    /// Bias (Hong eq 1's `b`, what the gyro reads at rest) before any fix \[rad/s\].
    pub initial_bias: f64,
    /// Its standard deviation \[rad/s\], > 0 and at most 1000, the range of the bias itself.
    pub initial_bias_sigma: f64,
    /// Standard deviation of the scale error `s` before any fix, in (0, 0.5].
    pub initial_scale_sigma: f64,
    /// Outlier gate: a fix whose innovation squared over its variance exceeds this is rejected
    /// (> 0; 10.83 rejects 0.1 % of good fixes; infinity turns the gate off).
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_float"))]
    pub gate: f64,
    /// Re-admission \[s\]: when the gate has rejected every fix for this long (from the first it
    /// rejected), the filter takes its own certainty to be what is wrong: the next fix within
    /// [`READMIT_REACH`] gate radii that is at least the [`READMIT_MIN_REJECTED`]th in a row to
    /// fail the gate (two rejected before it) is applied with the heading's variance raised to
    /// let it pass and the bias's and scale's raised back to their initial ones (>= 0; infinity:
    /// never, the gate alone). A gap in the fixes longer than [`READMIT_GAP`] times their
    /// interval and half of this (an outage) counts in a run of rejections' length as no more.
    /// A fix beyond the reach is re-admitted too where the run's innovations drift steadily away
    /// from within it (a filter far too sure of a wrong bias; rust/src/fixes_drift.rs).
    #[cfg_attr(
        feature = "serde",
        serde(with = "crate::serde_float", default = "never")
    )]
    pub readmit_after: f64,
}

/// The fewest fixes in a row that fail the gate, counting the last of them, the one the filter
/// re-admits (`readmit_after`; two rejected before it): two would let one stray fix on each side
/// of an outage reset the heading.
pub const READMIT_MIN_REJECTED: u64 = 3;

/// The longest gap between two fixes counted whole in a run of rejections, in multiples of the
/// shortest interval between two fixes so far (and at least half of `readmit_after`, the gap
/// that lets [`READMIT_MIN_REJECTED`] fixes span it): a longer one is an outage, which holds no
/// rejection and counts in the run's length as this longest gap, so two stray fixes before a
/// tunnel and one after it are not a lock-out.
pub const READMIT_GAP: f64 = 3.0;

/// How far beyond the gate a fix may lie and still be re-admitted, in multiples of the gate's
/// radius: a filter locked out by its own certainty sees the fixes a few gate radii off (its
/// heading's sigma grows with the bias it no longer corrects, as its error does), while a
/// receiver's lasting wrong course (a reflection, reversing) lies tens of radii off.
pub const READMIT_REACH: f64 = 4.0;

/// A configuration stored before re-admission existed reads back without it; a filter stored
/// before the fixes' interval was kept reads back as one that has seen none.
#[cfg(feature = "serde")]
pub(crate) fn never() -> f64 {
    f64::INFINITY
}

/// The largest initial bias and initial bias sigma \[rad/s\]: far beyond any gyro's.
pub(crate) const MAX_INITIAL_BIAS: f64 = 1e3;

/// The smallest standard deviation of a fix \[rad\] (about 2e-10 deg): its square stays a normal
/// number, so an innovation's variance is never 0.
pub const MIN_FIX_SIGMA: f64 = 1e-12;

impl Default for FusionConfig {
    /// A consumer MEMS gyro on a car: the noise settings every fold chose leave-one-log-out
    /// over the twelve KITTI logs with fixes of 1, 0.3 and 0.1 deg (docs/fixes_results.md; the
    /// twins' true `N` is 5.2e-4, `K` 8.7e-5: `arw` also covers what the model lacks between
    /// fixes, the rate's lag and interpolated stretches, which finer fixes reveal), unknown
    /// initial heading, bias within about 1 deg/s, scale within 5 %.
    fn default() -> Self {
        FusionConfig {
            arw: 1e-2,
            bias_walk: 2e-5,
            scale_walk: 1e-5,
            initial_heading: 0.0,
            initial_heading_sigma: PI,
            initial_bias: 0.0,
            initial_bias_sigma: 0.02,
            initial_scale_sigma: 0.05,
            gate: 10.83,
            readmit_after: 60.0,
        }
    }
}

impl FusionConfig {
    /// Checks every parameter (the error names it).
    pub fn validate(&self) -> Result<(), Error> {
        check_magnitude("arw", self.arw)?;
        check_magnitude("bias_walk", self.bias_walk)?;
        check_magnitude("scale_walk", self.scale_walk)?;
        let sigma = "> 0 and at most 2^20";
        // the pipeline's limit, where a sample's increment still counts
        check_initial_heading(self.initial_heading)?;
        let (least, most) = (f64::MIN_POSITIVE, MAX_READING);
        check_range(
            "initial_heading_sigma",
            self.initial_heading_sigma,
            least,
            most,
            sigma,
        )?;
        check_range(
            "initial_bias",
            self.initial_bias,
            -MAX_INITIAL_BIAS,
            MAX_INITIAL_BIAS,
            "within +-1000 rad/s",
        )?;
        // Within the bias's own range: 1e6 rad/s beside an unknown heading (sigma 2^20) left the
        // first fix's covariance to rounding (a variance of -1e-4, a NaN heading sigma for good).
        check_range(
            "initial_bias_sigma",
            self.initial_bias_sigma,
            least,
            MAX_INITIAL_BIAS,
            "> 0 and at most 1000 rad/s (the range of initial_bias)",
        )?;
        // s_bar = 1/(1+s) must stay away from 0 for eq 1's b and s to exist.
        let scale = "> 0 and at most 0.5";
        check_range(
            "initial_scale_sigma",
            self.initial_scale_sigma,
            f64::MIN_POSITIVE,
            0.5,
            scale,
        )?;
        check_range(
            "gate",
            self.gate,
            f64::MIN_POSITIVE,
            f64::INFINITY,
            "> 0 (inf: no gate)",
        )?;
        check_range(
            "readmit_after",
            self.readmit_after,
            0.0,
            f64::INFINITY,
            ">= 0 s (inf: never)",
        )
    }
}
