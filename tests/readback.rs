//! States read back (`serde` feature) by an embedding user: a state no valid input leaves (a
//! heading or a reading beyond what the limits of a sample allow, a clock beyond `MAX_TIME`) is
//! refused naming its field (the heading-fix filter's covariance: tests/readback_fusion.rs).
#![cfg(feature = "serde")]

use gyrocore::*;
use serde_json::{json, Value};

mod states;
use states::{edited, fusion, read, refuses, Reader};

/// A pipeline of the combined preset that holds the last reading over a NaN, after a few samples.
fn holding() -> Pipeline {
    let mut c = Preset::Combined.config();
    c.input.non_finite = NonFinite::Hold;
    let mut p = Pipeline::new(c).unwrap();
    for i in 0..50 {
        p.update(i as f64 * 0.01, 0.01);
    }
    p
}

/// A heading beyond 2^225 rad, which no valid input reaches (an initial heading within 2^20 rad,
/// a rate below 2^183 rad/s over 2^41 s), read back as a pipeline's, an integrator's or the
/// heading-fix filter's: each was read back (up to 2^256), and no increment counted on it.
/// Refused naming it; a heading of 2^224 reads back.
#[test]
fn a_heading_beyond_what_valid_input_reaches_is_refused() {
    let beyond = 2f64.powi(225) * (1.0 + f64::EPSILON);
    let within = 2f64.powi(224);
    let pipeline = serde_json::to_value(holding()).unwrap();
    let mut i = Integrator::new(IntegratorConfig::default()).unwrap();
    i.update(0.0, 1.0);
    let integrator = serde_json::to_value(i).unwrap();
    let fusion = serde_json::to_value(fusion()).unwrap();
    let cases: [(&Value, &str, &str, Reader); 4] = [
        (
            &pipeline,
            "/engine/Hdr/state/3/heading",
            "heading",
            read::<Pipeline>,
        ),
        (
            &pipeline,
            "/last_output/heading",
            "last heading",
            read::<Pipeline>,
        ),
        (&integrator, "/state/heading", "heading", read::<Integrator>),
        (&fusion, "/segment/x/0", "filter heading", read::<Fusion>),
    ];
    for (v, at, name, read) in cases {
        for value in [beyond, -beyond, 1e70] {
            let err = read(edited(v, &[(at, value)])).unwrap_err();
            let expected = format!("invalid parameter {name} = ");
            assert!(
                err.contains(&expected) && err.contains("within +-2^225 rad"),
                "{at} = {value:e}: {err}"
            );
        }
        assert!(read(edited(v, &[(at, within)])).is_ok(), "{at} = 2^224");
    }
}

/// The reading a pipeline holds over a NaN (`NonFinite::Hold`), read back beyond the limit of a
/// reading: it was held into infinite headings. The output a skipped sample repeats, read back
/// beyond reach: it was repeated as it was. Both refused naming them.
#[test]
fn a_held_reading_or_repeated_output_beyond_reach_is_refused() {
    let v = serde_json::to_value(holding()).unwrap();
    for (at, value, message) in [
        (
            "/last_reading/0",
            1e308,
            "invalid parameter last rate = 1e308",
        ),
        (
            "/last_reading/0",
            -MAX_READING,
            "invalid parameter last rate = -1048576",
        ),
        (
            "/last_reading/1",
            5e6,
            "invalid parameter last temperature = 5000000",
        ),
        (
            "/last_output/rate",
            1e308,
            "invalid parameter last output rate = 1e308",
        ),
        (
            "/last_output/drift",
            -1e308,
            "invalid parameter last drift = -1e308",
        ),
    ] {
        refuses::<Pipeline>(&v, &[(at, value)], message);
    }
    // the largest reading the policy takes is held, and the headings stay finite
    let mut e = v.clone();
    e["last_reading"][0] = json!(MAX_READING * (1.0 - f64::EPSILON));
    let mut p: Pipeline = serde_json::from_value(e).unwrap();
    for k in 0..5 {
        let out = p.update(1.0 + k as f64 * 0.01, f64::NAN);
        assert!(out.heading.is_finite(), "{out:?}");
    }
}

