//! Each stage against values worked out by hand from the papers' equations.

mod common;
use common::run;
use gyrocore::*;

const EPS: f64 = 1e-12;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= EPS * (1.0 + b.abs())
}

#[test]
fn correction_applies_bias_then_calibration_then_direction_factors() {
    // r = (s_bar (r_m - eps0) + b_bar) * C_dir: HDR eq 2, Hong eq 3, FOG eq 3.
    let config = CorrectionConfig {
        bias: StaticBias::Fixed(0.1),
        scale: 1.1,
        offset: -0.05,
        c_cw: 1.02,
        c_ccw: 0.98,
        temperature: None,
    };
    let mut c = Correction::new(config).unwrap();
    assert!(close(c.update(0.0, 0.6), (1.1 * 0.5 - 0.05) * 0.98));
    assert!(close(c.update(1.0, -0.4), (1.1 * -0.5 - 0.05) * 1.02));
}

#[test]
fn hong_calibration_recovers_the_true_rate_of_section_3_1() {
    // s = -10 %, b = 0.1 rad/s: r_m = 0.9 r + 0.1, s_bar = 1/0.9, b_bar = -0.1/0.9 (Hong eq 2-3).
    let (s, b) = (-0.1, 0.1);
    let config = CorrectionConfig {
        scale: 1.0 / (1.0 + s),
        offset: -b / (1.0 + s),
        ..Default::default()
    };
    let mut c = Correction::new(config).unwrap();
    for (i, r) in [-1.0, -0.2, 0.0, 0.35, 2.0].into_iter().enumerate() {
        assert!(close(c.update(i as f64, (1.0 + s) * r + b), r));
    }
}

#[test]
fn temperature_factor_is_fog_eq_6() {
    // FOG eq 5-6: E_T = -0.52 T + 19.23 deg, C_T = 360 / (379.23 - 0.52 T).
    let model = TemperatureScale {
        slope: -0.52 / 360.0,
        offset: 19.23 / 360.0,
    };
    for temp in [0.0, 25.0, 40.0] {
        assert!(close(model.factor(temp), 360.0 / (379.23 - 0.52 * temp)));
    }
    let config = CorrectionConfig {
        temperature: Some(model),
        ..Default::default()
    };
    let mut c = Correction::new(config).unwrap();
    assert!(close(
        c.apply(0.0, 0.5, Some(25.0)),
        0.5 * 360.0 / (379.23 - 13.0)
    ));
}

#[test]
fn static_bias_window_is_the_time_weighted_mean_at_rest_and_then_frozen() {
    let config = CorrectionConfig {
        bias: StaticBias::Window {
            start: 0.0,
            end: 2.0,
        },
        ..Default::default()
    };
    let mut c = Correction::new(config).unwrap();
    let out = run(
        &mut c,
        &[0.0, 0.5, 2.0, 3.0, 4.0],
        &[0.1, 0.3, 0.2, 1.0, 0.2],
    );
    // Estimate: 0.1 (first reading), then 0.3 (0.5 s), then (0.3*0.5 + 0.2*1.5)/2 = 0.225; frozen.
    let expected = [0.0, 0.0, 0.2 - 0.225, 1.0 - 0.225, 0.2 - 0.225];
    for (o, e) in out.iter().zip(expected) {
        assert!(close(*o, e), "{out:?}");
    }
    assert!(close(c.bias(), 0.225));
    assert_eq!(c.bias_sample_count(), 3);
    assert!(!c.bias_learning());
}

