//! Bindings of the simulated gyro (`gyrocore.sim` documents the Python API). The configuration
//! arrives as a flat dict of SI values; `gyrocore.sim.GyroSpec` builds it from datasheet units.

use gyrocore::{GyroModel, GyroModelConfig, Stage};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{fill, slice, zeros, Array};
use crate::fused::Block;
use crate::interrupt::{detach_watched, PIECE};
use crate::settings::{names, set_all, Field};

/// The accepted configuration keys, with their units and fields.
const FIELDS: &[Field<GyroModelConfig>] = &[
    ("rate_hz", "output data rate [Hz]", |c| &mut c.rate_hz),
    (
        "jitter",
        "standard deviation of the sampling instants [s]",
        |c| &mut c.jitter,
    ),
    (
        "drop_probability",
        "probability that a sample is lost [1]",
        |c| &mut c.drop_probability,
    ),
    ("scale_error", "scale error s of Hong eq 1 [1]", |c| {
        &mut c.scale_error
    }),
    ("scale_asymmetry", "ccw minus cw scale error [1]", |c| {
        &mut c.scale_asymmetry
    }),
    (
        "scale_temperature",
        "scale error per degree [1/degC]",
        |c| &mut c.scale_temperature,
    ),
    (
        "bias",
        "bias b of Hong eq 1 at the reference temperature [rad/s]",
        |c| &mut c.bias,
    ),
    ("bias_temperature", "bias per degree [rad/s/degC]", |c| {
        &mut c.bias_temperature
    }),
    ("arw", "angle random walk N [rad/sqrt(s)]", |c| &mut c.arw),
    (
        "bandwidth",
        "corner of the low-pass on the white noise [Hz]",
        |c| &mut c.bandwidth,
    ),
    ("bias_instability", "bias instability B [rad/s]", |c| {
        &mut c.bias_instability
    }),
    (
        "flicker_min",
        "shortest flicker correlation time [s]",
        |c| &mut c.flicker_min,
    ),
    ("flicker_max", "longest flicker correlation time [s]", |c| {
        &mut c.flicker_max
    }),
    ("rrw", "rate random walk K [rad/s/sqrt(s)]", |c| &mut c.rrw),
    ("drift_step", "grid of the slow bias [s]", |c| {
        &mut c.drift_step
    }),
    (
        "temperature_start",
        "temperature at the first sample [degC]",
        |c| &mut c.temperature.start,
    ),
    (
        "temperature_end",
        "temperature reached in the end [degC]",
        |c| &mut c.temperature.end,
    ),
    (
        "temperature_time_constant",
        "time constant of the temperature [s]",
        |c| &mut c.temperature.time_constant,
    ),
    (
        "reference_temperature",
        "temperature of scale_error and bias [degC]",
        |c| &mut c.reference_temperature,
    ),
    ("resolution", "one least significant bit [rad/s]", |c| {
        &mut c.resolution
    }),
    ("range", "measurement range [rad/s]", |c| &mut c.range),
];

/// Most samples one call may produce (8 GB of float64): a guard against a duration in ms.
const MAX_SAMPLES: f64 = 1.0e9;

/// Builds and validates the core configuration from the flat SI dict (every key in `FIELDS`).
fn config_from(dict: &Bound<'_, PyDict>) -> PyResult<GyroModelConfig> {
    let rate_hz: f64 = match dict.get_item("rate_hz")? {
        Some(v) => v.extract()?,
        None => {
            return Err(PyValueError::new_err(
                "the gyro configuration needs rate_hz",
            ))
        }
    };
    let mut c = GyroModelConfig::ideal(rate_hz);
    set_all(&mut c, dict, FIELDS, "gyro parameter")?;
    c.validate()
        .map_err(|e| PyValueError::new_err(format!("gyro model: {e}")))?;
    Ok(c)
}

/// Readings of the simulated gyro for true rates `rate` [rad/s] at times `t` [s]; returns
/// (reading [rad/s], temperature [degC], bias b + d [rad/s], scale error s [1]) per sample.
#[pyfunction]
fn gyro_measure<'py>(
    py: Python<'py>,
    config: &Bound<'py, PyDict>,
    seed: u64,
    t: PyReadonlyArray1<'py, f64>,
    rate: PyReadonlyArray1<'py, f64>,
) -> PyResult<(Array<'py>, Array<'py>, Array<'py>, Array<'py>)> {
    let mut model = GyroModel::new(config_from(config)?, seed)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let block = Block::of(&t, &rate, None, None)?;
    let n = block.t.len();
    let out = [zeros(py, n), zeros(py, n), zeros(py, n), zeros(py, n)];
    fill([&out[0], &out[1], &out[2], &out[3]], |[r, temp, b, s]| {
        // each piece checked after the last time of the one before, as a pipeline checks a block
        block.watched_pieces(py, |piece, range| {
            block.check_piece(piece, &range)?;
            for (i, (&ti, &ri)) in range.zip(piece.t.iter().zip(piece.rate)) {
                let m = model.update(ti, ri);
                (r[i], temp[i], b[i], s[i]) = (m.rate, m.temperature, m.bias, m.scale);
            }
            Ok(())
        })
    })??
    .map_err(|e: gyrocore::Error| PyValueError::new_err(e.to_string()))?;
    let [r, temp, b, s] = out;
    Ok((r, temp, b, s))
}

