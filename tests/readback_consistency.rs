//! A pipeline's state read back (`serde` feature) whose fields contradict each other or its
//! configuration: each refused naming what is wrong, where it ran on to NaN, to headings far
//! off, or to a state that no longer read back.
#![cfg(feature = "serde")]

mod common;
mod states;

use gyrocore::*;
use serde_json::json;
use states::{edited, refused, refuses};

/// Samples `t0 + 0.01 i` for `i` in `1..=secs * 100`: 3 s at rest, 3 s driving, in turn.
fn drive(p: &mut Pipeline, t0: f64, secs: f64) -> f64 {
    let n = (secs / 0.01) as usize;
    let t: Vec<f64> = (1..=n).map(|i| t0 + 0.01 * i as f64).collect();
    let still = |i: usize| (i / 300).is_multiple_of(2);
    let rate: Vec<f64> = (0..n)
        .map(|i| {
            if still(i) {
                0.001 + 1e-4 * ((i * 7919 % 13) as f64 - 6.0)
            } else {
                0.05
            }
        })
        .collect();
    let speed: Vec<f64> = (0..n).map(|i| if still(i) { 0.0 } else { 5.0 }).collect();
    let mut h = vec![0.0; n];
    p.process_block_with_speed(&t, &rate, None, Some(&speed), Outputs::heading(&mut h))
        .unwrap();
    h[n - 1]
}

/// A pipeline of `config` after `n` samples at 100 Hz from t = 0, each reading `rate`.
fn steady(config: PipelineConfig, n: usize, rate: f64) -> Pipeline {
    let mut p = Pipeline::new(config).unwrap();
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.01).collect();
    let mut h = vec![0.0; n];
    p.process_block(&t, &vec![rate; n], None, Outputs::heading(&mut h))
        .unwrap();
    p
}

/// A rest-tracking pipeline 20 s into a drive, several rests found.
fn tracking() -> Pipeline {
    let mut config = Preset::Tracked.config();
    config.correction.bias = StaticBias::Leading { duration: 1.0 };
    let mut p = Pipeline::new(config).unwrap();
    drive(&mut p, -0.01, 20.0);
    assert!(p.rest_tracker().unwrap().rests_found() > 0);
    p
}

/// A negative variance gave a NaN standard error, a NaN bound on HDR, every later rest refused
/// and a state that no longer read back; the tracker's other fields likewise named.
#[test]
fn a_rest_tracker_with_a_negative_variance_or_sums_out_of_order_is_refused() {
    let p = tracking();
    let v = serde_json::to_value(&p).unwrap();
    let at = "/engine/Tracked/state/tracker";
    let now = v.pointer(&format!("{at}/now")).unwrap().as_f64().unwrap();
    for (field, value, name) in [
        ("variance", -1.0, "rest tracker variance"),
        ("variance", -1e-12, "rest tracker variance"),
        ("noise", -1.0, "rest tracker noise"),
        ("noise", 1e300, "rest tracker noise"),
        ("updated", now + 1.0, "rest tracker updated"),
        ("now", -1.0, "rest tracker now"),
        ("block/sums/start", now + 1.0, "rest tracker sums start"),
        ("block/sums/duration", -1.0, "rest tracker sums duration"),
        (
            "block/sums/squared_differences",
            -1.0,
            "rest tracker sums squared",
        ),
    ] {
        let message = format!("invalid parameter {name}");
        refuses::<Pipeline>(&v, &[(&format!("{at}/{field}"), value)], &message);
    }
    // Read back untouched, it runs on and its own state reads back again.
    let mut back: Pipeline = serde_json::from_value(v).unwrap();
    drive(&mut back, 19.99, 30.0);
    let json = serde_json::to_string(&back).unwrap();
    assert!(serde_json::from_str::<Pipeline>(&json).is_ok());
}

