//! Python bindings of the gyrocore core crate: convert, validate shapes, release the GIL, call the
//! core, and move results into numpy without copying.

mod allan;
mod arrays;
mod blocks;
mod fixes;
mod fused;
mod interrupt;
mod params;
mod pending;
mod prefault;
mod settings;
mod sim;
mod table;

use arrays::{fill, slice, zeros, Array};
use gyrocore::{Error, Pipeline, PipelineConfig, Preset, Rest};
use interrupt::detach_watched;
use numpy::PyReadonlyArray1;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

pyo3::create_exception!(
    _gyrocore,
    SampleError,
    PyValueError,
    "A sample that cannot be processed: NaN/inf, beyond the limits of a sample, or a timestamp \
     that does not increase by at least 1e-12 s. \
     Attributes: index (of the sample), what ('t', 'rate' or 'temperature')."
);

/// Maps a core error to a Python exception with the core's message: `SampleError` (a
/// `ValueError` carrying `index` and `what`) for a bad sample, `ValueError` otherwise. A stream's
/// step back also carries `log_message`, its words as a whole series' ([`Error::of_series`],
/// without `restart_clock()`): a log or a file processed by a stream is one series to mend.
fn value_error(e: Error) -> PyErr {
    let Some(index) = e.index() else {
        return PyValueError::new_err(e.to_string());
    };
    let what = match e {
        Error::NonFinite { what, .. } | Error::OutOfRange { what, .. } => what,
        _ => "t",
    };
    Python::attach(|py| {
        let err = SampleError::new_err(e.to_string());
        let value = err.value(py);
        // matched, not compared with `of_series`: a NaN in an error's value is unequal to itself
        let series = matches!(e, Error::ClockStepsBack { .. })
            .then(|| value.setattr("log_message", e.of_series().to_string()));
        let set = value
            .setattr("index", index)
            .and(value.setattr("what", what))
            .and(series.unwrap_or(Ok(())));
        match set {
            Ok(()) => err,
            Err(set) => set,
        }
    })
}

/// The streaming pipeline of the core crate (see `gyrocore.Pipeline` for the documented API).
#[pyclass(module = "gyrocore._gyrocore", name = "Pipeline")]
#[derive(Clone)]
struct PyPipeline {
    inner: fused::Core,
}

/// A rest the tracker found, as [`PyPipeline::process`] returns it: (start, end [s since the
/// first sample], bias, standard error, noise [rad/s], samples, found by speed, accepted,
/// filtered bias after it [rad/s]).
type RestView = (f64, f64, f64, f64, f64, u64, bool, bool, f64);

fn build_preset(name: &str) -> PyResult<Preset> {
    Preset::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = Preset::ALL.iter().map(|p| p.name()).collect();
        let mut choices = names.clone();
        choices.push("recommended");
        PyValueError::new_err(format!(
            "unknown preset '{name}'{}; choose one of {}, recommended",
            did_you_mean(name, &choices),
            names.join(", ")
        ))
    })
}

/// `" (did you mean 'x'?)"` for a likely typo of one of `choices`, by
/// `gyrocore._checks.did_you_mean`, so that every unknown name of the package is answered the
/// same way; empty when none is close (or the package cannot be imported).
pub(crate) fn did_you_mean(name: &str, choices: &[&str]) -> String {
    Python::attach(|py| {
        py.import("gyrocore._checks")
            .and_then(|m| m.call_method1("did_you_mean", (name, choices.to_vec())))
            .and_then(|hint| hint.extract::<String>())
            .unwrap_or_default()
    })
}

fn build_config(preset: &str, overrides: Option<&Bound<'_, PyDict>>) -> PyResult<PipelineConfig> {
    let mut config = build_preset(preset)?.config();
    if let Some(o) = overrides {
        params::apply(&mut config, o)?;
    }
    Ok(config)
}

#[pymethods]
impl PyPipeline {
    #[new]
    #[pyo3(signature = (preset, overrides=None))]
    fn new(preset: &str, overrides: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let config = build_config(preset, overrides)?;
        Ok(PyPipeline {
            inner: fused::Core::Plain(Box::new(Pipeline::new(config).map_err(value_error)?)),
        })
    }