#[test]
fn leading_bias_window_starts_at_the_first_sample() {
    let config = CorrectionConfig {
        bias: StaticBias::Leading { duration: 2.5 },
        ..Default::default()
    };
    let mut c = Correction::new(config).unwrap();
    run(&mut c, &[100.0, 101.0, 102.0, 103.0], &[0.2, 0.4, 0.6, 9.0]);
    assert!(close(c.bias(), 0.5));
    assert_eq!(c.bias_sample_count(), 3);
    // A time the clock refuses, or a NaN or out-of-range reading, is corrected but teaches the
    // bias nothing: the window starts at the first usable sample, and the bias stays finite (a
    // NaN first time left it unlearned forever, a NaN reading made every output NaN).
    c.reset();
    let t = [f64::NAN, 100.0, 101.0, 101.5, 102.0, 103.0];
    let rate = [7.0, 0.2, 0.4, f64::NAN, 0.6, 9.0];
    let out = run(&mut c, &t, &rate);
    assert!(close(c.bias(), 0.5), "bias {}", c.bias());
    assert_eq!(c.bias_sample_count(), 3);
    assert!(!c.bias_learning());
    assert!(out[3].is_nan() && close(out[5], 8.5), "{out:?}");
}

#[test]
fn threshold_is_hong_eq_12() {
    let mut th = Threshold::new(ThresholdConfig { threshold: 0.1 }).unwrap();
    let out = run(
        &mut th,
        &[0.0, 1.0, 2.0, 3.0, 4.0],
        &[0.05, -0.05, 0.1, -0.2, 0.0999],
    );
    assert_eq!(out, vec![0.0, 0.0, 0.1, -0.2, 0.0]);
}

#[test]
fn lowpass_is_hdr_eq_7_with_the_actual_interval() {
    let mut lp = LowPass::new(LowPassConfig { tau: 1.0 }).unwrap();
    let out = run(&mut lp, &[0.0, 1.0, 2.0, 2.5], &[1.0, 0.0, 0.0, 3.0]);
    // y0 = x0; y1 = (0*1 + 1*1)/2; y2 = (0 + 0.5)/2; y3 = (3*0.5 + 1*0.25)/1.5.
    let expected = [1.0, 0.5, 0.25, (1.5 + 0.25) / 1.5];
    for (o, e) in out.iter().zip(expected) {
        assert!(close(*o, e), "{out:?}");
    }
}

#[test]
fn delag_is_hdr_eq_13_and_inverts_the_lowpass() {
    let mut d = DeLag::new(LowPassConfig { tau: 0.75 }).unwrap();
    let out = run(&mut d, &[0.0, 0.5, 1.5], &[1.0, 2.0, 1.0]);
    // w_d = w + tau/T (w_i - w_{i-1}): (2 - 1) over 0.5 s, then (1 - 2) over 1 s.
    let expected = [
        1.0,
        2.0 + 0.75 / 0.5 * (2.0 - 1.0),
        1.0 + 0.75 / 1.0 * (1.0 - 2.0),
    ];
    for (o, e) in out.iter().zip(expected) {
        assert!(close(*o, e), "{out:?}");
    }
    // Irregular timestamps: de-lag(low-pass(x)) == x.
    let t: Vec<f64> = (0..200)
        .map(|i| i as f64 * 0.01 + 0.003 * ((i * 7 % 5) as f64))
        .collect();
    let x: Vec<f64> = (0..200).map(|i| (i as f64 * 0.37).sin()).collect();
    let mut lp = LowPass::new(LowPassConfig { tau: 0.75 }).unwrap();
    let mut dl = DeLag::new(LowPassConfig { tau: 0.75 }).unwrap();
    for ((&ti, &xi), i) in t.iter().zip(&x).zip(0..) {
        let y = dl.update(ti, lp.update(ti, xi));
        assert!((y - xi).abs() < 1e-9, "sample {i}: {y} vs {xi}");
    }
}

fn hand_hdr() -> HdrConfig {
    // R(r) = 1.5 / (1 + 0.5 r): R(1) = 1, R(2) = 0.75, R(3) = 0.6.
    HdrConfig {
        increment: 0.1,
        turn_threshold: 1.0,
        c1: 0.5,
        c2: 1.0,
        interval: 1.0,
        tau: 0.0,
        max_correction: f64::INFINITY,
    }
}

