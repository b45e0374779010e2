//! The simulated gyro's randomness (Hong eq 10-11): reference vectors of the random generators,
//! and the noise statistics against their closed forms.

mod common;

use common::{at_rest, deg};
use gyrocore::sim::{Gaussian, SplitMix64, Xoshiro256PlusPlus};
use gyrocore::{GyroModel, GyroModelConfig};

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
    let draw = |seed, stream| -> Vec<f64> {
        let mut g = Gaussian::new(seed, stream);
        (0..1000).map(|_| g.sample()).collect()
    };
    let (a, b, c) = (draw(1, 1), draw(1, 2), draw(2, 1));
    let corr = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>() / 1000.0;
    assert!(corr(&a, &b).abs() < 0.15 && corr(&a, &c).abs() < 0.15);
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

/// Non-overlapping Allan variance of `x` over `m` samples: half the mean square of the
/// differences of consecutive `m`-sample means.
fn allan_variance_of(x: &[f64], m: usize) -> f64 {
    let means: Vec<f64> = x.chunks_exact(m).map(mean).collect();
    let d: Vec<f64> = means.windows(2).map(|w| w[1] - w[0]).collect();
    d.iter().map(|v| v * v).sum::<f64>() / (2.0 * d.len() as f64)
}

#[test]
fn closed_form_allan_variance_holds_below_the_noise_bandwidth() {
    // The XV3500's 20 Hz noise bandwidth at 100 Hz: the closed form said N^2 / tau at every tau,
    // which the samples' Allan deviation is 0.63 of at tau = 0.01 s (0.77 at 0.02 s, 0.88 at 0.04 s).
    let arw = deg(2.5) / 60.0;
    let config = GyroModelConfig {
        arw,
        bandwidth: 20.0,
        ..GyroModelConfig::ideal(100.0)
    };
    let a = (-std::f64::consts::TAU * 20.0 / 100.0f64).exp();
    // one sample: the variance of the difference of two, N^2 f (1 - a)^2 / (1 + a)
    let one = arw * arw * 100.0 * (1.0 - a) * (1.0 - a) / (1.0 + a);
    assert!((config.allan_variance(0.01) / one - 1.0).abs() < 1e-12);
    let mut m = GyroModel::new(config, 23).unwrap();
    let x: Vec<f64> = at_rest(&mut m, 400_000).iter().map(|s| s.rate).collect();
    for samples in [1, 2, 4, 8, 32] {
        let tau = samples as f64 / 100.0;
        let ratio = allan_variance_of(&x, samples) / config.allan_variance(tau);
        // at least 12,500 differences: the estimate's relative standard error is at most 1.3 %
        assert!((ratio - 1.0).abs() < 0.05, "tau {tau}: {ratio}");
    }
    // far above 1 / bandwidth the density is kept: N^2 / tau
    assert!((config.allan_variance(100.0) / (arw * arw / 100.0) - 1.0).abs() < 1e-3);
}
