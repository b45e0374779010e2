//! A rest window's state read back (`serde` feature) mid-window: its noise sums (the last
//! reading, the squared differences, each part's integral and time) must be ones readings within
//! `MAX_READING` leave; the rest statistics and the headings after the window stay finite.
#![cfg(feature = "serde")]

use gyrocore::*;
use serde_json::json;

/// A pipeline of `preset` measuring a 3 s leading window, 1 s into it, with its noise scaling.
fn measuring(preset: Preset) -> Pipeline {
    let mut c = preset.config();
    c.correction.bias = StaticBias::Leading { duration: 3.0 };
    let mut p = Pipeline::new(c).unwrap();
    for i in 0..100 {
        p.update(i as f64 * 0.01, 0.001 * ((i * 7919 % 13) as f64));
    }
    p
}

/// Runs `p` through the rest of its window and a turn: every heading and statistic finite.
fn run_on(mut p: Pipeline) -> Result<(), String> {
    let t: Vec<f64> = (100..2000).map(|i| i as f64 * 0.01).collect();
    let r: Vec<f64> = (100..2000)
        .map(|i| 0.001 * ((i * 7919 % 13) as f64) + if i > 600 { 0.2 } else { 0.0 })
        .collect();
    let mut h = vec![0.0; t.len()];
    p.process_block(&t, &r, None, Outputs::heading(&mut h))
        .map_err(|e| e.to_string())?;
    if let Some(i) = h.iter().position(|x| !x.is_finite()) {
        return Err(format!("heading {} at {}", h[i], t[i]));
    }
    match p.rest_statistics() {
        Some(s) if !(s.noise.is_finite() && s.bias_std_error.is_finite()) => Err(format!("{s:?}")),
        _ => Ok(()),
    }
}

/// A part of the window's time of 1e-300 under its integral (the rest tracker's headings were
/// NaN from the window's end on, the bias's standard error infinite), squared differences of -1
/// (a NaN noise) or of 1e308, an integral of 1e308, a last reading of 1e308 (an infinite noise):
/// each refused naming it. Read back as it was, the window runs on to finite statistics.
#[test]
fn a_rest_window_with_sums_beyond_reach_is_refused() {
    for preset in [Preset::Tracked, Preset::Combined] {
        let p = measuring(preset);
        let v = serde_json::to_value(&p).unwrap();
        for (at, value, name) in [
            (
                "/bias/noise/batch_duration/0",
                1e-300,
                "rest window part integral",
            ),
            (
                "/bias/noise/batch_duration/1",
                -1.0,
                "rest window part duration",
            ),
            (
                "/bias/noise/batch_integral/0",
                1e308,
                "rest window part integral",
            ),
            (
                "/bias/noise/squared_differences",
                -1.0,
                "rest window squared differences",
            ),
            (
                "/bias/noise/squared_differences",
                1e308,
                "rest window squared differences",
            ),
            ("/bias/noise/previous", 1e308, "rest window last reading"),
        ] {
            let mut e = v.clone();
            *e.pointer_mut(at).unwrap() = json!(value);
            let err = serde_json::from_value::<Pipeline>(e)
                .map(run_on)
                .unwrap_err()
                .to_string();
            assert!(
                err.contains(&format!("invalid parameter {name} = ")),
                "{preset:?} {at} = {value:e}: {err}"
            );
        }
        run_on(serde_json::from_value(v).unwrap()).unwrap();
    }
}