/// How many samples `[start, end)` asks for at the configured rate: an error naming the span
/// unless it is finite and not empty, and holds at most [`MAX_SAMPLES`].
fn sample_count(c: &GyroModelConfig, start: f64, end: f64) -> PyResult<f64> {
    if !(start.is_finite() && end.is_finite() && end > start) {
        return Err(PyValueError::new_err(format!(
            "the sampling span must be finite with end > start, got [{start}, {end})"
        )));
    }
    let expected = (end - start) * c.rate_hz;
    if expected > MAX_SAMPLES {
        return Err(PyValueError::new_err(format!(
            "{expected:.3e} samples requested ({} s at {} Hz): more than {MAX_SAMPLES:.0e}; \
             is the duration in seconds?",
            end - start,
            c.rate_hz
        )));
    }
    // Jitter leaves consecutive instants a tenth of a period apart at least; where that is below
    // float64's step at the span's largest time, rounding made them repeat (1e7 Hz at 1.7e9 s).
    let resolution = f64::EPSILON * start.abs().max(end.abs());
    if 0.1 / c.rate_hz <= resolution {
        return Err(PyValueError::new_err(format!(
            "{} Hz at times up to {} s: samples {:.3e} s apart are within what float64 resolves \
             there ({resolution:.1e} s), so timestamps would repeat; start the clock nearer 0 or \
             lower rate_hz",
            c.rate_hz,
            start.abs().max(end.abs()),
            1.0 / c.rate_hz
        )));
    }
    Ok(expected)
}

/// Checks a sampling span as `gyro_sample_times` does, making no samples (asked before a long
/// route is built).
#[pyfunction]
fn gyro_check_span(config: &Bound<'_, PyDict>, start: f64, end: f64) -> PyResult<()> {
    sample_count(&config_from(config)?, start, end).map(|_| ())
}

/// The kept sampling instants in `[start, end)` [s] (jittered grid, dropped samples left out).
#[pyfunction]
fn gyro_sample_times<'py>(
    py: Python<'py>,
    config: &Bound<'py, PyDict>,
    seed: u64,
    start: f64,
    end: f64,
) -> PyResult<Array<'py>> {
    let c = config_from(config)?;
    let expected = sample_count(&c, start, end)?;
    let model = GyroModel::new(c, seed).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let mut times = Vec::with_capacity(expected as usize + 1);
    let mut sampler = model.sampler(start);
    // PIECE instants at a time, until one reaches `end`.
    detach_watched(py, expected as usize, |stop| loop {
        let before = times.len();
        times.extend(sampler.by_ref().take(PIECE).take_while(|&t| t < end));
        if times.len() < before + PIECE || stop.requested() {
            return;
        }
    })?;
    Ok(PyArray1::from_vec(py, times))
}

/// Closed-form Allan deviation [rad/s] of the configured noise at averaging times `taus` [s].
#[pyfunction]
fn gyro_allan_deviation<'py>(
    py: Python<'py>,
    config: &Bound<'py, PyDict>,
    taus: PyReadonlyArray1<'py, f64>,
) -> PyResult<Array<'py>> {
    let c = config_from(config)?;
    let taus = slice("taus", &taus)?;
    if let Some(i) = taus.iter().position(|&x| !(x.is_finite() && x > 0.0)) {
        return Err(PyValueError::new_err(format!(
            "taus[{i}] = {} must be finite and > 0",
            taus[i]
        )));
    }
    let adev: Vec<f64> = taus.iter().map(|&x| c.allan_variance(x).sqrt()).collect();
    Ok(PyArray1::from_vec(py, adev))
}

/// The gyro configuration keys with their units.
#[pyfunction]
fn gyro_parameter_names() -> Vec<(&'static str, &'static str)> {
    names(FIELDS)
}

/// Adds the simulation functions to the extension module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(gyro_measure, m)?)?;
    m.add_function(wrap_pyfunction!(gyro_sample_times, m)?)?;
    m.add_function(wrap_pyfunction!(gyro_check_span, m)?)?;
    m.add_function(wrap_pyfunction!(gyro_allan_deviation, m)?)?;
    m.add_function(wrap_pyfunction!(gyro_parameter_names, m)?)?;
    Ok(())
}
