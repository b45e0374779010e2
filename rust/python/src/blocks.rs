//! Bindings of the core's calls over one block of samples that keep no state between calls:
//! checks, integration, block means, projection onto the up axis. Each goes through the core in
//! pieces, watched for a Ctrl-C (see [`interrupt`](crate::interrupt)); its outputs are new arrays,
//! thrown away when it stops.

use gyrocore::{Downsample, DownsampleConfig, Integrator, IntegratorConfig, Stage, Up};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::arrays::{fill, slice, zeros, Array};
use crate::fused::Block;
use crate::interrupt::watched_pieces;
use crate::{params, value_error};

/// The core's checks of a block of samples ([`gyrocore::check_block`]: lengths; finite, strictly
/// increasing times; finite readings and temperatures within the limit of a reading), processing
/// nothing: the error names the first bad sample, as a pipeline's would.
#[pyfunction]
#[pyo3(signature = (t, rate, temperature=None))]
fn check_samples<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
    rate: PyReadonlyArray1<'py, f64>,
    temperature: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<()> {
    let block = Block::of(&t, &rate, temperature.as_ref(), None)?;
    block
        .watched_pieces(py, |piece, range| block.check_piece(piece, &range))?
        .map_err(value_error)
}

/// Integrates rate into a continuous heading.
#[pyfunction]
#[pyo3(signature = (t, rate, method="trapezoid", initial_heading=0.0))]
fn integrate<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
    rate: PyReadonlyArray1<'py, f64>,
    method: &str,
    initial_heading: f64,
) -> PyResult<Array<'py>> {
    let (t, rate) = (slice("t", &t)?, slice("rate", &rate)?);
    let config = IntegratorConfig {
        method: params::parse_method(method)?,
        initial_heading,
    };
    let mut integrator = Integrator::new(config).map_err(value_error)?;
    let heading = zeros(py, t.len());
    let block = Block::new(t, rate);
    // the stage checks each piece as it goes, refusing the block by the first bad sample's index
    fill([&heading], |[h]| {
        block.watched_pieces(py, |piece, range| {
            integrator.process_block(piece.t, piece.rate, &mut h[range])
        })
    })??
    .map_err(value_error)?;
    Ok(heading)
}

/// The yaw rate of a three-axis gyro: `(x, y, z) . up` per sample, `up` normalised.
#[pyfunction]
fn project_up<'py>(
    py: Python<'py>,
    x: PyReadonlyArray1<'py, f64>,
    y: PyReadonlyArray1<'py, f64>,
    z: PyReadonlyArray1<'py, f64>,
    up: [f64; 3],
) -> PyResult<Array<'py>> {
    let (x, y, z) = (slice("x", &x)?, slice("y", &y)?, slice("z", &z)?);
    let up = Up::new(up).map_err(value_error)?;
    let rate = zeros(py, x.len());
    // Arrays of different lengths go whole: the core names the one that differs.
    let same = y.len() == x.len() && z.len() == x.len();
    let n = if same { x.len() } else { 0 };
    fill([&rate], |[r]| {
        watched_pieces(py, n, |range| {
            let (x, y, z) = if same {
                (&x[range.clone()], &y[range.clone()], &z[range.clone()])
            } else {
                (x, y, z)
            };
            up.project_block(x, y, z, &mut r[range.clone()])
        })
    })??
    .map_err(value_error)?;
    Ok(rate)
}

/// Block means over `interval` seconds (HDR's second eq 14); returns (t_end, mean rate).
#[pyfunction]
fn downsample<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
    rate: PyReadonlyArray1<'py, f64>,
    interval: f64,
) -> PyResult<(Array<'py>, Array<'py>)> {
    let (t, rate) = (slice("t", &t)?, slice("rate", &rate)?);
    let mut stage = Downsample::new(DownsampleConfig { interval }).map_err(value_error)?;
    let (mut out_t, mut out_rate) = (vec![0.0; t.len()], vec![0.0; t.len()]);
    let block = Block::new(t, rate);
    // A piece closes at most one interval per sample: its means fit from the count so far.
    let mut n = 0;
    block
        .watched_pieces(py, |piece, _| {
            let len = piece.t.len();
            let (out_t, out_rate) = (&mut out_t[n..n + len], &mut out_rate[n..n + len]);
            n += stage.process_block(piece.t, piece.rate, out_t, out_rate)?;
            Ok(())
        })?
        .map_err(value_error)?;
    out_t.truncate(n);
    out_rate.truncate(n);
    Ok((
        PyArray1::from_vec(py, out_t),
        PyArray1::from_vec(py, out_rate),
    ))
}

/// Adds these functions to the extension module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(check_samples, m)?)?;
    m.add_function(wrap_pyfunction!(integrate, m)?)?;
    m.add_function(wrap_pyfunction!(downsample, m)?)?;
    m.add_function(wrap_pyfunction!(project_up, m)?)?;
    Ok(())
}
