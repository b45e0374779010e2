//! The rest tracker: rests found from speed and from the rate alone, the bias filter, its rules,
//! and the stream's invariants (chunking, per-sample updates, snapshots).

mod common;

use common::bits;
use gyrocore::{
    Error, Output, Outputs, Pipeline, PipelineConfig, Preset, Rest, RestTrackerConfig, StaticBias,
};
use proptest::prelude::*;

/// A drive at 100 Hz: `(t, rate, speed)`, with white noise of `noise` [rad/s] (a fixed
/// generator) and a bias that steps from `b0` to `b1` at `step` s. It drives (turning, at
/// 5 m/s) except in `stops` (start, end) [s], where the rate is the bias and noise.
fn drive(
    length: f64,
    stops: &[(f64, f64)],
    b0: f64,
    b1: f64,
    step: f64,
    noise: f64,
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = (length * 100.0) as usize;
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut uniform = move || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let (mut t, mut r, mut s) = (vec![], vec![], vec![]);
    for i in 0..n {
        let ti = i as f64 * 0.01;
        let stopped = stops.iter().any(|&(a, b)| ti >= a && ti <= b);
        let turn = if stopped { 0.0 } else { 0.2 * (0.3 * ti).sin() };
        let bias = if ti < step { b0 } else { b1 };
        // Sum of uniforms: near-normal noise of standard deviation `noise`.
        let w = (0..4).map(|_| uniform()).sum::<f64>() * noise * (3.0f64).sqrt();
        t.push(ti);
        r.push(turn + bias + w);
        s.push(if stopped { 0.0 } else { 5.0 });
    }
    (t, r, s)
}

/// The drives' bias walk: a step of 0.01 rad/s within a minute is about one standard deviation of
/// a random walk of this intensity [rad^2/s^3].
const WALK: f64 = 1e-6;

fn tracked(bias: StaticBias) -> PipelineConfig {
    let mut c = Preset::StaticBias.config();
    c.correction.bias = bias;
    c.rest_tracker = Some(RestTrackerConfig {
        bias_walk: WALK,
        ..RestTrackerConfig::default()
    });
    c
}

fn run(p: &mut Pipeline, t: &[f64], r: &[f64], s: Option<&[f64]>) -> Result<Vec<Output>, Error> {
    common::try_block_with_speed(p, t, r, s)
}

/// The outputs of a block and the rests the pipeline hands over while it takes it.
fn run_reporting(
    p: &mut Pipeline,
    t: &[f64],
    r: &[f64],
    s: Option<&[f64]>,
) -> (Vec<Output>, Vec<Rest>) {
    let n = t.len();
    let (mut h, mut ra, mut d) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut rests = vec![];
    let out = Outputs::all(&mut h, &mut ra, &mut d);
    p.process_block_reporting(t, r, None, s, out, &mut |rest| rests.push(rest))
        .unwrap();
    let outputs = (0..n)
        .map(|i| Output {
            heading: h[i],
            rate: ra[i],
            drift: d[i],
        })
        .collect();
    (outputs, rests)
}

fn rests_of(p: &mut Pipeline, t: &[f64], r: &[f64], s: Option<&[f64]>) -> Vec<Rest> {
    run_reporting(p, t, r, s).1
}

