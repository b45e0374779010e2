//! Bindings of the heading-fix filter and its smoother (`gyrocore.fixes` documents the Python
//! API). Settings arrive as a flat dict of SI values named like the core's `FusionConfig`.

use gyrocore::fixes_smooth::Knot;
use gyrocore::{smooth, Fix, FixCounts, Fusion, FusionConfig, FusionError, FusionOutputs};
use numpy::PyReadonlyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{fill, slice, zeros, Array};
use crate::fused::{part, Block};
use crate::interrupt::{detach_watched, Stop, PIECE};
use crate::pending::Pending;
use crate::settings::{names, set_all, values, Field};
use crate::{value_error, SampleError};

/// The settings keys, with their units and fields (the core's `FusionConfig`).
const FIELDS: &[Field<FusionConfig>] = &[
    ("arw", "angle random walk N [rad/sqrt(s)]", |c| &mut c.arw),
    (
        "bias_walk",
        "rate random walk K of the bias [rad/s/sqrt(s)]",
        |c| &mut c.bias_walk,
    ),
    (
        "scale_walk",
        "random walk of the scale error [1/sqrt(s)]",
        |c| &mut c.scale_walk,
    ),
    (
        "initial_heading",
        "heading before the first fix [rad]",
        |c| &mut c.initial_heading,
    ),
    (
        "initial_heading_sigma",
        "its standard deviation [rad]",
        |c| &mut c.initial_heading_sigma,
    ),
    ("initial_bias", "bias before any fix [rad/s]", |c| {
        &mut c.initial_bias
    }),
    (
        "initial_bias_sigma",
        "its standard deviation [rad/s]",
        |c| &mut c.initial_bias_sigma,
    ),
    (
        "initial_scale_sigma",
        "standard deviation of the scale error before any fix [1]",
        |c| &mut c.initial_scale_sigma,
    ),
    (
        "gate",
        "outlier gate on the innovation squared over its variance [1]",
        |c| &mut c.gate,
    ),
    (
        "readmit_after",
        "fixes re-admitted after the gate has rejected them this long [s]",
        |c| &mut c.readmit_after,
    ),
];

/// The core configuration from the settings dict (defaults for the keys it lacks).
pub(crate) fn config_from(settings: Option<&Bound<'_, PyDict>>) -> PyResult<FusionConfig> {
    let mut c = FusionConfig::default();
    if let Some(settings) = settings {
        set_all(&mut c, settings, FIELDS, "fusion setting")?;
    }
    c.validate().map_err(value_error)?;
    Ok(c)
}

pub(crate) fn fusion_error(e: FusionError) -> PyErr {
    match e {
        FusionError::Gyro(e) => value_error(e),
        e => PyValueError::new_err(e.to_string()),
    }
}

/// Fixes from three arrays of one length.
pub(crate) fn fixes_from(
    t: &PyReadonlyArray1<'_, f64>,
    heading: &PyReadonlyArray1<'_, f64>,
    sigma: &PyReadonlyArray1<'_, f64>,
) -> PyResult<Vec<Fix>> {
    let (t, h, s) = (
        slice("fix t", t)?,
        slice("fix heading", heading)?,
        slice("fix sigma", sigma)?,
    );
    if h.len() != t.len() || s.len() != t.len() {
        return Err(PyValueError::new_err(format!(
            "fix t, heading and sigma must have one length, got {}, {} and {}",
            t.len(),
            h.len(),
            s.len()
        )));
    }
    Ok(t.iter()
        .zip(h)
        .zip(s)
        .map(|((&t, &heading), &sigma)| Fix { t, heading, sigma })
        .collect())
}

fn counts_dict<'py>(
    py: Python<'py>,
    c: FixCounts,
    after_end: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("applied", c.applied)?;
    d.set_item("rejected", c.rejected)?;
    d.set_item("readmitted", c.readmitted)?;
    d.set_item("before_start", c.before_start)?;
    d.set_item("after_end", after_end)?;
    Ok(d)
}

type Columns<'py> = (Array<'py>, Array<'py>, Array<'py>, Array<'py>);