#[test]
fn hdr_follows_eq_9_to_12_step_by_step() {
    let mut h = Hdr::new(hand_hdr()).unwrap();
    let t: Vec<f64> = (0..6).map(f64::from).collect();
    let out = run(&mut h, &t, &[0.2; 6]);
    // I: 0 -> -0.1 (r=1) -> -0.175 (r=2) -> -0.235 (r=3) -> -0.135 (sign flips, r=1) -> ...
    let expected = [0.2, 0.2, 0.1, 0.025, -0.035, 0.065];
    for (o, e) in out.iter().zip(expected) {
        assert!(close(*o, e), "{out:?}");
    }
    assert_eq!(h.repetitions(), 1);
    // After t = 5 (w = 0.065 > 0 follows w = -0.035 < 0): r = 1, I = -0.135 - 0.1.
    assert!(close(h.drift(), 0.235));
}

#[test]
fn hdr_turn_switch_uses_the_absolute_rate_and_disables_above_the_threshold() {
    // The text of section 4.2.2 (eq 8 as printed has the cases swapped and no absolute value).
    for rate in [2.0, -2.0] {
        let mut h = Hdr::new(hand_hdr()).unwrap();
        run(&mut h, &[0.0, 1.0, 2.0, 3.0], &[rate; 4]);
        assert_eq!(h.drift(), 0.0, "turning at {rate} rad/s must not move I");
    }
    for rate in [0.5, -0.5] {
        let mut h = Hdr::new(hand_hdr()).unwrap();
        run(&mut h, &[0.0, 1.0], &[rate; 2]);
        assert!(
            close(h.drift(), 0.1 * rate.signum()),
            "below the threshold HDR must act"
        );
    }
}

#[test]
fn hdr_decides_once_per_interval_at_any_rate() {
    // 10 Hz: the integrator changes only at whole seconds, by the same steps as at 1 Hz.
    let mut h = Hdr::new(hand_hdr()).unwrap();
    let t: Vec<f64> = (0..=40).map(|i| i as f64 * 0.1).collect();
    let out = run(&mut h, &t, &vec![0.2; t.len()]);
    let per_second = [0.2, 0.1, 0.025, -0.035];
    for (i, o) in out.iter().enumerate().skip(1) {
        let second = (i - 1) / 10;
        assert!(close(*o, per_second[second]), "sample {i}: {o}");
    }
}

#[test]
fn attenuator_table_matches_eq_10_beyond_its_end() {
    let c = HdrConfig::table_iii();
    assert!(close(c.attenuation(1), 1.0));
    assert!(close(
        c.attenuation(40),
        1.16 / (1.0 + 0.16 * 40f64.powf(1.8))
    ));
    // A constant rate below the turn threshold keeps its sign for 60 steps: r passes the table.
    let mut h = Hdr::new(c).unwrap();
    let mut expected_i = 0.0;
    for k in 0..=60 {
        h.update(k as f64, 0.004);
        if k >= 1 {
            expected_i -= c.attenuation(k) * c.increment;
        }
    }
    assert_eq!(h.repetitions(), 60);
    assert!((h.drift() + expected_i).abs() < 1e-15);
}

#[test]
fn integration_rectangle_is_hdr_eq_3_and_trapezoid_averages_neighbours() {
    let t = [0.0, 1.0, 3.0];
    let r = [1.0, 2.0, 3.0];
    let mut rect = Integrator::new(IntegratorConfig {
        method: Method::Rectangle,
        initial_heading: 0.5,
    })
    .unwrap();
    assert_eq!(run(&mut rect, &t, &r), vec![0.5, 2.5, 8.5]);
    let mut trap = Integrator::new(IntegratorConfig {
        method: Method::Trapezoid,
        initial_heading: 0.0,
    })
    .unwrap();
    assert_eq!(run(&mut trap, &t, &r), vec![0.0, 1.5, 6.5]);
}