#[test]
fn a_bias_step_is_caught_at_a_stop_found_from_speed() {
    // No rest at the start; the bias steps at 60 s; the car stops at 30-45 s and 90-110 s.
    let (b0, b1) = (0.01, 0.02);
    let (t, r, s) = drive(150.0, &[(30.0, 45.0), (90.0, 110.0)], b0, b1, 60.0, 0.005);
    let mut p = Pipeline::new(tracked(StaticBias::Fixed(0.0))).unwrap();
    let out = run(&mut p, &t, &r, Some(&s)).unwrap();
    let rests = rests_of(
        &mut Pipeline::new(tracked(StaticBias::Fixed(0.0))).unwrap(),
        &t,
        &r,
        Some(&s),
    );
    let tracker = p.rest_tracker().unwrap();
    assert_eq!(rests.len(), 2, "{rests:?}");
    assert_eq!(tracker.last_rest(), rests.last().copied());
    assert!(
        rests.iter().all(|r| r.by_speed && r.samples > 0),
        "{rests:?}"
    );
    // Each rest without its first and last block; times count from the first sample.
    assert!(rests[0].start >= 30.0 && rests[0].end <= 45.0, "{rests:?}");
    assert!(rests[1].start >= 90.0 && rests[1].end <= 110.0, "{rests:?}");
    for (rest, truth) in rests.iter().zip([b0, b1]) {
        assert!(rest.accepted);
        assert!((rest.bias - truth).abs() < 4.0 * rest.std_error, "{rest:?}");
        // An honest standard error: about the noise over sqrt(samples), not far below it.
        let white = 0.005 / ((rest.end - rest.start) * 100.0).sqrt();
        assert!(rest.std_error >= white * 0.9, "{rest:?}");
    }
    // The filtered bias follows the step within its own standard error.
    let bias = tracker.bias();
    let e = tracker
        .std_error(&tracked(StaticBias::Fixed(0.0)).rest_tracker.unwrap())
        .unwrap();
    assert!(
        (bias - b1).abs() < 4.0 * e + 1e-12,
        "bias {bias}, std error {e}"
    );
    // After the second stop, the corrected rate is the turn with no bias left.
    let after = t.iter().position(|&ti| ti > 112.0).unwrap();
    let drift: f64 = out[after..]
        .iter()
        .zip(&t[after..])
        .map(|(o, ti)| o.rate - 0.2 * (0.3 * ti).sin())
        .sum::<f64>()
        / (out.len() - after) as f64;
    assert!(drift.abs() < 1e-3, "residual bias {drift}");
}

#[test]
fn every_rest_of_a_long_drive_is_reported() {
    // 100 stops of 6 s, one every 20 s: each reaches the caller, however the stream is cut.
    let stops: Vec<(f64, f64)> = (0..100)
        .map(|k| (20.0 * k as f64 + 10.0, 20.0 * k as f64 + 16.0))
        .collect();
    let (t, r, s) = drive(2005.0, &stops, 0.01, 0.01, 0.0, 0.005);
    let config = tracked(StaticBias::Fixed(0.0));
    let whole = rests_of(&mut Pipeline::new(config).unwrap(), &t, &r, Some(&s));
    assert_eq!(whole.len(), 100);
    for (rest, (a, b)) in whole.iter().zip(&stops) {
        assert!(
            *a <= rest.start && rest.end <= *b,
            "{rest:?} outside {a}..{b}"
        );
    }
    let mut p = Pipeline::new(config).unwrap();
    let mut chunked = vec![];
    for (tc, (rc, sc)) in t.chunks(4321).zip(r.chunks(4321).zip(s.chunks(4321))) {
        chunked.extend(rests_of(&mut p, tc, rc, Some(sc)));
    }
    assert_eq!(chunked, whole);
    assert_eq!(p.rest_tracker().unwrap().rests_found(), 100);
}

#[test]
fn rests_are_found_from_the_rate_alone_once_the_noise_at_rest_is_known() {
    // A rest window at the start gives the noise; the mid-drive stop is found without speed.
    let (t, r, _) = drive(
        120.0,
        &[(0.0, 10.0), (50.0, 65.0)],
        0.01,
        0.015,
        30.0,
        0.005,
    );
    let mut p = Pipeline::new(tracked(StaticBias::Window {
        start: 0.0,
        end: 10.0,
    }))
    .unwrap();
    let rests = rests_of(&mut p, &t, &r, None);
    let tracker = p.rest_tracker().unwrap();
    assert_eq!(rests.len(), 1, "{rests:?}");
    assert!(!rests[0].by_speed);
    // The noise of one reading, as simulated.
    assert!((rests[0].noise / 0.005 - 1.0).abs() < 0.1, "{rests:?}");
    assert!(rests[0].start >= 50.0 && rests[0].end <= 65.0, "{rests:?}");
    assert!((tracker.bias() - 0.015).abs() < 1e-3, "{}", tracker.bias());
    // Without the window there is no noise at rest to judge by, and no speed: nothing is found.
    let mut p = Pipeline::new(tracked(StaticBias::Fixed(0.0))).unwrap();
    run(&mut p, &t, &r, None).unwrap();
    assert_eq!(p.rest_tracker().unwrap().rests_found(), 0);
}

