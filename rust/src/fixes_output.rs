//! What the heading-fix filter ([`Fusion`](crate::Fusion)) reports: its [`Estimate`] at one
//! time, and the per-sample [`FusionOutputs`] of a block, each written only where wanted.

use crate::fixes::FusionConfig;
use crate::fixes_segment::Segment;
use crate::fixes_smooth::Mat3;
use crate::stage::check_outputs;
use crate::Error;

/// The estimate at one time: heading and its standard deviation, and Hong eq 1's bias and scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Heading \[rad\], continuous (not wrapped).
    pub heading: f64,
    /// Its standard deviation \[rad\].
    pub heading_sigma: f64,
    /// Bias `b` \[rad/s\]: what the gyro reads at rest.
    pub bias: f64,
    /// Scale error `s`: the gyro reads `(1 + s)` times the true rate.
    pub scale: f64,
}

impl Estimate {
    /// The estimate of state `x = [psi, s_bar, b_bar]` with covariance `p` (Hong eq 3 to eq 1).
    pub(crate) fn of(x: &[f64; 3], p: &Mat3) -> Self {
        Estimate {
            heading: x[0],
            heading_sigma: sigma_of(p[0][0]),
            bias: bias_of(x),
            scale: scale_of(x),
        }
    }
}

/// The standard deviation of a heading variance: the root of its magnitude, as a variance that
/// rounds below 0 (its terms cancelling below what float64 resolves, where fixes are far tighter
/// than the gyro's noise) is within that rounding of 0, not a NaN sigma, nor a 0 that would claim
/// certainty; and no branch in a per-sample loop.
#[inline(always)]
pub(crate) fn sigma_of(variance: f64) -> f64 {
    libm::sqrt(variance.abs())
}

/// Hong eq 1's bias and scale error of state `x`: they change only at a fix (the propagation
/// moves the heading alone), so a segment between two fixes takes them once.
#[inline(always)]
pub(crate) fn calibration_of(x: &[f64; 3]) -> (f64, f64) {
    (bias_of(x), scale_of(x))
}

/// Hong eq 1's bias `b = -b_bar / s_bar` of state `x` (eq 3 inverted).
#[inline(always)]
fn bias_of(x: &[f64; 3]) -> f64 {
    -x[2] / x[1]
}

/// Hong eq 1's scale error `s = 1 / s_bar - 1` of state `x` (eq 3 inverted).
#[inline(always)]
fn scale_of(x: &[f64; 3]) -> f64 {
    1.0 / x[1] - 1.0
}

/// Output slices of [`Fusion::process_block`](crate::Fusion::process_block), one value per gyro
/// sample: the heading, and each other estimate where wanted (`None` is not computed; the sigma
/// takes a square root per sample, and each column a pass of stores).
#[derive(Debug)]
pub struct FusionOutputs<'a> {
    /// Heading \[rad\].
    pub heading: &'a mut [f64],
    /// Its standard deviation \[rad\].
    pub heading_sigma: Option<&'a mut [f64]>,
    /// Bias \[rad/s\].
    pub bias: Option<&'a mut [f64]>,
    /// Scale error.
    pub scale: Option<&'a mut [f64]>,
}

impl<'a> FusionOutputs<'a> {
    /// All four estimates.
    pub fn all(
        heading: &'a mut [f64],
        heading_sigma: &'a mut [f64],
        bias: &'a mut [f64],
        scale: &'a mut [f64],
    ) -> Self {
        FusionOutputs {
            heading,
            heading_sigma: Some(heading_sigma),
            bias: Some(bias),
            scale: Some(scale),
        }
    }

    /// The heading alone.
    pub fn heading(heading: &'a mut [f64]) -> Self {
        FusionOutputs {
            heading,
            heading_sigma: None,
            bias: None,
            scale: None,
        }
    }

    /// Fails unless every slice given holds `n` samples.
    pub(crate) fn check(&self, n: usize) -> Result<(), Error> {
        check_outputs(
            [
                ("heading", Some(&*self.heading)),
                ("heading_sigma", self.heading_sigma.as_deref()),
                ("bias", self.bias.as_deref()),
                ("scale", self.scale.as_deref()),
            ],
            n,
        )
    }

    /// The first `n` samples of each slice (all it has, after [`FusionOutputs::check`]), so that
    /// indexing below `n` needs no bounds check.
    #[inline(always)]
    pub(crate) fn first(&mut self, n: usize) -> FusionOutputs<'_> {
        FusionOutputs {
            heading: &mut self.heading[..n],
            heading_sigma: self.heading_sigma.as_deref_mut().map(|s| &mut s[..n]),
            bias: self.bias.as_deref_mut().map(|s| &mut s[..n]),
            scale: self.scale.as_deref_mut().map(|s| &mut s[..n]),
        }
    }

    /// Writes the estimate at `t` (the last point of `segment`) as sample `k`'s, where it is
    /// wanted, given the segment's [`Segment::calibration`] (taken once per segment). Unless
    /// `CALIBRATION`, the bias and scale are not asked for (a caller that wants neither runs a
    /// loop that does not test for them on every sample).
    #[inline(always)]
    pub(crate) fn set<const CALIBRATION: bool>(
        &mut self,
        k: usize,
        segment: &Segment,
        t: f64,
        config: &FusionConfig,
        calibration: (f64, f64),
    ) {
        self.heading[k] = segment.heading(t);
        if let Some(s) = &mut self.heading_sigma {
            s[k] = segment.heading_sigma(t, config);
        }
        if !CALIBRATION {
            return;
        }
        if let Some(s) = &mut self.bias {
            s[k] = calibration.0;
        }
        if let Some(s) = &mut self.scale {
            s[k] = calibration.1;
        }
    }

    /// Writes the estimate `e` as sample `k`'s, where it is wanted.
    #[inline(always)]
    pub(crate) fn set_estimate(&mut self, k: usize, e: &Estimate) {
        self.heading[k] = e.heading;
        for (column, value) in [
            (&mut self.heading_sigma, e.heading_sigma),
            (&mut self.bias, e.bias),
            (&mut self.scale, e.scale),
        ] {
            if let Some(s) = column {
                s[k] = value;
            }
        }
    }

    /// True if the bias or the scale is wanted.
    pub(crate) fn wants_calibration(&self) -> bool {
        self.bias.is_some() || self.scale.is_some()
    }
}
