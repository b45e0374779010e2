//! The flat parameter names of the Python API, mapped to and from the core's `PipelineConfig`.
//!
//! This is the one place that knows the names; presets come from the core crate.

use gyrocore::{
    GapAction, HdrConfig, Method, NonFinite, PipelineConfig, RestTrackerConfig, StaticBias,
    TemperatureScale, ThresholdConfig,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Every accepted parameter name, with its unit, for error messages and the docs.
pub const NAMES: &[(&str, &str)] = &[
    (
        "bias",
        "static bias eps0 [rad/s] (what the gyro reads at rest)",
    ),
    (
        "bias_window",
        "(start, end) rest window [s] to measure the bias in",
    ),
    (
        "bias_duration",
        "measure the bias over the first T_bias seconds [s]",
    ),
    ("scale", "s_bar of Hong eq 3 [1]"),
    ("offset", "b_bar of Hong eq 3 [rad/s]"),
    ("c_cw", "clockwise correction factor C_cw (FOG eq 2a) [1]"),
    (
        "c_ccw",
        "counter-clockwise correction factor C_ccw (FOG eq 2b) [1]",
    ),
    (
        "temp_slope",
        "turn error per degC of FOG eq 5 divided by 360 deg [1/degC]",
    ),
    (
        "temp_offset",
        "turn error at 0 degC of FOG eq 5 divided by 360 deg [1]",
    ),
    (
        "threshold",
        "dead band r_thres of Hong eq 12 [rad/s], 0 = off",
    ),
    (
        "lowpass_tau",
        "low-pass time constant tau of HDR eq 7, per sample and on HDR's steps [s], 0 = off",
    ),
    (
        "threshold_sigmas",
        "dead band in noise standard deviations of the rest window (replaces threshold) [1], None = off",
    ),
    ("delag", "undo the low-pass lag (HDR eq 13) [bool]"),
    ("hdr", "run Heuristic Drift Reduction [bool]"),
    ("hdr_increment", "i_c [rad/s per step]"),
    ("hdr_turn_threshold", "Theta_w [rad/s]"),
    ("hdr_c1", "repetition attenuator constant c_1 [1]"),
    ("hdr_c2", "repetition attenuator power c_2 [1]"),
    ("hdr_interval", "HDR step length [s]"),
    (
        "hdr_max_correction",
        "bound on HDR's correction |I| [rad/s] (inf: none, as in the paper)",
    ),
    (
        "hdr_bound_sigmas",
        "bound on HDR's |I| in standard errors of the static bias from the rest window (replaces hdr_max_correction) [1], None = off",
    ),
    ("integration", "'trapezoid' or 'rectangle'"),
    ("initial_heading", "heading at the first sample [rad]"),
    (
        "nonfinite",
        "NaN/inf readings: 'error' (default), 'hold' the last reading, or 'skip' the sample",
    ),
    (
        "gap_limit",
        "longest interval that is not a gap [s] (default 2; inf: none)",
    ),
    (
        "gap_action",
        "at a gap: 'bridge' (default) or 'reset' HDR, low-pass and de-lag",
    ),
    (
        "track_rests",
        "find rests while driving and re-measure the bias at each (a Kalman filter) [bool]",
    ),
    ("rest_block", "rest detection block length [s]"),
    (
        "rest_min_duration",
        "shortest rest that counts, without its first and last block [s]",
    ),
    (
        "rest_noise_ratio",
        "without speed: a still block's noise at most this times the noise at rest [1]",
    ),
    (
        "rest_change_sigmas",
        "without speed: a still block's mean within this many standard errors of the previous block's [1]",
    ),
    ("rest_speed_threshold", "speed below which the vehicle is at rest [m/s]"),
    (
        "rest_bias_walk",
        "random-walk intensity of the bias q [rad^2/s^3] (see gyrocore.rests.bias_walk)",
    ),
    (
        "rest_gate_sigmas",
        "refuse a rest further than this many innovation standard deviations from the bias [1] (inf: none)",
    ),
    (
        "rest_noise",
        "reading noise at rest [rad/s] if known beforehand; None: from the rest window or the first rest",
    ),
];

fn unknown(name: &str) -> PyErr {
    let valid: Vec<&str> = NAMES.iter().map(|(n, _)| *n).collect();
    PyValueError::new_err(format!(
        "unknown parameter '{name}'{}; valid names: {}",
        crate::did_you_mean(name, &valid),
        valid.join(", ")
    ))
}

/// Applies `overrides` (name -> value) to `config`, name by name in the order of [`NAMES`] (so
/// a switch such as `hdr` comes before the parameters it enables, whatever the caller's order);
/// every rule between parameters is the core's (`PipelineConfig::validate`), checked when the
/// pipeline is built. Only what the core's types cannot express is checked here: one bias
/// source, and HDR parameters need HDR.
pub fn apply(config: &mut PipelineConfig, overrides: &Bound<'_, PyDict>) -> PyResult<()> {
    for key in overrides.keys() {
        let name: String = key.extract()?;
        if !NAMES.iter().any(|(n, _)| *n == name) {
            return Err(unknown(&name));
        }
    }
    let mut bias_sources = Vec::new();
    for &(name, _) in NAMES {
        // `None` leaves a parameter as the preset has it, so callers can pass optional values through.
        let Some(value) = overrides.get_item(name)?.filter(|v| !v.is_none()) else {
            continue;
        };
        let c = &mut config.correction;
        match name {
            "bias" => c.bias = StaticBias::Fixed(value.extract()?),
            "bias_window" => {
                let (start, end): (f64, f64) = value.extract()?;
                c.bias = StaticBias::Window { start, end };
            }
            "bias_duration" => {
                c.bias = StaticBias::Leading {
                    duration: value.extract()?,
                }
            }
            "scale" => c.scale = value.extract()?,
            "offset" => c.offset = value.extract()?,
            "c_cw" => c.c_cw = value.extract()?,
            "c_ccw" => c.c_ccw = value.extract()?,
            "temp_slope" => temperature_model(c).slope = value.extract()?,
            "temp_offset" => temperature_model(c).offset = value.extract()?,
            "threshold" => {
                let threshold: f64 = value.extract()?;
                config.threshold = (threshold != 0.0).then_some(ThresholdConfig { threshold });
            }
            "lowpass_tau" => config.set_lowpass_tau(value.extract()?),
            "delag" => config.delag = value.extract()?,
            "threshold_sigmas" => config.noise_scaled.threshold_sigmas = value.extract()?,
            "hdr" => config.set_hdr(value.extract()?),
            "hdr_bound_sigmas" => {
                hdr_of(config, name)?;
                config.noise_scaled.hdr_bound_sigmas = value.extract()?;
            }
            "hdr_increment" => hdr_of(config, name)?.increment = value.extract()?,
            "hdr_turn_threshold" => hdr_of(config, name)?.turn_threshold = value.extract()?,
            "hdr_c1" => hdr_of(config, name)?.c1 = value.extract()?,
            "hdr_c2" => hdr_of(config, name)?.c2 = value.extract()?,
            "hdr_interval" => hdr_of(config, name)?.interval = value.extract()?,
            "hdr_max_correction" => hdr_of(config, name)?.max_correction = value.extract()?,
            "integration" => {
                let method: String = value.extract()?;
                config.integrator.method = parse_method(&method)?;
            }
            "initial_heading" => config.integrator.initial_heading = value.extract()?,
            "nonfinite" => {
                config.input.non_finite = match value.extract::<String>()?.as_str() {
                    "error" => NonFinite::Error,
                    "hold" => NonFinite::Hold,
                    "skip" => NonFinite::Skip,
                    other => {
                        return Err(choice_error(
                            "nonfinite",
                            other,
                            "'error', 'hold' or 'skip'",
                        ))
                    }
                }
            }
            "gap_limit" => config.input.gap_limit = value.extract()?,
            "gap_action" => {
                config.input.gap_action = match value.extract::<String>()?.as_str() {
                    "bridge" => GapAction::Bridge,
                    "reset" => GapAction::Reset,
                    other => return Err(choice_error("gap_action", other, "'bridge' or 'reset'")),
                }
            }
            "track_rests" => {
                let on: bool = value.extract()?;
                config.rest_tracker = on.then(|| config.rest_tracker.unwrap_or_default());
            }
            "rest_block" => tracker_of(config, name)?.block = value.extract()?,
            "rest_min_duration" => tracker_of(config, name)?.min_duration = value.extract()?,
            "rest_noise_ratio" => tracker_of(config, name)?.noise_ratio = value.extract()?,
            "rest_change_sigmas" => tracker_of(config, name)?.change_sigmas = value.extract()?,
            "rest_speed_threshold" => {
                tracker_of(config, name)?.speed_threshold = value.extract()?
            }
            "rest_bias_walk" => tracker_of(config, name)?.bias_walk = value.extract()?,
            "rest_gate_sigmas" => tracker_of(config, name)?.gate_sigmas = value.extract()?,
            "rest_noise" => tracker_of(config, name)?.noise = Some(value.extract()?),
            _ => return Err(unknown(name)),
        }
        if BIAS_SOURCES.contains(&name) {
            bias_sources.push(name);
        }
    }
    if bias_sources.len() > 1 {
        return Err(PyValueError::new_err(format!(
            "give at most one of bias, bias_window, bias_duration (got {})",
            bias_sources.join(", ")
        )));
    }
    Ok(())
}

/// The names that each give the static bias.
pub(crate) const BIAS_SOURCES: [&str; 3] = ["bias", "bias_window", "bias_duration"];

/// The temperature model of `c`, created (as the identity) when first set.
fn temperature_model(c: &mut gyrocore::CorrectionConfig) -> &mut TemperatureScale {
    c.temperature.get_or_insert(TemperatureScale {
        slope: 0.0,
        offset: 0.0,
    })
}

/// HDR's parameters, or an error naming `name` when HDR is off.
fn hdr_of<'a>(config: &'a mut PipelineConfig, name: &str) -> PyResult<&'a mut HdrConfig> {
    config.hdr.as_mut().ok_or_else(|| {
        PyValueError::new_err(format!(
            "{name} is set but HDR is off; pass hdr=True to enable it"
        ))
    })
}