#[test]
fn a_gyro_that_reads_one_value_at_rest_has_one_rest_wherever_its_clock_starts() {
    // Quantised: one count (1.2e-3 rad/s) is far above the noise, so the stop reads one value and
    // its blocks' means differ only by rounding; at t0 = 1000 s the stop was split in two.
    let (t, rate, speed) = drive(60.0, &[(20.0, 30.0)], 0.0031, 0.0031, 0.0, 1e-5);
    let rate: Vec<f64> = rate.iter().map(|r| (r / 1.2e-3).round() * 1.2e-3).collect();
    for t0 in [0.0, 10.0, 100.0, 1000.0, 1.7e9] {
        let shifted: Vec<f64> = t.iter().map(|t| t + t0).collect();
        let rests = rests_of(
            &mut Pipeline::new(tracked(StaticBias::Fixed(0.0))).unwrap(),
            &shifted,
            &rate,
            Some(&speed),
        );
        assert_eq!(rests.len(), 1, "t0 = {t0}: {rests:?}");
        let (start, end) = (rests[0].start, rests[0].end); // from the first sample
        assert!(
            (start - 21.0).abs() < 1e-6 && (end - 29.49).abs() < 1e-6,
            "t0 = {t0}: {rests:?}"
        );
    }
}

#[test]
fn a_short_stop_is_not_a_rest() {
    // 2.5 s stopped: after dropping its first and last 1 s block, less than 3 s is left.
    let (t, r, s) = drive(60.0, &[(20.0, 22.5)], 0.01, 0.01, 0.0, 0.005);
    let mut config = tracked(StaticBias::Fixed(0.0));
    config.rest_tracker = config.rest_tracker.map(|c| RestTrackerConfig {
        block: 1.0,
        min_duration: 3.0,
        ..c
    });
    let mut p = Pipeline::new(config).unwrap();
    run(&mut p, &t, &r, Some(&s)).unwrap();
    assert_eq!(p.rest_tracker().unwrap().rests_found(), 0);
    assert_eq!(p.rest_tracker().unwrap().bias(), 0.0);
}

#[test]
fn the_dead_band_follows_the_noise_of_the_first_rest() {
    // No rest window: the dead band in noise units has nothing to scale until the stop at 30 s.
    let (t, r, s) = drive(90.0, &[(30.0, 45.0)], 0.01, 0.01, 0.0, 0.005);
    let mut config = tracked(StaticBias::Fixed(0.0));
    config.noise_scaled.threshold_sigmas = Some(3.0);
    let mut p = Pipeline::new(config).unwrap();
    let out = run(&mut p, &t, &r, Some(&s)).unwrap();
    let rest = p.rest_tracker().unwrap().last_rest().unwrap();
    let zeroed = |a: f64, b: f64| {
        t.iter()
            .zip(&out)
            .filter(|(&ti, o)| ti > a && ti < b && o.rate == 0.0)
            .count()
    };
    assert_eq!(zeroed(0.0, 30.0), 0);
    // After the rest every corrected rate below 3 sigmas (0.015 rad/s) is zeroed: the turn passes
    // zero twice a period and the stopped car reads noise only.
    let band = 3.0 * 0.005;
    let below = t
        .iter()
        .zip(&r)
        .filter(|(&ti, &ri)| ti > rest.end + 1.5 && (ri - rest.filtered).abs() < band * 0.9)
        .count();
    assert!(below > 100);
    assert!(
        zeroed(rest.end + 1.5, 90.0) >= below,
        "{} < {below}",
        zeroed(rest.end + 1.5, 90.0)
    );
}

