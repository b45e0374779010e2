//! The simulated gyro (Hong eq 1, 10-11): reference vectors of the random generators, statistics
//! with closed forms, reproducibility, continuous-time drift, sampling, and the stage invariants.

use gyrocore::sim::{Gaussian, Sampler, SplitMix64, Xoshiro256PlusPlus};
use gyrocore::{Error, GyroModel, GyroModelConfig, Stage, TemperatureProfile};

fn deg(x: f64) -> f64 {
    x.to_radians()
}

/// Readings of `model` at rest at `n` samples of `1 / rate_hz` seconds.
fn at_rest(model: &mut GyroModel, n: usize) -> Vec<gyrocore::GyroSample> {
    let dt = 1.0 / model.config().rate_hz;
    (0..n).map(|i| model.measure(i as f64 * dt, 0.0)).collect()
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

fn variance(x: &[f64]) -> f64 {
    let m = mean(x);
    x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (x.len() - 1) as f64
}

#[test]
fn splitmix64_matches_the_reference_outputs() {
    // Seed 1234567: the published first outputs of Vigna's splitmix64.c.
    let mut rng = SplitMix64::new(1234567);
    let expected = [
        6457827717110365317,
        3203168211198807973,
        9817491932198370423,
        4593380528125082431,
        16408922859458223821,
    ];
    for e in expected {
        assert_eq!(rng.next_u64(), e);
    }
}

#[test]
fn xoshiro256plusplus_matches_the_reference_outputs() {
    // State [1, 2, 3, 4]: the outputs of the reference xoshiro256plusplus.c.
    let mut rng = Xoshiro256PlusPlus::from_state([1, 2, 3, 4]);
    let expected = [
        41943041,
        58720359,
        3588806011781223,
        3591011842654386,
        9228616714210784205,
        9973669472204895162,
        14011001112246962877,
        12406186145184390807,
        15849039046786891736,
        10450023813501588000,
    ];
    for e in expected {
        assert_eq!(rng.next_u64(), e);
    }
}

#[test]
fn gaussian_deviates_have_mean_0_variance_1_and_normal_tails() {
    let mut g = Gaussian::new(7, 0);
    let x: Vec<f64> = (0..400_000).map(|_| g.sample()).collect();
    let n = x.len() as f64;
    // Standard errors: mean 1/sqrt(n), variance sqrt(2/n); 5 of them is far outside chance.
    assert!(mean(&x).abs() < 5.0 / n.sqrt(), "mean {}", mean(&x));
    assert!((variance(&x) - 1.0).abs() < 5.0 * (2.0 / n).sqrt());
    // P(|z| > 2) = 0.0455 for a normal distribution.
    let tail = x.iter().filter(|v| v.abs() > 2.0).count() as f64 / n;
    let p = 0.0455;
    assert!(
        (tail - p).abs() < 5.0 * (p * (1.0 - p) / n).sqrt(),
        "tail {tail}"
    );
    let u = Gaussian::new(7, 1).uniform();
    assert!((0.0..1.0).contains(&u));
}

#[test]
fn different_streams_and_seeds_are_unrelated() {
    let a: Vec<f64> = {
        let mut g = Gaussian::new(1, 1);
        (0..1000).map(|_| g.sample()).collect()
    };
    let b: Vec<f64> = {
        let mut g = Gaussian::new(1, 2);
        (0..1000).map(|_| g.sample()).collect()
    };
    let c: Vec<f64> = {
        let mut g = Gaussian::new(2, 1);
        (0..1000).map(|_| g.sample()).collect()
    };
    let corr = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>() / 1000.0;
    assert!(corr(&a, &b).abs() < 0.15 && corr(&a, &c).abs() < 0.15);
}

#[test]
fn a_perfect_gyro_reads_the_true_rate() {
    let mut m = GyroModel::new(GyroModelConfig::ideal(100.0), 0).unwrap();
    for i in 0..1000 {
        let r = (i as f64 * 0.01).sin();
        let s = m.measure(i as f64 * 0.01, r);
        assert_eq!(s.rate, r);
        assert_eq!((s.bias, s.scale, s.temperature), (0.0, 0.0, 25.0));
    }
}

#[test]
fn noise_free_readings_follow_hong_eq_1_with_cw_ccw_asymmetry() {
    // Hong section 3.1: s = -10 %, b = 0.1 rad/s; FOG-style asymmetry of 1 % between directions.
    let config = GyroModelConfig {
        scale_error: -0.1,
        scale_asymmetry: 0.01,
        bias: 0.1,
        ..GyroModelConfig::ideal(100.0)
    };
    let mut m = GyroModel::new(config, 3).unwrap();
    for (i, r) in [0.5, -0.5, 0.0, 2.0, -1.0].into_iter().enumerate() {
        let s = m.measure(i as f64, r);
        let scale = -0.1 + 0.005 * r.signum() * (r != 0.0) as i32 as f64;
        assert!(
            (s.rate - ((1.0 + scale) * r + 0.1)).abs() < 1e-15,
            "r = {r}"
        );
        assert_eq!(s.scale, scale);
    }
}

#[test]
fn bias_and_scale_follow_the_temperature_profile() {
    // FOG eq 5: turn error -0.52 deg per degC per 360 deg.
    let profile = TemperatureProfile {
        start: 20.0,
        end: 40.0,
        time_constant: 100.0,
    };
    let config = GyroModelConfig {
        scale_temperature: -0.52 / 360.0,
        bias_temperature: deg(0.001),
        temperature: profile,
        reference_temperature: 30.0,
        ..GyroModelConfig::ideal(10.0)
    };
    let mut m = GyroModel::new(config, 0).unwrap();
    for t in [0.0, 50.0, 100.0, 1000.0] {
        let s = m.measure(1000.0 + t, 1.0);
        let temp = 40.0 - 20.0 * (-t / 100.0f64).exp();
        assert!((s.temperature - temp).abs() < 1e-12);
        let scale = -0.52 / 360.0 * (temp - 30.0);
        let bias = deg(0.001) * (temp - 30.0);
        assert!(
            (s.rate - ((1.0 + scale) * 1.0 + bias)).abs() < 1e-12,
            "t = {t}"
        );
    }
}

#[test]
fn white_noise_has_the_angle_random_walk_standard_deviation() {
    // sigma = N sqrt(rate): 2.5 deg/sqrt(h) at 100 Hz is 0.4167 deg/s per sample.
    let arw = deg(2.5) / 60.0;
    let config = GyroModelConfig {
        arw,
        bias: 0.01,
        ..GyroModelConfig::ideal(100.0)
    };
    let mut m = GyroModel::new(config, 11).unwrap();
    let rate: Vec<f64> = at_rest(&mut m, 200_000).iter().map(|s| s.rate).collect();
    let sd = arw * 100f64.sqrt();
    let n = rate.len() as f64;
    assert!((mean(&rate) - 0.01).abs() < 5.0 * sd / n.sqrt());
    assert!((variance(&rate).sqrt() / sd - 1.0).abs() < 5.0 / (2.0 * n).sqrt());
    // White: neighbouring readings are uncorrelated.
    let m0 = mean(&rate);
    let lag1 = rate
        .windows(2)
        .map(|w| (w[0] - m0) * (w[1] - m0))
        .sum::<f64>()
        / (n - 1.0);
    assert!((lag1 / variance(&rate)).abs() < 5.0 / n.sqrt());
}

#[test]
fn band_limited_noise_has_the_filter_variance_and_keeps_the_density() {
    // A 15 Hz first-order low-pass at 100 Hz: variance N^2 f (1 - a) / (1 + a), lag-1 correlation a,
    // and 1 s means with the variance N^2 / 1 s of the unfiltered density.
    let arw = deg(2.5) / 60.0;
    let config = GyroModelConfig {
        arw,
        bandwidth: 15.0,
        ..GyroModelConfig::ideal(100.0)
    };
    let a = (-std::f64::consts::TAU * 15.0 / 100.0f64).exp();
    let mut m = GyroModel::new(config, 21).unwrap();
    let x: Vec<f64> = at_rest(&mut m, 400_000).iter().map(|s| s.rate).collect();
    let expected = arw * arw * 100.0 * (1.0 - a) / (1.0 + a);
    assert!(
        (variance(&x) / expected - 1.0).abs() < 0.02,
        "{}",
        variance(&x) / expected
    );
    let m0 = mean(&x);
    let lag1 = x.windows(2).map(|w| (w[0] - m0) * (w[1] - m0)).sum::<f64>() / (x.len() - 1) as f64;
    assert!((lag1 / variance(&x) - a).abs() < 0.01);
    let means: Vec<f64> = x.chunks(100).map(mean).collect();
    // 4000 means: the variance estimate's relative standard error is 2.2 %.
    assert!(
        (variance(&means) / (arw * arw) - 1.0).abs() < 0.1,
        "{}",
        variance(&means) / (arw * arw)
    );
}

#[test]
fn one_gauss_markov_term_has_its_closed_form_variance_and_correlation() {
    // A single term: stationary variance q^2 and autocorrelation exp(-lag / T).
    let config = GyroModelConfig {
        bias_instability: deg(18.0) / 3600.0,
        flicker_min: 10.0,
        flicker_max: 10.0,
        drift_step: 1.0,
        ..GyroModelConfig::ideal(1.0)
    };
    assert_eq!(config.flicker_terms(), 1);
    let (correlation, q) = config.flicker_term(0);
    assert_eq!(correlation, 10.0);
    let mut m = GyroModel::new(config, 5).unwrap();
    let d: Vec<f64> = at_rest(&mut m, 400_000).iter().map(|s| s.bias).collect();
    // 400 000 s hold 40 000 correlation times: the variance estimate's relative standard error
    // is about sqrt(2 T / L) = 2.2 %.
    assert!(
        (variance(&d) / (q * q) - 1.0).abs() < 0.08,
        "{}",
        variance(&d) / (q * q)
    );
    let m0 = mean(&d);
    let lag = 10;
    let cov = d
        .windows(lag + 1)
        .map(|w| (w[0] - m0) * (w[lag] - m0))
        .sum::<f64>()
        / (d.len() - lag) as f64;
    let rho = cov / variance(&d);
    assert!((rho - (-1.0f64).exp()).abs() < 0.03, "rho {rho}");
}

#[test]
fn the_flicker_sum_starts_stationary() {
    // Across seeds, the slow bias at the first sample has the variance of the sum of the terms.
    let config = GyroModelConfig {
        bias_instability: deg(66.0) / 3600.0,
        ..GyroModelConfig::ideal(10.0)
    };
    let expected: f64 = (0..config.flicker_terms())
        .map(|k| config.flicker_term(k).1.powi(2))
        .sum();
    let first: Vec<f64> = (0..4000)
        .map(|seed| GyroModel::new(config, seed).unwrap().measure(0.0, 0.0).bias)
        .collect();
    assert!((mean(&first).abs()) < 5.0 * (expected / 4000.0).sqrt());
    assert!((variance(&first) / expected - 1.0).abs() < 5.0 * (2.0 / 4000f64).sqrt());
}

#[test]
fn rate_random_walk_increments_have_variance_k2_lag() {
    // Hong eq 11: d' = n. Over a lag L the increment's variance is K^2 L.
    let k = deg(3.0) / 3600.0 / 60.0;
    let config = GyroModelConfig {
        rrw: k,
        drift_step: 1.0,
        ..GyroModelConfig::ideal(1.0)
    };
    let mut m = GyroModel::new(config, 9).unwrap();
    let d: Vec<f64> = at_rest(&mut m, 200_001).iter().map(|s| s.bias).collect();
    assert_eq!(d[0], 0.0, "the random walk starts at the bias");
    let lag = 100;
    let inc: Vec<f64> = d
        .chunks(lag)
        .filter(|c| c.len() == lag)
        .map(|c| c[lag - 1] - c[0])
        .collect();
    // Increments over lag - 1 grid steps, 2000 of them: relative standard error 3 %.
    let expected = k * k * (lag - 1) as f64;
    let got = inc.iter().map(|x| x * x).sum::<f64>() / inc.len() as f64;
    assert!((got / expected - 1.0).abs() < 0.15, "{}", got / expected);
}

#[test]
fn flicker_allan_deviation_is_flat_at_0664_b_inside_the_band() {
    // IEEE Std 952: flicker rate noise of coefficient B has Allan deviation sqrt(2 ln 2 / pi) B.
    let b = deg(18.0) / 3600.0;
    let config = GyroModelConfig {
        bias_instability: b,
        flicker_min: 1.0,
        flicker_max: 1.0e5,
        ..GyroModelConfig::ideal(10.0)
    };
    let floor = (2.0 * std::f64::consts::LN_2 / std::f64::consts::PI).sqrt() * b;
    for tau in [30.0, 100.0, 300.0, 1000.0, 3000.0, 1.0e4] {
        let ratio = config.allan_variance(tau).sqrt() / floor;
        assert!((0.96..=1.01).contains(&ratio), "tau {tau}: {ratio}");
    }
    // Outside the band the sum rolls off: below the shortest and above the longest time.
    assert!(config.allan_variance(0.1).sqrt() / floor < 0.6);
    assert!(config.allan_variance(1.0e7).sqrt() / floor < 0.3);
}

#[test]
fn closed_form_allan_variance_has_the_ieee_slopes() {
    let config = GyroModelConfig {
        arw: 1e-3,
        rrw: 1e-6,
        ..GyroModelConfig::ideal(10.0)
    };
    // N^2 / tau + K^2 tau / 3 at tau = 1 s and 3e6 s.
    let close = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-12;
    assert!(close(config.allan_variance(1.0), 1e-6 + 1e-12 / 3.0));
    assert!(close(config.allan_variance(3.0e6), 1e-6 / 3.0e6 + 1e-6));
    // A Gauss-Markov term tends to 2 q^2 T / tau (white) far above its correlation time.
    let gm = GyroModelConfig {
        bias_instability: 1e-3,
        flicker_min: 5.0,
        flicker_max: 5.0,
        drift_step: 1.0,
        ..GyroModelConfig::ideal(1.0)
    };
    let (t, q) = gm.flicker_term(0);
    let tau = 1.0e6;
    assert!((gm.allan_variance(tau) / (2.0 * q * q * t / tau) - 1.0).abs() < 1e-4);
    // ...and to 2 q^2 tau / (3 T) (a random walk) far below it, by the series branch.
    let tau = 1.0e-5;
    assert!((gm.allan_variance(tau) / (2.0 * q * q * tau / (3.0 * t)) - 1.0).abs() < 1e-4);
}

#[test]
fn same_seed_same_readings_other_seed_other_readings() {
    let config = GyroModelConfig {
        arw: 1e-3,
        bias_instability: 1e-4,
        rrw: 1e-6,
        ..GyroModelConfig::ideal(50.0)
    };
    let run = |seed| {
        let mut m = GyroModel::new(config, seed).unwrap();
        at_rest(&mut m, 5000)
            .iter()
            .map(|s| s.rate)
            .collect::<Vec<f64>>()
    };
    assert_eq!(run(42), run(42));
    assert_ne!(run(42), run(43));
}

#[test]
fn the_slow_bias_is_a_function_of_time_not_of_the_sample_rate() {
    // The same seed sampled at 10 Hz and 100 Hz sees the same drift at the shared instants.
    let config = |rate_hz| GyroModelConfig {
        arw: 1e-3,
        bias_instability: deg(66.0) / 3600.0,
        rrw: 1e-5,
        ..GyroModelConfig::ideal(rate_hz)
    };
    let mut slow = GyroModel::new(config(10.0), 4).unwrap();
    let mut fast = GyroModel::new(config(100.0), 4).unwrap();
    let coarse: Vec<f64> = (0..6000)
        .map(|i| slow.measure(i as f64 * 0.1, 0.0).bias)
        .collect();
    let fine: Vec<f64> = (0..60000)
        .map(|i| fast.measure(i as f64 * 0.01, 0.0).bias)
        .collect();
    for (i, c) in coarse.iter().enumerate() {
        assert!((c - fine[10 * i]).abs() < 1e-15, "sample {i}");
    }
    // ...while the white noise differs with the sampling, as a real gyro's does.
    assert!(coarse.iter().any(|&c| c != 0.0));
}

#[test]
fn readings_are_clipped_to_the_range_and_rounded_to_the_resolution() {
    let lsb = deg(0.01);
    let config = GyroModelConfig {
        arw: 1e-3,
        resolution: lsb,
        range: deg(100.0),
        ..GyroModelConfig::ideal(100.0)
    };
    let mut m = GyroModel::new(config, 1).unwrap();
    for i in 0..2000 {
        let r = deg(150.0) * ((i as f64) * 0.003).sin();
        let s = m.measure(i as f64 * 0.01, r);
        let steps = s.rate / lsb;
        assert!(
            (steps - steps.round()).abs() < 1e-9,
            "not a multiple of the LSB: {}",
            s.rate
        );
        assert!(s.rate.abs() <= deg(100.0) + lsb / 2.0);
    }
    let mut m = GyroModel::new(config, 1).unwrap();
    assert!((m.measure(0.0, deg(500.0)).rate - deg(100.0)).abs() <= lsb / 2.0);
}

#[test]
fn sampler_drops_the_requested_fraction_and_jitters_the_instants() {
    let config = GyroModelConfig {
        jitter: 1e-3,
        drop_probability: 0.1,
        ..GyroModelConfig::ideal(100.0)
    };
    let m = GyroModel::new(config, 8).unwrap();
    let t: Vec<f64> = m.sampler(5.0).take_while(|&t| t < 1005.0).collect();
    assert_eq!(t[0], 5.0);
    assert!(t.windows(2).all(|w| w[1] > w[0]), "instants must increase");
    let kept = t.len() as f64 / 100_000.0;
    assert!(
        (kept - 0.9).abs() < 5.0 * (0.09f64 / 100_000.0).sqrt(),
        "kept {kept}"
    );
    // Offsets from the nominal grid: the jitter's standard deviation.
    let offsets: Vec<f64> = t[1..]
        .iter()
        .map(|&x| {
            let k = ((x - 5.0) * 100.0).round();
            x - 5.0 - k / 100.0
        })
        .collect();
    let sd = (offsets.iter().map(|o| o * o).sum::<f64>() / offsets.len() as f64).sqrt();
    assert!((sd / 1e-3 - 1.0).abs() < 0.03, "jitter sd {sd}");
    // Without jitter and drops: the nominal grid.
    let m = GyroModel::new(GyroModelConfig::ideal(8.0), 8).unwrap();
    let grid: Vec<f64> = m.sampler(1.0).take(5).collect();
    assert_eq!(grid, vec![1.0, 1.125, 1.25, 1.375, 1.5]);
}

#[test]
fn samplers_of_one_seed_agree_and_do_not_touch_the_readings() {
    let config = GyroModelConfig {
        jitter: 1e-3,
        drop_probability: 0.2,
        arw: 1e-3,
        ..GyroModelConfig::ideal(100.0)
    };
    let m = GyroModel::new(config, 3).unwrap();
    let a: Vec<f64> = m.sampler(0.0).take(100).collect();
    let b: Vec<f64> = Sampler::clone(&m.sampler(0.0)).take(100).collect();
    assert_eq!(a, b);
}

#[test]
fn stage_invariants_reset_block_and_clone() {
    let config = GyroModelConfig {
        arw: 1e-3,
        bias_instability: 1e-4,
        rrw: 1e-6,
        scale_error: 0.02,
        ..GyroModelConfig::ideal(20.0)
    };
    let t: Vec<f64> = (0..3000).map(|i| i as f64 * 0.05).collect();
    let r: Vec<f64> = t.iter().map(|x| (x * 0.3).sin()).collect();
    let mut a = GyroModel::new(config, 12).unwrap();
    let mut block = vec![gyrocore::GyroSample::default(); t.len()];
    a.process_block(&t, &r, &mut block).unwrap();
    a.reset();
    let again: Vec<_> = t
        .iter()
        .zip(&r)
        .map(|(&ti, &ri)| a.update(ti, ri))
        .collect();
    assert_eq!(block, again, "reset equals fresh, block equals update");
    let mut b = GyroModel::new(config, 12).unwrap();
    for i in 0..1000 {
        b.update(t[i], r[i]);
    }
    let mut c = b.clone();
    let rest_b: Vec<_> = (1000..3000).map(|i| b.update(t[i], r[i])).collect();
    let rest_c: Vec<_> = (1000..3000).map(|i| c.update(t[i], r[i])).collect();
    assert_eq!(rest_b, rest_c);
    assert_eq!(rest_b, block[1000..]);
}

#[test]
fn invalid_configuration_names_the_field() {
    let bad = |c: GyroModelConfig| match GyroModel::new(c, 0) {
        Err(Error::InvalidParameter { name, .. }) => name,
        other => panic!("expected an error, got {other:?}"),
    };
    let ok = GyroModelConfig::ideal(100.0);
    assert_eq!(bad(GyroModelConfig { rate_hz: 0.0, ..ok }), "rate_hz");
    assert_eq!(bad(GyroModelConfig { jitter: 0.01, ..ok }), "jitter");
    assert_eq!(
        bad(GyroModelConfig {
            drop_probability: 1.0,
            ..ok
        }),
        "drop_probability"
    );
    assert_eq!(
        bad(GyroModelConfig {
            scale_error: -1.0,
            ..ok
        }),
        "scale_error"
    );
    assert_eq!(bad(GyroModelConfig { arw: -1.0, ..ok }), "arw");
    assert_eq!(
        bad(GyroModelConfig {
            bias: f64::NAN,
            ..ok
        }),
        "bias"
    );
    assert_eq!(
        bad(GyroModelConfig {
            flicker_max: 1e9,
            ..ok
        }),
        "flicker_max"
    );
    let coarse = GyroModelConfig {
        bias_instability: 1e-4,
        drift_step: 2.0,
        ..ok
    };
    assert_eq!(bad(coarse), "drift_step");
    assert_eq!(bad(GyroModelConfig { range: 0.0, ..ok }), "range");
    assert_eq!(
        bad(GyroModelConfig {
            bandwidth: 0.0,
            ..ok
        }),
        "bandwidth"
    );
    let cold = GyroModelConfig {
        temperature: TemperatureProfile {
            time_constant: 0.0,
            ..TemperatureProfile::constant(20.0)
        },
        ..ok
    };
    assert_eq!(bad(cold), "temperature.time_constant");
}

#[test]
fn non_finite_input_gives_a_reading_and_no_panic() {
    let config = GyroModelConfig {
        bias_instability: 1e-4,
        arw: 1e-3,
        ..GyroModelConfig::ideal(10.0)
    };
    let mut m = GyroModel::new(config, 0).unwrap();
    m.measure(0.0, 0.0);
    let _ = m.measure(f64::NAN, f64::NAN);
    let _ = m.measure(-5.0, 1.0);
    assert!(m.measure(1.0, 0.0).rate.is_finite());
    // A timestamp years ahead jumps the slow bias there instead of stepping through every grid point.
    assert!(m.measure(1.0e9, 0.0).rate.is_finite());
    let _ = m.measure(f64::INFINITY, 0.0);
}