    /// Processes a block; returns (heading, rate, drift, rests, fused), rate and drift None
    /// unless asked for in `outputs` (rate, drift), rests the ones the tracker found in the block
    /// (see [`RestView`]), fused the fix stage's (heading_sigma, bias, scale, counts) when the
    /// pipeline has one (the heading is then the filter's; each column None unless asked for in
    /// `fix_outputs`, each costing per sample when it is). `fixes` are (t, heading, sigma)
    /// arrays, after any still waiting. `out` are the caller's (heading, rate, drift) arrays to
    /// fill instead of fresh ones (each None or one per output asked for; see [`output`]).
    /// Nothing is processed from an invalid block; its error counts sample indices from
    /// `index_offset`.
    #[pyo3(signature = (t, rate, temperature=None, index_offset=0, outputs=(true, true), speed=None, fixes=None, out=None, fix_outputs=(true, true, true)))]
    #[allow(clippy::type_complexity, clippy::too_many_arguments)]
    fn process<'py>(
        &mut self,
        py: Python<'py>,
        t: PyReadonlyArray1<'py, f64>,
        rate: PyReadonlyArray1<'py, f64>,
        temperature: Option<PyReadonlyArray1<'py, f64>>,
        index_offset: usize,
        outputs: (bool, bool),
        speed: Option<PyReadonlyArray1<'py, f64>>,
        fixes: Option<[PyReadonlyArray1<'py, f64>; 3]>,
        out: Option<[Option<Array<'py>>; 3]>,
        fix_outputs: (bool, bool, bool),
    ) -> PyResult<(
        Array<'py>,
        Option<Array<'py>>,
        Option<Array<'py>>,
        Vec<RestView>,
        Option<fused::FusedColumns<'py>>,
    )> {
        let block = fused::Block::of(&t, &rate, temperature.as_ref(), speed.as_ref())?;
        let mut rests = Vec::new();
        let mut on_rest = |r: Rest| {
            rests.push((
                r.start,
                r.end,
                r.bias,
                r.std_error,
                r.noise,
                r.samples,
                r.by_speed,
                r.accepted,
                r.filtered,
            ))
        };
        let wanted = fused::Wanted {
            pipeline: outputs,
            fixes: fix_outputs,
            given: out,
        };
        let (heading, out_rate, drift, fused) =
            self.inner
                .process(py, &block, fixes, wanted, index_offset, &mut on_rest)?;
        Ok((heading, out_rate, drift, rests, fused))
    }

    /// Adds the heading-fix stage (settings as `gyrocore._gyrocore.Fusion` takes them) to a
    /// pipeline before its first sample.
    #[pyo3(signature = (settings=None))]
    fn start_fusion(&mut self, settings: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        self.inner.start_fusion(settings)
    }

    /// Whether the pipeline has the fix stage.
    fn fused(&self) -> bool {
        matches!(self.inner, fused::Core::Fused { .. })
    }

    /// Returns the pipeline to its state before the first sample.
    fn reset(&mut self) {
        self.inner.reset();
    }

    /// Takes the next sample on a new time base (a clock that jumped back), keeping every
    /// estimate; returns how many fixes waiting for later samples it dropped (see
    /// `gyrocore.Pipeline.restart_clock`).
    fn restart_clock(&mut self) -> PyResult<usize> {
        self.inner.restart_clock().map_err(value_error)
    }

    /// The configuration as a flat parameter dict.
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        params::to_dict(py, self.inner.pipeline().config())
    }

    /// (bias [rad/s], number of readings it averages, still measuring?).
    fn bias(&self) -> (f64, u64, bool) {
        let p = self.inner.pipeline();
        let (b, n) = p.bias();
        (b, n, p.bias_learning())
    }

    /// (noise [rad/s], bias standard error [rad/s]) of the rest window once it is over, or None.
    fn rest_statistics(&self) -> Option<(f64, f64)> {
        self.inner
            .pipeline()
            .rest_statistics()
            .map(|r| (r.noise, r.bias_std_error))
    }

    /// The rest tracker, or None without one: (filtered bias [rad/s], its standard error now
    /// [rad/s] or None before any rest, rests found).
    fn rest_tracker(&self) -> Option<(f64, Option<f64>, u64)> {
        let tracker = self.inner.pipeline().rest_tracker()?;
        let config = self.inner.pipeline().config().rest_tracker?;
        Some((
            tracker.bias(),
            tracker.std_error(&config),
            tracker.rests_found(),
        ))
    }

    /// What the input policy did so far: held, skipped, gaps, longest_gap [s].
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let r = self.inner.pipeline().report();
        let d = PyDict::new(py);
        d.set_item("held", r.held)?;
        d.set_item("skipped", r.skipped)?;
        d.set_item("gaps", r.gaps)?;
        d.set_item("longest_gap", r.longest_gap)?;
        Ok(d)
    }

    /// The last timestamp processed, or None.
    fn last_time(&self) -> Option<f64> {
        self.inner.pipeline().last_time()
    }

    /// Complete state (configuration included) as JSON; floats round-trip exactly.
    fn state_json(&self) -> PyResult<String> {
        self.inner.state_json()
    }

    /// Rebuilds a pipeline from `state_json()`.
    #[staticmethod]
    fn from_state_json(state: &str) -> PyResult<Self> {
        Ok(PyPipeline {
            inner: fused::Core::from_state_json(state)?,
        })
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }
}

/// Flat parameters of a preset (after optional overrides).
#[pyfunction]
#[pyo3(signature = (preset, overrides=None))]
fn preset_params<'py>(
    py: Python<'py>,
    preset: &str,
    overrides: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    params::to_dict(py, &build_config(preset, overrides)?)
}