#[test]
fn heading_is_continuous_past_pi() {
    let mut trap = Integrator::new(IntegratorConfig::default()).unwrap();
    let t: Vec<f64> = (0..=100).map(|i| i as f64 * 0.1).collect();
    let out = run(&mut trap, &t, &vec![1.0; t.len()]);
    assert!(close(out[100], 10.0));
}

#[test]
fn downsample_averages_blocks_like_the_second_eq_14() {
    let mut d = Downsample::new(DownsampleConfig { interval: 1.0 }).unwrap();
    let t: Vec<f64> = (0..=30).map(|i| i as f64 * 0.1).collect();
    let rate: Vec<f64> = (0..=30).map(f64::from).collect();
    let (mut ot, mut or) = (vec![0.0; t.len()], vec![0.0; t.len()]);
    let n = d.process_block(&t, &rate, &mut ot, &mut or).unwrap();
    assert_eq!(n, 3);
    // Block k holds samples 10k+1 ..= 10k+10: the mean of those indices.
    for k in 0..3 {
        assert!(close(or[k], 10.0 * k as f64 + 5.5));
        assert!(close(ot[k], (k + 1) as f64));
    }
}

#[test]
fn invalid_parameters_name_the_parameter() {
    let cases: Vec<(Error, &str)> = vec![
        (
            LowPass::new(LowPassConfig { tau: -1.0 }).unwrap_err(),
            "lowpass_tau",
        ),
        (
            Threshold::new(ThresholdConfig { threshold: -0.1 }).unwrap_err(),
            "threshold",
        ),
        (
            Hdr::new(HdrConfig {
                c2: 0.0,
                ..HdrConfig::table_iii()
            })
            .unwrap_err(),
            "hdr_c2",
        ),
        (
            Hdr::new(HdrConfig {
                increment: f64::NAN,
                ..HdrConfig::table_iii()
            })
            .unwrap_err(),
            "hdr_increment",
        ),
        (
            Hdr::new(HdrConfig {
                interval: 0.0,
                ..HdrConfig::table_iii()
            })
            .unwrap_err(),
            "hdr_interval",
        ),
        (
            Correction::new(CorrectionConfig {
                scale: 0.0,
                ..Default::default()
            })
            .unwrap_err(),
            "scale",
        ),
        (
            Correction::new(CorrectionConfig {
                bias: StaticBias::Window {
                    start: 2.0,
                    end: 1.0,
                },
                ..Default::default()
            })
            .unwrap_err(),
            "bias_window.end",
        ),
    ];
    for (err, name) in cases {
        match err {
            Error::InvalidParameter { name: n, .. } => assert_eq!(n, name),
            other => panic!("expected InvalidParameter for {name}, got {other:?}"),
        }
        assert!(err.to_string().contains(name));
    }
}

/// `Hdr::bound_correction` of NaN keeps the bound in force (NaN lifted every bound: `I` ran to
/// 0.235 past a bound of 0.05); a negative bound is its magnitude, 0 turns HDR off.
#[test]
fn hdr_bound_of_nan_keeps_the_bound_in_force() {
    let t: Vec<f64> = (0..6).map(f64::from).collect();
    for (bound, drift) in [(f64::NAN, 0.05), (-0.05, 0.05), (0.0, 0.0)] {
        let mut h = Hdr::new(hand_hdr()).unwrap();
        h.bound_correction(0.05);
        h.bound_correction(bound);
        run(&mut h, &t, &[0.2; 6]);
        assert!(close(h.drift(), drift), "{bound}: {}", h.drift());
    }
}

#[test]
fn hdr_with_a_bound_of_0_corrects_nothing() {
    // What a rest of exactly constant readings measures: a bias known without error, so HDR has
    // nothing to remove (the config refused 0, and whole mode stopped on such a log).
    let mut h = Hdr::new(HdrConfig {
        max_correction: 0.0,
        ..hand_hdr()
    })
    .unwrap();
    let t: Vec<f64> = (0..6).map(f64::from).collect();
    assert_eq!(run(&mut h, &t, &[0.2; 6]), vec![0.2; 6]);
}
