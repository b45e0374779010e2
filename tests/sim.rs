//! The simulated gyro (Hong eq 1): its readings, reproducibility, continuous-time drift,
//! sampling, and the stage invariants (the noise statistics: `sim_noise.rs`).

mod common;

use common::{at_rest, deg};
use gyrocore::sim::Sampler;
use gyrocore::{Error, GyroModel, GyroModelConfig, Stage, TemperatureProfile};

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
    // Above 0.99, each sample loops through ever more dropped draws (1 - 1e-16: never returns).
    assert_eq!(
        bad(GyroModelConfig {
            drop_probability: 0.995,
            ..ok
        }),
        "drop_probability"
    );
    assert_eq!(
        bad(GyroModelConfig {
            rate_hz: 1e-310,
            ..ok
        }),
        "rate_hz"
    );
    // Values whose readings would overflow to infinity.
    assert_eq!(
        bad(GyroModelConfig {
            arw: f64::MAX,
            ..ok
        }),
        "arw"
    );
    assert_eq!(bad(GyroModelConfig { bias: 1e300, ..ok }), "bias");
    assert_eq!(
        bad(GyroModelConfig {
            drift_step: f64::MAX,
            ..ok
        }),
        "drift_step"
    );
    assert_eq!(
        bad(GyroModelConfig {
            scale_error: -1.0,
            ..ok
        }),
        "scale_error"
    );
    // Each term within its range, the gain they make together not: a reading of the wrong sign.
    // A scale error of -0.5 at 25 degC, 0.01 per degree, warming from `start` to 25 degC.
    let warming_from = |start: f64| GyroModelConfig {
        scale_error: -0.5,
        scale_temperature: 0.01,
        temperature: TemperatureProfile {
            start,
            end: 25.0,
            time_constant: 600.0,
        },
        reference_temperature: 25.0,
        ..ok
    };
    for flipped in [
        GyroModelConfig {
            scale_error: -0.9,
            scale_asymmetry: 0.3,
            ..ok
        },
        warming_from(-40.0),
        GyroModelConfig {
            scale_error: -0.5,
            scale_temperature: -0.01,
            temperature: TemperatureProfile::constant(80.0),
            ..ok
        },
    ] {
        assert_eq!(bad(flipped), "gain");
    }
    // The same terms where the gain stays above 0 are a model.
    for kept in [
        GyroModelConfig {
            scale_error: -0.8,
            scale_asymmetry: 0.3,
            ..ok
        },
        warming_from(0.0),
    ] {
        assert!(kept.validate().is_ok());
    }
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
    // Long before the first sample the temperature is the profile's start (its exponential
    // overflowed: 0 * inf = NaN even at a constant temperature).
    let mut m = GyroModel::new(GyroModelConfig::ideal(10.0), 0).unwrap();
    m.measure(0.0, 0.0);
    let early = m.measure(-1e4, 0.5);
    assert_eq!((early.rate, early.temperature), (0.5, 25.0));
}

/// Its own defaults (no filter, no range: infinities) read back from JSON; a model read back
/// with a negative range is refused as `new` refuses it, and a sampler read back with a negative
/// period (which is not checked) gives instants, not a panic.
#[cfg(feature = "serde")]
#[test]
fn a_model_round_trips_through_json_and_an_unchecked_one_does_not_panic() {
    let config = GyroModelConfig {
        jitter: 1e-3,
        ..GyroModelConfig::ideal(100.0)
    };
    let json = serde_json::to_string(&config).unwrap();
    assert_eq!(
        serde_json::from_str::<GyroModelConfig>(&json).unwrap(),
        config
    );
    let model = GyroModel::new(config, 3).unwrap();
    let json = serde_json::to_string(&model).unwrap();
    let mut back: GyroModel = serde_json::from_str(&json).unwrap();
    assert_eq!(back, model);
    let broken =
        serde_json::from_str::<GyroModel>(&json.replace("\"range\":\"inf\"", "\"range\":-1.0"));
    let e = broken.unwrap_err().to_string();
    assert!(e.contains("invalid parameter range = -1"), "{e}");
    back.measure(0.0, 0.1);
    let sampler = model.sampler(0.0);
    let json = serde_json::to_string(&sampler)
        .unwrap()
        .replace("\"period\":0.01", "\"period\":-0.01");
    let mut broken: Sampler = serde_json::from_str(&json).unwrap();
    assert!(broken.nth(3).is_some());
}

/// The flicker term count of a configuration not validated, spanning 1e-300 to 1e308 s (an
/// infinite number of decades), is the most there are (it overflowed: a panic in a debug build).
#[test]
fn flicker_terms_of_an_unchecked_span_saturate() {
    let config = GyroModelConfig {
        bias_instability: 1e-4,
        flicker_min: 1e-300,
        flicker_max: 1e308,
        ..GyroModelConfig::ideal(100.0)
    };
    assert!(config.validate().is_err());
    let most = GyroModelConfig {
        bias_instability: 1e-4,
        flicker_max: 1e7,
        flicker_min: 1.0,
        ..GyroModelConfig::ideal(100.0)
    };
    assert!(config.flicker_terms() >= most.flicker_terms());
}

/// A sampler read back with a drop probability of 1 or more (no validation) still gives
/// instants: it kept nothing after the first, and `next` never returned.
#[cfg(feature = "serde")]
#[test]
fn a_sampler_read_back_losing_every_sample_still_returns() {
    let model = GyroModel::new(GyroModelConfig::ideal(100.0), 1).unwrap();
    let json = serde_json::to_string(&model.sampler(0.0)).unwrap();
    let json = json.replace("\"drop_probability\":0.0", "\"drop_probability\":1.5");
    let mut broken: Sampler = serde_json::from_str(&json).unwrap();
    let (sent, received) = std::sync::mpsc::channel();
    std::thread::spawn(move || sent.send(broken.nth(3)));
    let fourth = received.recv_timeout(std::time::Duration::from_secs(10));
    assert!(fourth.expect("next never returned").is_some());
}
