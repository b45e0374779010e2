//! The core behind `gyrocore.Pipeline`: the pipeline alone, or with its heading-fix stage (the
//! core's `FusedPipeline`) and the fixes given ahead of the samples that reach them.

use gyrocore::{
    check_block, Error, Fix, FusedOutputs, FusedPipeline, FusionError, Outputs, Pipeline,
    PipelineConfig, Rest, Samples,
};
use numpy::PyReadonlyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::ops::Range;

use crate::arrays::{fill_some, output, slice, zeros, Array};
use crate::fixes::{config_from, fixes_from, fusion_error, renumbered};
use crate::interrupt::{detach_watched, pieces, Stop, PIECE};
use crate::pending::Pending;
use crate::value_error;

/// The names of the caller's output arrays, as the binding's `out` holds them.
const OUT: [&str; 3] = ["out[0] (heading)", "out[1] (rate)", "out[2] (drift)"];

/// Output `i` (0 heading, 1 rate, 2 drift) with its name, if there is one.
fn named<'a, 'py>(i: usize, a: Option<&'a Array<'py>>) -> Option<(&'static str, &'a Array<'py>)> {
    a.map(|a| (OUT[i], a))
}

/// The pipeline, with or without the fix stage (boxed: each is a few kB).
#[derive(Clone)]
pub(crate) enum Core {
    Plain(Box<Pipeline>),
    Fused {
        inner: Box<FusedPipeline>,
        /// Fixes after the last block's last sample, for the next block.
        pending: Pending,
    },
}

/// A block's samples as the binding received them.
#[derive(Clone, Copy)]
pub(crate) struct Block<'a> {
    pub(crate) t: &'a [f64],
    pub(crate) rate: &'a [f64],
    pub(crate) temperature: Option<&'a [f64]>,
    pub(crate) speed: Option<&'a [f64]>,
}

impl<'a> Block<'a> {
    /// Times and rates alone.
    pub(crate) fn new(t: &'a [f64], rate: &'a [f64]) -> Self {
        Block {
            t,
            rate,
            temperature: None,
            speed: None,
        }
    }

    /// The block of a call's arrays, each contiguous float64 (else an error naming it).
    pub(crate) fn of(
        t: &'a PyReadonlyArray1<'_, f64>,
        rate: &'a PyReadonlyArray1<'_, f64>,
        temperature: Option<&'a PyReadonlyArray1<'_, f64>>,
        speed: Option<&'a PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Self> {
        Ok(Block {
            t: slice("t", t)?,
            rate: slice("rate", rate)?,
            temperature: temperature.map(|a| slice("temperature", a)).transpose()?,
            speed: speed.map(|a| slice("speed", a)).transpose()?,
        })
    }

