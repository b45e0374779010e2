//! What the pipeline writes: one [`Output`] per sample, into the slices an [`Outputs`] names.

use crate::kernel::Signal;
use crate::stage::check_outputs;
use crate::Error;

/// Per-sample output of the pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Output {
    /// Continuous heading \[rad\], counter-clockwise positive.
    pub heading: f64,
    /// Corrected (and de-lagged) rate that was integrated [rad/s].
    pub rate: f64,
    /// HDR's drift estimate `-I` applied to this sample [rad/s] (0 without HDR).
    pub drift: f64,
}

impl Output {
    /// What the pipeline reports of a signal that passed the whole chain.
    #[inline(always)]
    pub(super) fn of(y: Signal) -> Self {
        Output {
            heading: y.heading,
            rate: y.rate,
            drift: y.drift,
        }
    }
}

/// Where [`Pipeline::process_block`](super::Pipeline::process_block) writes its outputs: each slice as long as the input, or
/// `None` for an output the caller does not need (it then costs nothing to fill).
#[derive(Debug, Default)]
pub struct Outputs<'a> {
    /// Receives [`Output::heading`].
    pub heading: Option<&'a mut [f64]>,
    /// Receives [`Output::rate`].
    pub rate: Option<&'a mut [f64]>,
    /// Receives [`Output::drift`].
    pub drift: Option<&'a mut [f64]>,
}

impl<'a> Outputs<'a> {
    /// All three outputs.
    pub fn all(heading: &'a mut [f64], rate: &'a mut [f64], drift: &'a mut [f64]) -> Self {
        Outputs {
            heading: Some(heading),
            rate: Some(rate),
            drift: Some(drift),
        }
    }

    /// The heading alone.
    pub fn heading(heading: &'a mut [f64]) -> Self {
        Outputs {
            heading: Some(heading),
            ..Outputs::default()
        }
    }

    /// Fails unless every slice given holds `n` samples.
    pub(super) fn check(&self, n: usize) -> Result<(), Error> {
        check_outputs(
            [
                ("heading", self.heading.as_deref()),
                ("rate out", self.rate.as_deref()),
                ("drift", self.drift.as_deref()),
            ],
            n,
        )
    }

    /// The first `n` samples of each slice (all it has, after [`Outputs::check`]).
    #[inline(always)]
    pub(super) fn first(&mut self, n: usize) -> Outputs<'_> {
        Outputs {
            heading: self.heading.as_deref_mut().map(|s| &mut s[..n]),
            rate: self.rate.as_deref_mut().map(|s| &mut s[..n]),
            drift: self.drift.as_deref_mut().map(|s| &mut s[..n]),
        }
    }

    /// Writes sample `i`'s output where it is wanted.
    #[inline(always)]
    pub(super) fn set(&mut self, i: usize, o: Output) {
        if let Some(s) = &mut self.heading {
            s[i] = o.heading;
        }
        if let Some(s) = &mut self.rate {
            s[i] = o.rate;
        }
        if let Some(s) = &mut self.drift {
            s[i] = o.drift;
        }
    }
}