/// Preset names, and the name the `recommended` alias stands for.
#[pyfunction]
fn preset_names() -> (Vec<&'static str>, &'static str) {
    (
        Preset::ALL.iter().map(|p| p.name()).collect(),
        Preset::RECOMMENDED.name(),
    )
}

/// Whether a preset subtracts a static bias (so it wants a bias or a rest window).
#[pyfunction]
fn preset_uses_static_bias(preset: &str) -> PyResult<bool> {
    Ok(build_preset(preset)?.uses_static_bias())
}

/// Parameter names and their descriptions.
#[pyfunction]
fn parameter_names() -> Vec<(&'static str, &'static str)> {
    params::NAMES.to_vec()
}

/// The static bias test over `[start, end]`: (bias [rad/s], readings, noise [rad/s] or None,
/// bias standard error [rad/s] or None), by the estimator the pipeline's rest window uses.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn static_bias_test(
    py: Python<'_>,
    t: PyReadonlyArray1<'_, f64>,
    rate: PyReadonlyArray1<'_, f64>,
    start: f64,
    end: f64,
) -> PyResult<(f64, u64, Option<f64>, Option<f64>)> {
    let (t, rate) = (slice("t", &t)?, slice("rate", &rate)?);
    let test = detach_watched(py, t.len(), |stop| {
        gyrocore::static_bias_test_stoppable(t, rate, start, end, &stop.0)
    })?
    .map_err(value_error)?
    // stopped only by a Ctrl-C, whose exception detach_watched returned
    .ok_or_else(|| PyRuntimeError::new_err("the static bias test was stopped"))?;
    let stats = test.statistics;
    Ok((
        test.bias,
        test.count,
        stats.map(|s| s.noise),
        stats.map(|s| s.bias_std_error),
    ))
}

/// The Kalman filter of a random-walk bias over rests (`gyrocore::bias_walk::filter_rests`):
/// (filtered mean, filtered variance, predicted variance) at each rest, from the first rest to
/// the last, or from the last to the first where `backward`.
#[pyfunction]
fn filter_rests<'py>(
    py: Python<'py>,
    times: PyReadonlyArray1<'py, f64>,
    values: PyReadonlyArray1<'py, f64>,
    variances: PyReadonlyArray1<'py, f64>,
    q: f64,
    floor: f64,
    backward: bool,
) -> PyResult<(Array<'py>, Array<'py>, Array<'py>)> {
    let (times, values) = (slice("times", &times)?, slice("values", &values)?);
    let variances = slice("variances", &variances)?;
    let n = times.len();
    let (mean, variance, predicted) = (zeros(py, n), zeros(py, n), zeros(py, n));
    fill([&mean, &variance, &predicted], |[m, v, p]| {
        py.detach(|| {
            gyrocore::bias_walk::filter_rests(
                times,
                values,
                variances,
                q,
                floor,
                backward,
                (m, v, p),
            )
        })
    })?
    .map_err(value_error)?;
    Ok((mean, variance, predicted))
}

/// Panics inside Rust, with the GIL released as in real work: proves that a panic reaches Python
/// as an exception (pyo3's PanicException) instead of aborting the interpreter.
#[pyfunction]
fn _panic_for_test(py: Python<'_>) {
    py.detach(|| panic!("forced panic for the no-abort test"));
}

#[pymodule]
fn _gyrocore(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // rust-numpy finds NumPy's C API on its first use, running Python code (numpy's version
    // check) that a Ctrl-C can interrupt, and then panics. Found here, as the module is imported,
    // before any command owns its signals, no later call meets it.
    numpy::PyArray1::<f64>::zeros(m.py(), 0, false);
    m.add_class::<PyPipeline>()?;
    m.add("SampleError", m.py().get_type::<SampleError>())?;
    m.add_function(wrap_pyfunction!(preset_params, m)?)?;
    m.add_function(wrap_pyfunction!(preset_names, m)?)?;
    m.add_function(wrap_pyfunction!(parameter_names, m)?)?;
    m.add_function(wrap_pyfunction!(preset_uses_static_bias, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_test, m)?)?;
    m.add_function(wrap_pyfunction!(static_bias_test, m)?)?;
    m.add_function(wrap_pyfunction!(filter_rests, m)?)?;
    allan::register(m)?;
    blocks::register(m)?;
    fixes::register(m)?;
    sim::register(m)?;
    table::register(m)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The core's limits and names, which the Python package checks against before calling it.
    m.add("MAX_READING", gyrocore::MAX_READING)?;
    m.add("MAX_TIME", gyrocore::MAX_TIME)?;
    m.add("MIN_INTERVAL", gyrocore::MIN_INTERVAL)?;
    m.add("BIAS_SOURCES", params::BIAS_SOURCES)?;
    Ok(())
}
