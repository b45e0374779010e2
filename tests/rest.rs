//! The rest window's noise statistics and what they scale: the dead band and HDR's bound
//! (`NoiseScaled`), and the bound itself (`HdrConfig::max_correction`).

mod common;

use gyrocore::sim::Gaussian;
use gyrocore::*;

/// A 10 Hz stream: `rest` seconds of `bias + noise`, then `rate_after(t)` plus the same bias.
fn stream(
    rest: f64,
    total: f64,
    bias: f64,
    noise: impl FnMut() -> f64,
    rate_after: impl Fn(f64) -> f64,
) -> (Vec<f64>, Vec<f64>) {
    let mut noise = noise;
    let t: Vec<f64> = (0..(total * 10.0) as usize)
        .map(|i| i as f64 * 0.1)
        .collect();
    let r = t
        .iter()
        .map(|&ti| bias + noise() + if ti > rest { rate_after(ti) } else { 0.0 })
        .collect();
    (t, r)
}

fn headings(config: PipelineConfig, t: &[f64], r: &[f64]) -> Vec<f64> {
    let mut p = Pipeline::new(config).unwrap();
    common::try_block(&mut p, t, r)
        .unwrap()
        .iter()
        .map(|o| o.heading)
        .collect()
}

#[test]
fn white_noise_gives_its_standard_deviation_and_the_standard_error_of_the_mean() {
    let sigma = 0.002;
    let n = 200.0; // 20 s at 10 Hz
    let (mut noise_ratio, mut error_ratio) = (0.0, 0.0);
    let trials = 200;
    for seed in 0..trials {
        let mut g = Gaussian::new(seed, 0);
        let (t, r) = stream(20.0, 25.0, 0.01, || sigma * g.sample(), |_| 0.0);
        let mut p = Pipeline::new(common::with_window(Preset::StaticBias, 0.0, 20.0)).unwrap();
        common::try_block(&mut p, &t, &r).unwrap();
        let s = p.rest_statistics().unwrap();
        noise_ratio += s.noise / sigma / trials as f64;
        error_ratio += s.bias_std_error / (sigma / f64::sqrt(n)) / trials as f64;
    }
    assert!(
        (noise_ratio - 1.0).abs() < 0.02,
        "noise / sigma = {noise_ratio}"
    );
    // Batch means with 8 parts: E[s] = c4(8) sigma_mean = 0.965 sigma_mean.
    assert!(
        (error_ratio - 0.965).abs() < 0.05,
        "std error / (sigma / sqrt n) = {error_ratio}"
    );
}

#[test]
fn correlated_noise_gets_the_larger_standard_error_it_has() {
    // AR(1) noise with coefficient 0.9: the mean of n readings varies about 19 times as much as
    // for white noise of the same variance, (1 + a) / (1 - a); sqrt gives 4.36 in std.
    let a: f64 = 0.9;
    let mut ratio = 0.0;
    let trials = 100;
    for seed in 0..trials {
        let mut g = Gaussian::new(seed, 1);
        let mut x = 0.0;
        let mut next = || {
            x = a * x + f64::sqrt(1.0 - a * a) * 0.002 * g.sample();
            x
        };
        let (t, r) = stream(60.0, 61.0, 0.0, &mut next, |_| 0.0);
        let mut p = Pipeline::new(common::with_window(Preset::StaticBias, 0.0, 60.0)).unwrap();
        common::try_block(&mut p, &t, &r).unwrap();
        let s = p.rest_statistics().unwrap();
        ratio += s.bias_std_error / (0.002 / f64::sqrt(600.0)) / trials as f64;
    }
    let expected = f64::sqrt((1.0 + a) / (1.0 - a));
    assert!(
        (ratio / expected - 0.965).abs() < 0.1,
        "ratio {ratio}, white-noise formula would give 1"
    );
}

#[test]
fn a_fixed_bias_or_a_window_in_progress_has_no_statistics() {
    let (t, r) = stream(20.0, 30.0, 0.0, || 0.0, |_| 0.0);
    let mut fixed = Pipeline::new(Preset::StaticBias.config()).unwrap();
    common::try_block(&mut fixed, &t, &r).unwrap();
    assert_eq!(fixed.rest_statistics(), None);
    let mut measuring = Pipeline::new(common::with_window(Preset::StaticBias, 0.0, 20.0)).unwrap();
    common::try_block(&mut measuring, &t[..100], &r[..100]).unwrap();
    assert_eq!(measuring.rest_statistics(), None);
    common::try_block(&mut measuring, &t[100..], &r[100..]).unwrap();
    assert!(measuring.rest_statistics().is_some());
}

/// Gentle curves, all below Table III's turn switch: what HDR must not take for drift.
fn gentle_curves(t: f64) -> f64 {
    0.008 * f64::sin(t / 40.0) + 0.004 * f64::sin(t / 170.0)
}