/// The rest tracker's settings, or an error naming `name` when tracking is off.
fn tracker_of<'a>(
    config: &'a mut PipelineConfig,
    name: &str,
) -> PyResult<&'a mut RestTrackerConfig> {
    config.rest_tracker.as_mut().ok_or_else(|| {
        PyValueError::new_err(format!(
            "{name} is set but rest tracking is off; pass track_rests=True to enable it"
        ))
    })
}

fn choice_error(name: &str, got: &str, valid: &str) -> PyErr {
    PyValueError::new_err(format!("unknown {name} '{got}': use {valid}"))
}

/// Parses an integration rule name.
pub fn parse_method(name: &str) -> PyResult<Method> {
    match name {
        "trapezoid" => Ok(Method::Trapezoid),
        "rectangle" => Ok(Method::Rectangle),
        _ => Err(choice_error(
            "integration method",
            name,
            "'trapezoid' or 'rectangle'",
        )),
    }
}

fn method_name(method: Method) -> &'static str {
    match method {
        Method::Trapezoid => "trapezoid",
        Method::Rectangle => "rectangle",
    }
}

/// The configuration as a flat dict; `apply` on a default config rebuilds it exactly.
pub fn to_dict<'py>(py: Python<'py>, config: &PipelineConfig) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let c = &config.correction;
    match c.bias {
        StaticBias::Fixed(b) => d.set_item("bias", b)?,
        StaticBias::Window { start, end } => d.set_item("bias_window", (start, end))?,
        StaticBias::Leading { duration } => d.set_item("bias_duration", duration)?,
    }
    d.set_item("scale", c.scale)?;
    d.set_item("offset", c.offset)?;
    d.set_item("c_cw", c.c_cw)?;
    d.set_item("c_ccw", c.c_ccw)?;
    if let Some(m) = c.temperature {
        d.set_item("temp_slope", m.slope)?;
        d.set_item("temp_offset", m.offset)?;
    }
    d.set_item("threshold", config.threshold.map_or(0.0, |t| t.threshold))?;
    d.set_item("lowpass_tau", config.lowpass.map_or(0.0, |l| l.tau))?;
    d.set_item("threshold_sigmas", config.noise_scaled.threshold_sigmas)?;
    d.set_item("delag", config.delag)?;
    d.set_item("hdr", config.hdr.is_some())?;
    if let Some(h) = config.hdr {
        d.set_item("hdr_increment", h.increment)?;
        d.set_item("hdr_turn_threshold", h.turn_threshold)?;
        d.set_item("hdr_c1", h.c1)?;
        d.set_item("hdr_c2", h.c2)?;
        d.set_item("hdr_interval", h.interval)?;
        d.set_item("hdr_max_correction", h.max_correction)?;
        d.set_item("hdr_bound_sigmas", config.noise_scaled.hdr_bound_sigmas)?;
    }
    d.set_item("integration", method_name(config.integrator.method))?;
    d.set_item("initial_heading", config.integrator.initial_heading)?;
    let input = &config.input;
    let nonfinite = match input.non_finite {
        NonFinite::Error => "error",
        NonFinite::Hold => "hold",
        NonFinite::Skip => "skip",
    };
    d.set_item("nonfinite", nonfinite)?;
    d.set_item("gap_limit", input.gap_limit)?;
    d.set_item(
        "gap_action",
        if input.gap_action == GapAction::Reset {
            "reset"
        } else {
            "bridge"
        },
    )?;
    d.set_item("track_rests", config.rest_tracker.is_some())?;
    if let Some(r) = config.rest_tracker {
        d.set_item("rest_block", r.block)?;
        d.set_item("rest_min_duration", r.min_duration)?;
        d.set_item("rest_noise_ratio", r.noise_ratio)?;
        d.set_item("rest_change_sigmas", r.change_sigmas)?;
        d.set_item("rest_speed_threshold", r.speed_threshold)?;
        d.set_item("rest_bias_walk", r.bias_walk)?;
        d.set_item("rest_gate_sigmas", r.gate_sigmas)?;
        d.set_item("rest_noise", r.noise)?;
    }
    Ok(d)
}
