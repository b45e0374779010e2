//! Public functions an embedding user calls with values at their limits: every call accepted
//! gives finite outputs.

use gyrocore::bias_walk::filter_rests;
use gyrocore::*;

/// `filter_rests` with a walk's intensity, a rest's variance or a floor near the largest float
/// (accepted as finite): the prediction `P + q |dt|` or the update's `P r` overflowed, NaN means
/// and infinite variances. Beyond 2^40 each is refused naming it; at 2^40, over rests 2^41 s
/// apart, every output is finite.
#[test]
fn filter_rests_at_its_limits_gives_finite_estimates() {
    let most = MAX_READING * MAX_READING;
    let t = [-MAX_TIME * 0.999, 0.0, MAX_TIME * 0.999];
    let v = [MAX_READING * 0.999, -MAX_READING * 0.999, 0.5];
    for (q, r, floor, name) in [
        (1e300, 1e-6, 1e-12, "q"),
        (1e-9, 1e308, 1e-12, "variances"),
        (1e-9, 3.0, 1e308, "floor"),
        (f64::MAX, 1.0, 1.0, "q"),
    ] {
        let (mut m, mut va, mut p) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        let err = filter_rests(&t, &v, &[r; 3], q, floor, false, (&mut m, &mut va, &mut p))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(&format!("invalid parameter {name} = ")),
            "{err}"
        );
    }
    for backward in [false, true] {
        for (q, r, floor) in [
            (most, most, most),
            (most, most, 1e-300),
            (0.0, 1e-300, most),
        ] {
            let (mut m, mut va, mut p) = ([0.0; 3], [0.0; 3], [0.0; 3]);
            filter_rests(
                &t,
                &v,
                &[r; 3],
                q,
                floor,
                backward,
                (&mut m, &mut va, &mut p),
            )
            .unwrap();
            assert!(
                m.iter().chain(&va).all(|x| x.is_finite()),
                "q {q:e} r {r:e} floor {floor:e}: {m:?} {va:?}"
            );
            assert!(p.iter().all(|x| !x.is_nan()), "{p:?}");
        }
    }
}

/// The rests the tracker reports on 5000 samples at 100 Hz from `t0` \[s\]: stops of 5 s of a
/// gyro that reads one value at rest (its noise below one count; 0.0125 rad/s), between turns at
/// 0.3 rad/s, with the speed, under `tracker`.
fn stops_of_one_reading(t0: f64, tracker: RestTrackerConfig) -> Vec<Rest> {
    let n = 5000;
    let t: Vec<f64> = (0..n).map(|i| t0 + i as f64 * 0.01).collect();
    let moving = |i: usize| (i / 500) % 2 == 1;
    let rate: Vec<f64> = (0..n)
        .map(|i| if moving(i) { 0.3 } else { 0.0125 })
        .collect();
    let speed: Vec<f64> = (0..n).map(|i| if moving(i) { 5.0 } else { 0.0 }).collect();
    let mut c = Preset::Tracked.config();
    c.correction.bias = StaticBias::Fixed(0.0);
    c.rest_tracker = Some(tracker);
    let mut p = Pipeline::new(c).unwrap();
    let (mut h, mut r, mut d) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut rests = Vec::new();
    let out = Outputs::all(&mut h, &mut r, &mut d);
    p.process_block_reporting(&t, &rate, None, Some(&speed), out, &mut |x| rests.push(x))
        .unwrap();
    rests
}

/// With no bias walk, after two rests of one reading the filter's variance is 0, and so is the
/// next rest's. `gate_sigmas = inf` ("no gate") then refused the third stop (`inf * 0` is NaN),
/// and any finite gate did too, for a mean that differs from the bias by its rounding alone
/// (0.01249999999999999 against 0.012500000000000008). Every stop of the one reading is accepted.
#[test]
fn stops_of_one_reading_pass_the_gate_without_a_bias_walk() {
    for gate_sigmas in [f64::INFINITY, 3.0] {
        let tracker = RestTrackerConfig {
            gate_sigmas,
            bias_walk: 0.0,
            ..RestTrackerConfig::default()
        };
        let rests = stops_of_one_reading(0.0, tracker);
        assert_eq!(rests.len(), 5, "{rests:?}");
        assert!(
            rests.iter().all(|x| x.accepted),
            "gate {gate_sigmas}: {rests:?}"
        );
    }
}

/// The change test with `change_sigmas = inf` ("no test") on a gyro that reads one value at
/// rest: a block's own noise is 0, and `inf * 0` (NaN) made every block moving, so no rest was
/// ever found. The stops are found, as with a finite number of sigmas.
#[test]
fn no_change_test_finds_the_stops_of_one_reading() {
    for change_sigmas in [f64::INFINITY, 4.0] {
        let tracker = RestTrackerConfig {
            change_sigmas,
            ..RestTrackerConfig::default()
        };
        let rests = stops_of_one_reading(1000.0, tracker);
        assert_eq!(rests.len(), 5, "change_sigmas {change_sigmas}: {rests:?}");
    }
}

/// `Up::new` of a finite direction whose length is beyond the largest float (components of
/// 1.5e308: it was refused as "three finite components, not all zero") is that direction.
#[test]
fn an_up_direction_longer_than_the_largest_float_is_normalised() {
    let up = Up::new([1.5e308, 0.0, 1.5e308]).unwrap();
    let half = std::f64::consts::FRAC_1_SQRT_2;
    for (u, e) in up.unit().iter().zip([half, 0.0, half]) {
        assert!((u - e).abs() < 1e-15, "{:?}", up.unit());
    }
    let third = Up::new([f64::MAX; 3]).unwrap().unit();
    assert!(
        third
            .iter()
            .all(|u| (u - 3f64.sqrt().recip()).abs() < 1e-15),
        "{third:?}"
    );
    assert!(Up::new([f64::INFINITY, 0.0, 1.0]).is_err());
    assert!(Up::new([f64::NAN, f64::INFINITY, 1.0]).is_err());
}

/// The rests found by `update_with_speed` over 50 s at 100 Hz (stops of 10 s between turns, a
/// bias of 0.01 rad/s) with `bad` as the speed of one sample in the middle of the second stop
/// (the noise at rest known from the first: a sample without speed is judged by its rate).
fn rests_with_one_speed(bad: f64) -> (u64, Option<Rest>) {
    let mut c = Preset::Tracked.config();
    c.correction.bias = StaticBias::Fixed(0.0);
    let mut p = Pipeline::new(c).unwrap();
    for i in 0..5000 {
        let moving = (i / 1000) % 2 == 1;
        let rate = if moving { 0.31 } else { 0.01 };
        let speed = match (i, moving) {
            (2500, _) => bad,
            (_, true) => 5.0,
            _ => 0.0,
        };
        p.update_with_speed(i as f64 * 0.01, rate, None, speed);
    }
    let tracker = p.rest_tracker().unwrap();
    (tracker.rests_found(), tracker.last_rest())
}

/// An infinite speed given to `update_with_speed` (which `process_block_with_speed` refuses) is
/// no speed, as NaN: it was taken as moving and cut the stop into two rests.
#[test]
fn an_infinite_speed_in_update_is_no_speed() {
    let none = rests_with_one_speed(f64::NAN);
    assert_eq!(none.0, 2, "{none:?}");
    for bad in [f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(rests_with_one_speed(bad), none, "speed {bad}");
    }
}