/// Runs the filter over one block into four new arrays: its estimates, or with `knots` the
/// smoothed ones (a forward pass recording the knots, the backward pass over them, and a second
/// forward pass of a fresh filter writing the smoothed estimates). A Ctrl-C stops a long block
/// (see [`interrupt`](crate::interrupt)) between pieces of a forward pass. `series`: the block
/// is a whole series (`fuse`), whose step back is a log's to mend, not a stream's to restart.
fn run<'py>(
    py: Python<'py>,
    fusion: &mut Fusion,
    t: &[f64],
    rate: &[f64],
    fixes: &[Fix],
    knots: Option<&mut Vec<Knot>>,
    series: bool,
) -> PyResult<(Columns<'py>, usize)> {
    let n = t.len();
    let cols = (zeros(py, n), zeros(py, n), zeros(py, n), zeros(py, n));
    let used = fill([&cols.0, &cols.1, &cols.2, &cols.3], |[h, s, b, sc]| {
        detach_watched(py, n, |stop| {
            let samples = (t, rate, fixes);
            let Some(knots) = knots else {
                return forward(samples, stop, [h, s, b, sc], |t, r, f, o| {
                    fusion.process_block(t, r, f, o)
                });
            };
            let mut again = Fusion::new(*fusion.config())?;
            // The smoother overwrites every column: the forward pass writes one.
            forward(samples, stop, [&mut *h], |t, r, f, o| {
                fusion.process_block_recording(t, r, f, o, |k| knots.push(k))
            })?;
            if stop.requested() {
                return Ok(0);
            }
            // Singular knots cannot happen with validated settings (all variances > 0).
            smooth(knots);
            // The knots are found by the count of fixes applied, whatever the pieces.
            forward(samples, stop, [h, s, b, sc], |t, r, f, o| {
                again.process_block_smoothed(t, r, f, knots, o)
            })
        })
    })??
    .map_err(|e| fusion_error(if series { e.of_series() } else { e }))?;
    Ok((cols, used))
}

/// `step` (a filter's block call) over (t, rate, fixes) piece by piece until `stop`, into the
/// columns `out` (heading, then heading sigma, bias and scale where given): the number of fixes
/// used, and errors as one call's.
fn forward<const N: usize>(
    (t, rate, fixes): (&[f64], &[f64], &[Fix]),
    stop: &Stop,
    out: [&mut [f64]; N],
    mut step: impl FnMut(&[f64], &[f64], &[Fix], FusionOutputs<'_>) -> Result<usize, FusionError>,
) -> Result<usize, FusionError> {
    let mut out = out.map(Some);
    let block = Block::new(t, rate);
    block.pieces_with_fixes(stop, fixes, |piece, range, fixes| {
        let mut columns = out.iter_mut().map(|o| part(o, &range));
        let estimates = FusionOutputs {
            heading: columns.next().flatten().unwrap_or_default(),
            heading_sigma: columns.next().flatten(),
            bias: columns.next().flatten(),
            scale: columns.next().flatten(),
        };
        step(piece.t, piece.rate, fixes, estimates)
    })
}

/// Whole-log fusion: (heading, heading_sigma, bias, scale, counts), causal or smoothed.
#[pyfunction]
#[pyo3(signature = (t, rate, fix_t, fix_heading, fix_sigma, settings=None, smoothed=false))]
#[allow(clippy::too_many_arguments)]
fn fuse<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
    rate: PyReadonlyArray1<'py, f64>,
    fix_t: PyReadonlyArray1<'py, f64>,
    fix_heading: PyReadonlyArray1<'py, f64>,
    fix_sigma: PyReadonlyArray1<'py, f64>,
    settings: Option<&Bound<'py, PyDict>>,
    smoothed: bool,
) -> PyResult<(
    Array<'py>,
    Array<'py>,
    Array<'py>,
    Array<'py>,
    Bound<'py, PyDict>,
)> {
    let mut fusion = Fusion::new(config_from(settings)?).map_err(value_error)?;
    let fixes = fixes_from(&fix_t, &fix_heading, &fix_sigma)?;
    // A whole log checks every fix given, those after its last sample too (a block of a stream
    // checks the ones it reaches).
    fusion.check_fixes(&fixes).map_err(fusion_error)?;
    let (t, rate) = (slice("t", &t)?, slice("rate", &rate)?);
    let mut knots = Vec::new();
    let knots = smoothed.then_some(&mut knots);
    let (cols, used) = run(py, &mut fusion, t, rate, &fixes, knots, true)?;
    let counts = counts_dict(py, fusion.counts(), fixes.len() - used)?;
    Ok((cols.0, cols.1, cols.2, cols.3, counts))
}

/// The streaming filter with the fixes given ahead of the samples that reach them.
#[pyclass(module = "gyrocore._gyrocore", name = "Fusion")]
#[derive(Clone)]
struct PyFusion {
    inner: Fusion,
    pending: Pending,
}