    /// Runs `f` on the block piece by piece, in order, each with its range of samples, until
    /// `stop` is requested or a piece fails (the core then puts back that piece; the caller the
    /// pieces before). A block whose arrays differ in length goes whole: the core names that.
    pub(crate) fn pieces<E>(
        &self,
        stop: &Stop,
        mut f: impl FnMut(Block<'_>, Range<usize>) -> Result<(), E>,
    ) -> Result<(), E> {
        let n = self.t.len();
        let others = [Some(self.rate), self.temperature, self.speed];
        if others.iter().flatten().any(|a| a.len() != n) {
            return f(*self, 0..n);
        }
        pieces(n, stop, |range| {
            let part = |a: &'a [f64]| &a[range.clone()];
            let piece = Block {
                t: part(self.t),
                rate: part(self.rate),
                temperature: self.temperature.map(part),
                speed: self.speed.map(part),
            };
            f(piece, range)
        })
    }

    /// [`Block::pieces`] without the GIL, watched for a Ctrl-C (see [`detach_watched`]); a
    /// piece's error names its sample counted from the block's first.
    pub(crate) fn watched_pieces(
        &self,
        py: Python<'_>,
        mut f: impl FnMut(Block<'_>, Range<usize>) -> Result<(), Error> + Send,
    ) -> PyResult<Result<(), Error>> {
        detach_watched(py, self.t.len(), |stop| {
            self.pieces(stop, |piece, range| {
                let start = range.start;
                f(piece, range).map_err(|e| e.with_index_offset(start))
            })
        })
    }

    /// The core's checks of `piece`, the samples `range` of this block ([`check_block`]), after
    /// the last time of the piece before it, as a pipeline checks a block.
    pub(crate) fn check_piece(&self, piece: Block<'_>, range: &Range<usize>) -> Result<(), Error> {
        let previous = range.start.checked_sub(1).map(|i| self.t[i]);
        check_block(piece.t, piece.rate, piece.temperature, previous, true)
    }

    /// [`Block::pieces`] for a filter that takes fixes: `f` gets each piece with the fixes no piece
    /// before it used and returns how many it used. Returns how many all used; a piece's error as
    /// the whole block's (its sample and fix indices counted from the block's first).
    pub(crate) fn pieces_with_fixes(
        &self,
        stop: &Stop,
        fixes: &[Fix],
        mut f: impl FnMut(Block<'_>, Range<usize>, &[Fix]) -> Result<usize, FusionError>,
    ) -> Result<usize, FusionError> {
        let mut used = 0;
        self.pieces(stop, |piece, range| {
            let start = range.start;
            used += f(piece, range, &fixes[used..]).map_err(|e| of_block(e, start, used))?;
            Ok::<(), FusionError>(())
        })?;
        Ok(used)
    }
}

/// The samples `range` of an output, if it is asked for.
pub(crate) fn part<'a>(
    out: &'a mut Option<&mut [f64]>,
    range: &Range<usize>,
) -> Option<&'a mut [f64]> {
    out.as_deref_mut().map(|o| &mut o[range.clone()])
}

/// The error of a piece that starts at sample `start`, `used` fixes after the block's first, as
/// the whole block's.
fn of_block(e: FusionError, start: usize, used: usize) -> FusionError {
    match e {
        FusionError::Gyro(e) => FusionError::Gyro(e.with_index_offset(start)),
        FusionError::Fix {
            index,
            what,
            value,
            problem,
        } => FusionError::Fix {
            index: index + used,
            what,
            value,
            problem,
        },
    }
}

/// The fix stage's columns of a block: heading sigma, bias, scale (each None unless asked for),
/// and the fix counts (applied, rejected, re-admitted, before the first sample, waiting for a later
/// block).
pub(crate) type FusedColumns<'py> = (
    Option<Array<'py>>,
    Option<Array<'py>>,
    Option<Array<'py>>,
    (u64, u64, u64, u64, usize),
);

/// Which outputs a block computes: the pipeline's (rate, drift) and the fix stage's (heading
/// sigma, bias, scale); the heading always. `given` are the caller's arrays for (heading, rate,
/// drift) to fill instead of fresh ones (see [`output`]).
pub(crate) struct Wanted<'py> {
    pub(crate) pipeline: (bool, bool),
    pub(crate) fixes: (bool, bool, bool),
    pub(crate) given: Option<[Option<Array<'py>>; 3]>,
}

/// What a block gives: heading, rate, drift (rate and drift None unless asked for), and the fix
/// stage's columns with it.
pub(crate) type Processed<'py> = (
    Array<'py>,
    Option<Array<'py>>,
    Option<Array<'py>>,
    Option<FusedColumns<'py>>,
);

impl Core {
    /// The pipeline (its configuration, bias, tracker, report).
    pub(crate) fn pipeline(&self) -> &Pipeline {
        match self {
            Core::Plain(p) => p,
            Core::Fused { inner, .. } => inner.pipeline(),
        }
    }

    /// Back to the state before the first sample (a fix stage stays, without its fixes).
    pub(crate) fn reset(&mut self) {
        match self {
            Core::Plain(p) => p.reset(),
            Core::Fused { inner, pending } => {
                inner.reset();
                pending.clear();
            }
        }
    }