/// The chain's copy of a fixed bias or of a dead band the configuration does not scale, edited
/// alone, ran as stored (a heading of -9992 rad where 2.19 was right) while `config()` showed
/// the configured values; likewise a noise-scaled dead band other than the rest window's.
#[test]
fn chain_settings_that_contradict_the_configuration_are_refused() {
    let mut c = Preset::Hdr.config();
    c.correction.bias = StaticBias::Fixed(0.001);
    let v = serde_json::to_value(steady(c, 100, 0.2)).unwrap();
    for (at, value) in [
        ("/engine/Hdr/config/1/threshold", 1000.0),
        ("/engine/Hdr/config/0/bias", 1000.0),
    ] {
        refuses::<Pipeline>(&v, &[(at, value)], "stages do not match");
    }
    // The pipeline's bias and its chain's, edited together, contradict the configuration.
    let both = [("/bias/value", 0.5), ("/engine/Hdr/config/0/bias", 0.5)];
    refuses::<Pipeline>(&v, &both, "invalid parameter bias = 0.5");
    // A bias learned in a window is the chain's too.
    let mut c = Preset::Combined.config();
    c.correction.bias = StaticBias::Leading { duration: 1.0 };
    c.noise_scaled.threshold_sigmas = Some(3.0);
    let mut p = Pipeline::new(c).unwrap();
    drive(&mut p, -0.01, 2.0);
    let v = serde_json::to_value(&p).unwrap();
    let bias = v
        .pointer("/engine/Hdr/config/0/bias")
        .unwrap()
        .as_f64()
        .unwrap();
    refuses::<Pipeline>(
        &v,
        &[("/engine/Hdr/config/0/bias", bias + 0.1)],
        "stages do not match",
    );
    // The noise-scaled dead band is the one the window's noise gives.
    let threshold = v.pointer("/engine/Hdr/config/1/threshold").unwrap();
    let threshold = threshold.as_f64().unwrap();
    assert!(threshold > 0.0);
    let at = "/engine/Hdr/config/1/threshold";
    refuses::<Pipeline>(&v, &[(at, 2.0 * threshold)], "invalid parameter threshold");
    // Under the tracker, the chain's bias is the tracker's.
    let v = serde_json::to_value(tracking()).unwrap();
    let at = "/engine/Tracked/state/config/0/bias";
    refuses::<Pipeline>(
        &v,
        &[(at, 0.5)],
        "invalid parameter rest tracker chain bias",
    );
}

/// An integral whose mean over its time is beyond 2^20 rad/s gave a bias of 1.05e6 rad/s, a
/// heading of -1.8e6 rad, and a state that no longer read back.
#[test]
fn a_rest_window_integral_whose_mean_is_no_reading_is_refused() {
    let config = common::with_window(Preset::StaticBias, 0.5, 1.5);
    let v = serde_json::to_value(steady(config, 130, 0.001)).unwrap();
    let err = refused::<Pipeline>(edited(&v, &[("/bias/integral", 1048576.0)]));
    assert!(err.contains("invalid parameter bias integral"), "{err}");
    // One within reach but not the bias's own is refused as well.
    let err = refused::<Pipeline>(edited(&v, &[("/bias/integral", 0.5)]));
    assert!(err.contains("invalid parameter bias = "), "{err}");
}

/// A clock at 2^40 s (every later sample skipped), a window not the configured one (the next
/// block refused naming it), a window marked over before it ran (the bias left at 0 without a
/// word), time measured without readings, a negative longest gap: each refused naming it.
#[test]
fn pipeline_fields_that_contradict_each_other_are_refused() {
    let mut p = Pipeline::new(Preset::Raw.config()).unwrap();
    p.update(0.0, 0.0);
    let v = serde_json::to_value(&p).unwrap();
    for t in [MAX_TIME, -MAX_TIME] {
        refuses::<Pipeline>(&v, &[("/clock/last", t)], "invalid parameter last_time");
    }
    refuses::<Pipeline>(
        &v,
        &[("/report/longest_gap", -1000.0)],
        "invalid parameter longest_gap",
    );
    let mut p = Pipeline::new(common::with_window(Preset::StaticBias, 0.5, 1.5)).unwrap();
    p.update(0.0, 0.001);
    let mut v = serde_json::to_value(&p).unwrap();
    let good = v.clone();
    v["bias"]["window"] = json!([2.0, 1.5]);
    let err = refused::<Pipeline>(v);
    assert!(err.contains("invalid parameter bias_window"), "{err}");
    refuses::<Pipeline>(&good, &[("/bias/duration", 1.0)], "invalid parameter bias");
    let mut c = Preset::StaticBias.config();
    c.correction.bias = StaticBias::Leading { duration: 1.0 };
    let fresh = serde_json::to_value(Pipeline::new(c).unwrap()).unwrap();
    let mut v = fresh.clone();
    v["bias"]["learning"] = json!(false);
    let err = refused::<Pipeline>(v);
    assert!(err.contains("invalid parameter bias learning"), "{err}");
    // A leading window is of the configured duration from its first sample.
    let mut p = Pipeline::new(c).unwrap();
    p.update(0.0, 0.001);
    let v = serde_json::to_value(&p).unwrap();
    let at = "/bias/window/1";
    refuses::<Pipeline>(&v, &[(at, 5.0)], "invalid parameter bias_window");
    // Read back as they were, both run on.
    let _: Pipeline = serde_json::from_value(good).unwrap();
    let _: Pipeline = serde_json::from_value(fresh).unwrap();
}