/// Names the fix as the caller numbered it: the new ones follow the `pending` ones. A bad gyro
/// sample's `SampleError` keeps its class, `index` and `what` (only its words grow), so a caller
/// catches it alike whether or not fixes were waiting.
pub(crate) fn renumbered(py: Python<'_>, pending: usize, e: PyErr) -> PyErr {
    match e.value(py).str() {
        Ok(m) if pending > 0 => {
            let words = format!(
                "{m} (fix numbers count {pending} fixes still waiting from earlier calls first)"
            );
            if !e.is_instance_of::<SampleError>(py) {
                return PyValueError::new_err(words);
            }
            match e.value(py).setattr("args", (words,)) {
                Ok(()) => e,
                Err(set) => set,
            }
        }
        _ => e,
    }
}

#[pymethods]
impl PyFusion {
    #[new]
    #[pyo3(signature = (settings=None))]
    fn new(settings: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let inner = Fusion::new(config_from(settings)?).map_err(value_error)?;
        Ok(PyFusion {
            inner,
            pending: Pending::default(),
        })
    }

    /// Processes a block with new fixes (after any given before); returns (heading,
    /// heading_sigma, bias, scale). Fixes after the block's last sample wait for the next block.
    fn process<'py>(
        &mut self,
        py: Python<'py>,
        t: PyReadonlyArray1<'py, f64>,
        rate: PyReadonlyArray1<'py, f64>,
        fix_t: PyReadonlyArray1<'py, f64>,
        fix_heading: PyReadonlyArray1<'py, f64>,
        fix_sigma: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Columns<'py>> {
        let (t, rate) = (slice("t", &t)?, slice("rate", &rate)?);
        // The core puts back the one piece it refuses; this the pieces before (and a Ctrl-C's).
        let before = (t.len() > PIECE).then_some(self.inner);
        let mark = self
            .pending
            .append(fixes_from(&fix_t, &fix_heading, &fix_sigma)?);
        match run(
            py,
            &mut self.inner,
            t,
            rate,
            self.pending.waiting(),
            None,
            false,
        ) {
            Ok((cols, used)) => {
                self.pending.consume(used);
                Ok(cols)
            }
            Err(e) => {
                if let Some(before) = before {
                    self.inner = before;
                }
                let waiting = self.pending.before(mark);
                self.pending.undo(mark);
                Err(renumbered(py, waiting, e))
            }
        }
    }

    /// Checks the waiting fixes and new ones, every one, processing nothing: the error the first
    /// bad one gives when a block reaches it.
    fn check(
        &mut self,
        py: Python<'_>,
        fix_t: PyReadonlyArray1<'_, f64>,
        fix_heading: PyReadonlyArray1<'_, f64>,
        fix_sigma: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<()> {
        let mark = self
            .pending
            .append(fixes_from(&fix_t, &fix_heading, &fix_sigma)?);
        let checked = self.inner.check_fixes(self.pending.waiting());
        let before = self.pending.before(mark);
        self.pending.undo(mark);
        checked.map_err(|e| renumbered(py, before, fusion_error(e)))
    }

    /// Restarts the clock (the core's `Fusion::restart_clock`) and drops the waiting fixes, which
    /// are on the old clock; returns how many, or None before the first sample (nothing to
    /// restart: the fixes wait on).
    fn restart_clock(&mut self) -> Option<usize> {
        self.inner.last_time()?;
        self.inner.restart_clock();
        let dropped = self.pending.len();
        self.pending.clear();
        Some(dropped)
    }

    /// (applied, rejected, readmitted, before_start, waiting) fix counts.
    fn counts(&self) -> (u64, u64, u64, u64, usize) {
        let c = self.inner.counts();
        let waiting = self.pending.len();
        (c.applied, c.rejected, c.readmitted, c.before_start, waiting)
    }

    /// The settings as a dict.
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, v) in values(self.inner.config(), FIELDS) {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    /// Complete state as JSON; floats round-trip exactly.
    fn state_json(&self) -> PyResult<String> {
        serde_json::to_string(&(&self.inner, self.pending.waiting()))
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// Rebuilds a filter from `state_json()`.
    #[staticmethod]
    fn from_state_json(state: &str) -> PyResult<Self> {
        let (inner, pending): (Fusion, Vec<Fix>) = serde_json::from_str(state)
            .map_err(|e| PyValueError::new_err(format!("not a gyrocore fusion state: {e}")))?;
        Ok(PyFusion {
            inner,
            pending: pending.into(),
        })
    }
}

/// The filter's settings keys with what each is and its unit.
#[pyfunction]
fn fusion_setting_names() -> Vec<(&'static str, &'static str)> {
    names(FIELDS)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyFusion>()?;
    m.add_function(wrap_pyfunction!(fuse, m)?)?;
    m.add_function(wrap_pyfunction!(fusion_setting_names, m)?)?;
    Ok(())
}