    /// Restarts the clock (the core's `Pipeline::restart_clock`, `FusedPipeline::restart_clock`):
    /// the fixes waiting for later samples are on the old clock and are dropped; returns how
    /// many. Refused in the rest window, nothing changed.
    pub(crate) fn restart_clock(&mut self) -> Result<usize, Error> {
        match self {
            Core::Plain(p) => p.restart_clock().map(|()| 0),
            // before the first sample there is no old clock: the fixes wait on
            Core::Fused { inner, .. } if inner.pipeline().last_time().is_none() => Ok(0),
            Core::Fused { inner, pending } => {
                inner.restart_clock()?;
                let dropped = pending.len();
                pending.clear();
                Ok(dropped)
            }
        }
    }

    /// Adds the fix stage with `settings` to a pipeline that has no sample yet.
    pub(crate) fn start_fusion(&mut self, settings: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let config: PipelineConfig = *self.pipeline().config();
        if self.pipeline().last_time().is_some() || matches!(self, Core::Fused { .. }) {
            return Err(PyValueError::new_err(
                "the fix stage starts before the first sample, once",
            ));
        }
        let inner = FusedPipeline::new(config, config_from(settings)?).map_err(value_error)?;
        let inner = Box::new(inner);
        *self = Core::Fused {
            inner,
            pending: Pending::default(),
        };
        Ok(())
    }