#[test]
fn the_dead_band_widens_with_the_bias_walk_between_stops() {
    // Stops at 0-10 s and 150-165 s (noise 0.005 rad/s); between them the car drives straight
    // and noise-free with the rate 0.025 rad/s over the bias. The band, 3 standard deviations of
    // the noise and the bias's error (sqrt(0.005^2 + q dt) with q = 1e-6), passes that rate until
    // about 44 s after the first stop (3 sqrt(2.5e-5 + 1e-6 dt) = 0.025) and cuts it after.
    let (b, delta, noise) = (0.01, 0.025, 0.005);
    let (mut t, mut r, mut s) = (vec![], vec![], vec![]);
    let stopped = |ti: f64| ti < 10.0 || (150.0..=165.0).contains(&ti);
    let mut seed: u64 = 7;
    for i in 0..20_000 {
        let ti = i as f64 * 0.01;
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        // A square wave of the noise's size: its successive differences give the noise exactly.
        let w = if seed >> 63 == 0 { noise } else { -noise };
        t.push(ti);
        r.push(if stopped(ti) { b + w } else { b + delta });
        s.push(if stopped(ti) { 0.0 } else { 5.0 });
    }
    let mut config = tracked(StaticBias::Fixed(0.0));
    config.noise_scaled.threshold_sigmas = Some(3.0);
    let mut p = Pipeline::new(config).unwrap();
    let out = run(&mut p, &t, &r, Some(&s)).unwrap();
    let passed = |a: f64, z: f64| {
        t.iter()
            .zip(&out)
            .filter(|(&ti, _)| ti > a && ti < z)
            .all(|(_, o)| (o.rate - delta).abs() < 2e-3)
    };
    let cut = |a: f64, z: f64| {
        t.iter()
            .zip(&out)
            .filter(|(&ti, _)| ti > a && ti < z)
            .all(|(_, o)| o.rate == 0.0)
    };
    assert!(
        passed(12.0, 40.0),
        "the band was wide right after the first stop"
    );
    assert!(cut(60.0, 150.0), "the band did not widen between the stops");
    // The second stop measures the bias again: the band is narrow again after it.
    assert!(
        passed(167.0, 190.0),
        "the band stayed wide after the second stop"
    );
}

#[test]
fn hdrs_bound_grows_with_the_bias_walk_between_rests() {
    // A rest window, then driving straight (speed 5 m/s: no rest) with the bias 0.008 rad/s
    // higher than the window measured: HDR's I chases that residual as far as its bound lets it.
    let (t, r, _) = drive(90.0, &[(0.0, 90.0)], 0.01, 0.018, 10.0, 0.005);
    let speed = vec![5.0; t.len()];
    let mut config = tracked(StaticBias::Window {
        start: 0.0,
        end: 10.0,
    });
    // an HDR that chases quickly (an earlier tuned preset's shape with a large increment)
    let tau = 1.41;
    config.lowpass = Some(gyrocore::LowPassConfig { tau });
    config.delag = true;
    config.hdr = Some(gyrocore::HdrConfig {
        increment: 1e-3,
        turn_threshold: 1.05e-2,
        c1: 0.690,
        c2: 0.402,
        interval: 1.0,
        tau,
        max_correction: 5e-5,
    });
    // a wide bound (the value an earlier tuned preset had), so that HDR reaches past the window's
    config.noise_scaled = gyrocore::NoiseScaled {
        threshold_sigmas: None,
        hdr_bound_sigmas: Some(14.3),
    };
    let mut p = Pipeline::new(config).unwrap();
    let out = run(&mut p, &t, &r, Some(&speed)).unwrap();
    assert_eq!(p.rest_tracker().unwrap().rests_found(), 0);
    // The window's bound alone: 14.3 standard errors of its bias.
    let window_bound = 14.3 * p.rest_statistics().unwrap().bias_std_error;
    assert!(window_bound < 4e-3, "{window_bound}");
    let largest = out.iter().map(|o| o.drift.abs()).fold(0.0, f64::max);
    assert!(
        largest > 6e-3,
        "HDR stayed within the window's bound: {largest}"
    );
    let error = p
        .rest_tracker()
        .unwrap()
        .std_error(&config.rest_tracker.unwrap())
        .unwrap();
    assert!(out.last().unwrap().drift.abs() <= 14.3 * error);
}

