//! Bindings of the core's Allan-family variances (`gyrocore.allan` documents the Python API).

use gyrocore::allan::{phase_from_rate_stoppable, variances_stoppable};
use gyrocore::{Error, Variance};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::interrupt::detach_watched;

fn parse_kind(name: &str) -> PyResult<Variance> {
    Ok(match name {
        "allan" => Variance::Allan,
        "overlapping_allan" => Variance::OverlappingAllan,
        "modified_allan" => Variance::ModifiedAllan,
        "hadamard" => Variance::Hadamard,
        "overlapping_hadamard" => Variance::OverlappingHadamard,
        _ => {
            return Err(PyValueError::new_err(format!(
                "unknown variance '{name}': use allan, overlapping_allan, modified_allan, \
                 hadamard or overlapping_hadamard"
            )))
        }
    })
}

/// Variances and their numbers of terms, as numpy arrays.
type Curve<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<u64>>);

/// Variances [(unit/s)^2 for angle data in unit] and their numbers of terms at each averaging
/// factor, summed on all cores. `data` is phase (angle) sampled every `tau0` seconds, or rate
/// when `is_rate` (then integrated once to phase here, the only large allocation).
#[pyfunction]
#[pyo3(signature = (data, tau0, factors, kind, is_rate))]
fn allan_variances<'py>(
    py: Python<'py>,
    data: PyReadonlyArray1<'py, f64>,
    tau0: f64,
    factors: Vec<usize>,
    kind: &str,
    is_rate: bool,
) -> PyResult<Curve<'py>> {
    let kind = parse_kind(kind)?;
    let data = data
        .as_slice()
        .map_err(|_| PyValueError::new_err("the samples must be a contiguous float64 array"))?;
    let (mut var, mut terms) = (vec![0.0; factors.len()], vec![0u64; factors.len()]);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    // The phase buffer comes from numpy, which asks the kernel for huge pages for large arrays:
    // 10^8 samples then cost a few hundred page faults instead of 200 000 (0.3 s).
    let mut phase = is_rate.then(|| PyArray1::<f64>::zeros(py, data.len() + 1, false).readwrite());
    let phase = phase.as_mut().map(|p| p.as_slice_mut()).transpose()?;
    // A Ctrl-C stops the sums (a modified deviation of 10^8 samples ran 28 s more after one).
    detach_watched(py, data.len(), |stop| -> Result<(), Error> {
        let stop = &stop.0;
        let x = match phase {
            Some(x) => {
                phase_from_rate_stoppable(data, tau0, x, stop)?;
                &*x
            }
            None => data,
        };
        variances_stoppable(x, tau0, &factors, kind, threads, stop, &mut var, &mut terms)
    })?
    .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((PyArray1::from_vec(py, var), PyArray1::from_vec(py, terms)))
}

/// Adds the Allan functions to the extension module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(allan_variances, m)?)?;
    Ok(())
}