    /// Runs a block; `fixes` (t, heading, sigma) only with the fix stage; `wanted` says which
    /// outputs are asked for and which arrays of the caller's are filled. Errors count sample
    /// indices from `index_offset`. A long block goes piece by piece and stops at a Ctrl-C (see
    /// [`interrupt`](crate::interrupt)); after any error, the interrupt's too, the state is as
    /// before the block.
    pub(crate) fn process<'py>(
        &mut self,
        py: Python<'py>,
        block: &Block<'_>,
        fixes: Option<[PyReadonlyArray1<'py, f64>; 3]>,
        wanted: Wanted<'py>,
        index_offset: usize,
        on_rest: &mut (dyn FnMut(Rest) + Send),
    ) -> PyResult<Processed<'py>> {
        // The core puts back the one piece it refuses; this puts back the pieces before it.
        let before = (block.t.len() > PIECE).then(|| self.clone());
        let result = self.process_pieces(py, block, fixes, wanted, index_offset, on_rest);
        if let (Err(_), Some(before)) = (&result, before) {
            *self = before;
        }
        result
    }

    /// [`Core::process`] but for putting back the state after an error.
    fn process_pieces<'py>(
        &mut self,
        py: Python<'py>,
        block: &Block<'_>,
        fixes: Option<[PyReadonlyArray1<'py, f64>; 3]>,
        wanted: Wanted<'py>,
        index_offset: usize,
        on_rest: &mut (dyn FnMut(Rest) + Send),
    ) -> PyResult<Processed<'py>> {
        let n = block.t.len();
        let [given_heading, given_rate, given_drift] = wanted.given.unwrap_or_default();
        let outputs = wanted.pipeline;
        let heading = output(py, OUT[0], given_heading, n, true)?.unwrap_or_else(|| zeros(py, n));
        let out_rate = output(py, OUT[1], given_rate, n, outputs.0)?;
        let drift = output(py, OUT[2], given_drift, n, outputs.1)?;
        let (inner, pending) = match self {
            Core::Plain(pipeline) => {
                if fixes.is_some() {
                    return Err(PyValueError::new_err(
                        "fixes given to a pipeline without a fix stage",
                    ));
                }
                fill_some(
                    [
                        named(0, Some(&heading)),
                        named(1, out_rate.as_ref()),
                        named(2, drift.as_ref()),
                    ],
                    |[mut h, mut r, mut d]| {
                        block.watched_pieces(py, |piece, range| {
                            let out = Outputs {
                                heading: part(&mut h, &range),
                                rate: part(&mut r, &range),
                                drift: part(&mut d, &range),
                            };
                            pipeline.process_block_reporting(
                                piece.t,
                                piece.rate,
                                piece.temperature,
                                piece.speed,
                                out,
                                on_rest,
                            )
                        })
                    },
                )??
                .map_err(|e| value_error(e.with_index_offset(index_offset)))?;
                return Ok((heading, out_rate, drift, None));
            }
            Core::Fused { inner, pending } => (inner, pending),
        };
        let new = match &fixes {
            Some([ft, fh, fs]) => fixes_from(ft, fh, fs)?,
            None => Vec::new(),
        };
        // The filter runs on the corrected rate: it is computed whether asked for or not.
        let rate_column = out_rate.unwrap_or_else(|| zeros(py, n));
        let wanted_array = |on: bool| on.then(|| zeros(py, n));
        let (fs, fb, fsc) = wanted.fixes;
        let (sigma, bias, scale) = (wanted_array(fs), wanted_array(fb), wanted_array(fsc));
        let mark = pending.append(new);
        let waiting = pending.waiting();
        let result = fill_some(
            [
                named(0, Some(&heading)),
                named(1, Some(&rate_column)),
                sigma.as_ref().map(|a| ("heading_sigma", a)),
                bias.as_ref().map(|a| ("bias", a)),
                scale.as_ref().map(|a| ("scale", a)),
                named(2, drift.as_ref()),
            ],
            |[mut h, mut r, mut s, mut bi, mut sc, mut dr]| {
                detach_watched(py, n, |stop| {
                    block.pieces_with_fixes(stop, waiting, |piece, range, fixes| {
                        let out = FusedOutputs {
                            heading: part(&mut h, &range).unwrap_or_default(),
                            heading_sigma: part(&mut s, &range),
                            bias: part(&mut bi, &range),
                            scale: part(&mut sc, &range),
                            rate: part(&mut r, &range).unwrap_or_default(),
                            drift: part(&mut dr, &range),
                        };
                        let samples = Samples {
                            t: piece.t,
                            rate: piece.rate,
                            temperature: piece.temperature,
                            speed: piece.speed,
                        };
                        inner.process_block_reporting(samples, fixes, out, on_rest)
                    })
                })
            },
        )
        .and_then(|watched| watched);
        // A failed block changes nothing: its new fixes go again.
        let used = match result {
            Ok(Ok(used)) => used,
            Ok(Err(e)) => {
                let before = pending.before(mark);
                pending.undo(mark);
                return Err(match e {
                    gyrocore::FusionError::Gyro(e) => {
                        value_error(e.with_index_offset(index_offset))
                    }
                    e => renumbered(py, before, fusion_error(e)),
                });
            }
            Err(e) => {
                pending.undo(mark);
                return Err(e);
            }
        };
        pending.consume(used);
        let c = inner.counts();
        let counts = (
            c.applied,
            c.rejected,
            c.readmitted,
            c.before_start,
            pending.len(),
        );
        let out_rate = outputs.0.then_some(rate_column);
        Ok((heading, out_rate, drift, Some((sigma, bias, scale, counts))))
    }

    /// The complete state as JSON (the plain pipeline's as before the fix stage existed).
    pub(crate) fn state_json(&self) -> PyResult<String> {
        match self {
            Core::Plain(p) => serde_json::to_string(p),
            Core::Fused { inner, pending } => serde_json::to_string(&(inner, pending.waiting())),
        }
        .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// Rebuilds from [`Core::state_json`]. The two shapes are told apart by their first
    /// character (an object, or the fused pair as an array), so that a damaged state is refused
    /// with its own reason, not the other shape's.
    pub(crate) fn from_state_json(state: &str) -> PyResult<Self> {
        let refused = |e: serde_json::Error| {
            PyValueError::new_err(format!("not a gyrocore pipeline state: {e}"))
        };
        if !state.trim_start().starts_with('[') {
            return Ok(Core::Plain(Box::new(
                serde_json::from_str(state).map_err(refused)?,
            )));
        }
        let (inner, pending): (Box<FusedPipeline>, Vec<Fix>) =
            serde_json::from_str(state).map_err(refused)?;
        Ok(Core::Fused {
            inner,
            pending: pending.into(),
        })
    }
}