#[test]
fn the_rules_name_the_parameter_at_fault() {
    type Spoil = fn(&mut RestTrackerConfig);
    let cases: [(&str, Spoil); 8] = [
        ("rest_block", |c| c.block = 0.0),
        ("rest_min_duration", |c| c.min_duration = 1.5 * c.block),
        ("rest_noise_ratio", |c| c.noise_ratio = 0.5),
        ("rest_change_sigmas", |c| c.change_sigmas = 0.0),
        ("rest_speed_threshold", |c| c.speed_threshold = -1.0),
        ("rest_bias_walk", |c| c.bias_walk = f64::INFINITY),
        ("rest_gate_sigmas", |c| c.gate_sigmas = 0.0),
        ("rest_noise", |c| c.noise = Some(-1.0)),
    ];
    for (name, spoil) in cases {
        let mut config = tracked(StaticBias::Fixed(0.0));
        spoil(config.rest_tracker.as_mut().unwrap());
        match Pipeline::new(config) {
            Err(Error::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{name}: {other:?}"),
        }
    }
    let ungated = RestTrackerConfig {
        gate_sigmas: f64::INFINITY,
        change_sigmas: f64::INFINITY,
        ..RestTrackerConfig::default()
    };
    assert!(ungated.validate().is_ok());
}

#[test]
fn bad_speed_is_refused_with_its_index_and_changes_nothing() {
    let (t, r, mut s) = drive(10.0, &[], 0.0, 0.0, 0.0, 0.001);
    let mut p = Pipeline::new(tracked(StaticBias::Fixed(0.0))).unwrap();
    let before = p.clone();
    let e = run(&mut p, &t, &r, Some(&s[..5])).unwrap_err();
    assert!(
        matches!(e, Error::LengthMismatch { what: "speed", .. }),
        "{e}"
    );
    s[7] = f64::INFINITY;
    let e = run(&mut p, &t, &r, Some(&s)).unwrap_err();
    assert!(
        matches!(
            e,
            Error::NonFinite {
                what: "speed",
                index: 7,
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(p, before);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    #[test]
    fn chunks_updates_and_snapshots_are_bit_identical(
        cuts in proptest::collection::vec(0usize..9000, 0..6),
        snapshot in 0usize..9000,
        window in any::<bool>(),
        hdr in any::<bool>(),
    ) {
        let (t, r, s) = drive(90.0, &[(0.0, 8.0), (25.0, 40.0), (60.0, 75.0)], 0.01, 0.02, 50.0, 0.004);
        // Speed only for part of the drive: the rest is judged by the rate.
        let s: Vec<f64> = s.iter().enumerate().map(|(i, &v)| if i < 4500 { v } else { f64::NAN }).collect();
        let mut config = tracked(if window {
            StaticBias::Window { start: 0.0, end: 8.0 }
        } else {
            StaticBias::Fixed(0.0)
        });
        if hdr {
            let tuned = Preset::Tuned.config();
            config = PipelineConfig { correction: config.correction, rest_tracker: config.rest_tracker, ..tuned };
        }
        let mut whole = Pipeline::new(config).unwrap();
        let (expected, rests) = run_reporting(&mut whole, &t, &r, Some(&s));
        prop_assert!(rests.len() >= 2);
        prop_assert_eq!(rests.len() as u64, whole.rest_tracker().unwrap().rests_found());

        let mut cuts = cuts;
        cuts.sort_unstable();
        let mut chunked = Pipeline::new(config).unwrap();
        let (mut got, mut got_rests) = (vec![], vec![]);
        let mut from = 0;
        for &c in cuts.iter().chain([&t.len()]) {
            let c = c.max(from);
            let (o, found) = run_reporting(&mut chunked, &t[from..c], &r[from..c], Some(&s[from..c]));
            got.extend(o);
            got_rests.extend(found);
            from = c;
        }
        prop_assert_eq!(bits(&got), bits(&expected));
        prop_assert_eq!(&got_rests, &rests);
        prop_assert_eq!(&chunked, &whole);

        // Sample by sample, each rest is read after the sample that ends it.
        let mut single = Pipeline::new(config).unwrap();
        let mut single_rests = vec![];
        let mut outputs = vec![];
        for i in 0..t.len() {
            outputs.push(single.update_with_speed(t[i], r[i], None, s[i]));
            let tracker = single.rest_tracker().unwrap();
            if tracker.ended_rest() {
                single_rests.extend(tracker.last_rest());
            }
        }
        prop_assert_eq!(bits(&outputs), bits(&expected));
        prop_assert_eq!(&single_rests, &rests);

        // a serde snapshot mid-stream (the snapshot needs the crate's serde feature)
        #[cfg(feature = "serde")]
        {
            let mut first = Pipeline::new(config).unwrap();
            let mut got = run(&mut first, &t[..snapshot], &r[..snapshot], Some(&s[..snapshot])).unwrap();
            let json = serde_json::to_string(&first).unwrap();
            let mut restored: Pipeline = serde_json::from_str(&json).unwrap();
            got.extend(run(&mut restored, &t[snapshot..], &r[snapshot..], Some(&s[snapshot..])).unwrap());
            prop_assert_eq!(bits(&got), bits(&expected));
        }
        #[cfg(not(feature = "serde"))]
        let _ = snapshot;
    }
}
