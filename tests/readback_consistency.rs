//! A pipeline's state read back (`serde` feature) whose fields contradict each other or its
//! configuration: each refused naming what is wrong, where it ran on to NaN, to headings far
//! off, or to a state that no longer read back.
#![cfg(feature = "serde")]

mod states;

use gyrocore::*;
use states::refuses;

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