#[test]
fn a_noise_free_rest_turns_the_dead_band_and_hdr_off() {
    // A gyro without noise: the scaled dead band and bound are 0, and the heading is that of
    // static bias removal (to rounding: the low-pass and de-lag still run), even with Table III's
    // HDR and, before, a 0.3 deg/s threshold.
    let (t, r) = stream(20.0, 1200.0, 0.02, || 0.0, gentle_curves);
    let mut config = common::with_window(Preset::Combined, 0.0, 20.0);
    config.noise_scaled = NoiseScaled {
        threshold_sigmas: Some(1.0),
        hdr_bound_sigmas: Some(3.0),
    };
    let scaled = headings(config, &t, &r);
    let plain = headings(common::with_window(Preset::StaticBias, 0.0, 20.0), &t, &r);
    let worst = |a: &[f64]| {
        a.iter()
            .zip(&plain)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    assert!(
        worst(&scaled) < 1e-9,
        "differs from static bias removal by {} rad",
        worst(&scaled)
    );
    // Without the scaling, Table III corrects the curves as drift.
    let unscaled = headings(common::with_window(Preset::Combined, 0.0, 20.0), &t, &r);
    assert!(
        worst(&unscaled) > 0.1,
        "Table III changed the heading by only {} rad",
        worst(&unscaled)
    );
}

#[test]
fn hdr_never_corrects_beyond_its_bound() {
    let bound = 2e-4;
    let mut config = common::with_window(Preset::Hdr, 0.0, 20.0);
    config.hdr = Some(HdrConfig {
        max_correction: bound,
        ..HdrConfig::table_iii()
    });
    let (t, r) = stream(20.0, 600.0, 0.0, || 0.0, |_| 0.003);
    let mut p = Pipeline::new(config).unwrap();
    let out = common::try_block(&mut p, &t, &r).unwrap();
    let largest = out.iter().map(|o| o.drift.abs()).fold(0.0, f64::max);
    assert_eq!(
        largest, bound,
        "HDR chases the 0.003 rad/s curve up to its bound, not further"
    );
    // With the bound, the heading error over the curve is at most bound * time.
    let truth = 0.003 * (t[t.len() - 1] - 20.0);
    assert!((out[out.len() - 1].heading - truth).abs() <= bound * 600.0);
}

#[test]
fn the_scaled_bound_survives_a_gap_restart_and_a_reset_restores_the_configured_one() {
    let mut g = Gaussian::new(7, 0);
    let (t, r) = stream(20.0, 40.0, 0.0, || 1e-3 * g.sample(), |_| 0.0);
    let mut config = common::with_window(Preset::Hdr, 0.0, 20.0);
    config.noise_scaled.hdr_bound_sigmas = Some(2.0);
    config.input.gap_action = GapAction::Reset;
    let mut p = Pipeline::new(config).unwrap();
    common::try_block(&mut p, &t, &r).unwrap();
    let expected = 2.0 * p.rest_statistics().unwrap().bias_std_error;
    // A gap of 10 s restarts HDR; the bound is the sensor's and stays. (0.005 rad/s is below
    // the turn switch, so HDR chases it.)
    let late: Vec<f64> = (0..600).map(|i| 50.0 + i as f64 * 0.1).collect();
    let out = common::try_block(&mut p, &late, &vec![0.005; 600]).unwrap();
    assert_eq!(p.report().gaps, 1);
    let largest = out.iter().map(|o| o.drift.abs()).fold(0.0, f64::max);
    assert!(
        largest > 0.0 && largest <= expected,
        "{largest} vs {expected}"
    );
    p.reset();
    assert_eq!(p, Pipeline::new(config).unwrap());
}

/// A factor beyond 2^20 is refused too: 1e308 over a noisy rest made the dead band infinite
/// (every rate 0, and a state `serde_json` wrote but could not read back). At 2^20 over a rest
/// whose readings swing by +-3 rad/s the pipeline round-trips.
#[test]
fn negative_non_finite_or_huge_factors_are_rejected() {
    type Set = fn(&mut NoiseScaled, f64);
    let settings: [(&str, Set); 2] = [
        ("threshold_sigmas", |n, v| n.threshold_sigmas = Some(v)),
        ("hdr_bound_sigmas", |n, v| n.hdr_bound_sigmas = Some(v)),
    ];
    for (field, set) in settings {
        for bad in [-1.0, f64::NAN, f64::INFINITY, 1e308, 2.0 * MAX_READING] {
            let mut config = Preset::Hdr.config();
            set(&mut config.noise_scaled, bad);
            let err = Pipeline::new(config).unwrap_err();
            assert!(
                matches!(err, Error::InvalidParameter { name, .. } if name == field),
                "{err:?}"
            );
        }
    }
}

#[cfg(feature = "serde")]
#[test]
fn the_largest_factors_over_a_noisy_rest_round_trip() {
    let mut config = Preset::Tuned.config();
    config.correction.bias = StaticBias::Leading { duration: 1.0 };
    config.noise_scaled = NoiseScaled {
        threshold_sigmas: Some(MAX_READING),
        hdr_bound_sigmas: Some(MAX_READING),
    };
    let mut p = Pipeline::new(config).unwrap();
    for i in 0..300 {
        p.update(i as f64 * 0.01, if i % 2 == 0 { 3.0 } else { -3.0 });
    }
    let json = serde_json::to_string(&p).unwrap();
    assert_eq!(serde_json::from_str::<Pipeline>(&json).unwrap(), p);
}