/// A stand-alone stage read back with a clock beyond 2^40 s (-1e308 made the next block's first
/// interval 1e308: an infinite heading; 1e308 refused every later block) or a last output of
/// 1e308 (repeated for a skipped sample): refused naming it.
#[test]
fn a_stand_alone_stage_with_a_clock_or_output_beyond_reach_is_refused() {
    let mut i = Integrator::new(IntegratorConfig::default()).unwrap();
    i.update(0.0, 1.0);
    let mut d = DeLag::new(LowPassConfig { tau: 0.75 }).unwrap();
    d.update(0.0, 1.0);
    let integrator = serde_json::to_value(i).unwrap();
    let delag = serde_json::to_value(d).unwrap();
    for (at, value, message) in [
        (
            "/clock/last",
            -1e308,
            "invalid parameter last_time = -1e308",
        ),
        ("/clock/last", 1e308, "invalid parameter last_time = 1e308"),
        (
            "/clock/last",
            2.0 * MAX_TIME,
            "invalid parameter last_time = 2199023255552",
        ),
        ("/last", 1e308, "invalid parameter last output = 1e308"),
    ] {
        refuses::<Integrator>(&integrator, &[(at, value)], message);
        refuses::<DeLag>(&delag, &[(at, value)], message);
    }
    // a clock edited to a time valid input reaches carries on, with finite outputs
    let mut e = integrator.clone();
    e["clock"]["last"] = json!(-1e9);
    let mut i: Integrator = serde_json::from_value(e).unwrap();
    let mut out = [0.0; 2];
    i.process_block(&[0.0, 0.1], &[2.0, 2.0], &mut out).unwrap();
    assert!(out.iter().all(|h| h.is_finite()), "{out:?}");
}

/// A `Downsample` read back with an open block no valid input leaves: an integral of 1e308 over
/// a time of 1e-300 (its next mean was infinite), a time taken of -1e308 (the step never closed
/// again), a clock beyond 2^40 s. Only its configuration was checked; each is refused naming it.
#[test]
fn a_downsample_with_a_block_beyond_reach_is_refused() {
    let mut d = Downsample::new(DownsampleConfig { interval: 1.0 }).unwrap();
    for i in 0..150 {
        d.update(i as f64 * 0.01, 0.3);
    }
    let v = serde_json::to_value(&d).unwrap();
    let edits: [(&[(&str, f64)], &str); 4] = [
        (
            &[("/block/sum", 1e308), ("/block/duration", 1e-300)],
            "invalid parameter block integral = 1e308",
        ),
        (
            &[("/block/duration", -1e308)],
            "invalid parameter block duration = -1e308",
        ),
        (
            &[("/block/elapsed", -1e308)],
            "invalid parameter block elapsed = -1e308",
        ),
        (
            &[("/clock/last", -1e308)],
            "invalid parameter last_time = -1e308",
        ),
    ];
    for (edit, message) in edits {
        refuses::<Downsample>(&v, edit, message);
    }
    // read back as it was, it carries on with finite means
    let mut back: Downsample = serde_json::from_value(v).unwrap();
    let closed: Vec<_> = (150..400)
        .filter_map(|i| back.update(i as f64 * 0.01, 0.3))
        .collect();
    assert!(!closed.is_empty() && closed.iter().all(|(_, m)| (m - 0.3).abs() < 1e-12));
}

/// A stand-alone `Correction` read back with a bias in force of 1e308 (its corrected rates were
/// infinite) or a clock beyond 2^40 s: only its configuration and its estimate were checked.
#[test]
fn a_correction_with_a_bias_or_clock_beyond_reach_is_refused() {
    let mut c = Correction::new(CorrectionConfig {
        bias: StaticBias::Leading { duration: 100.0 },
        scale: 2.0,
        ..Default::default()
    })
    .unwrap();
    for i in 0..50 {
        c.update(i as f64 * 0.01, 0.01);
    }
    let v = serde_json::to_value(&c).unwrap();
    for (at, value, message) in [
        ("/calibration/bias", 1e308, "invalid parameter bias = 1e308"),
        (
            "/clock/last",
            -1e308,
            "invalid parameter last_time = -1e308",
        ),
    ] {
        refuses::<Correction>(&v, &[(at, value)], message);
    }
    let mut back: Correction = serde_json::from_value(v).unwrap();
    assert!(back.update(1.0, -5.0).is_finite());
}
