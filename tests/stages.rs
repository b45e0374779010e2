//! Each stage against values worked out by hand from the papers' equations.

use gyrocore::*;

const EPS: f64 = 1e-12;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= EPS * (1.0 + b.abs())
}

fn run<S: Stage<Output = f64>>(stage: &mut S, t: &[f64], rate: &[f64]) -> Vec<f64> {
    t.iter()
        .zip(rate)
        .map(|(&ti, &ri)| stage.update(ti, ri))
        .collect()
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

/// A stand-alone stage skips a reading it cannot use, as the pipeline's `update` does: a NaN,
/// an infinity or a rate beyond `MAX_READING` taken into the state made every later heading
/// NaN (or, for HDR, its low-passed step mean NaN forever). The run equals one without it.
#[test]
fn a_stage_skips_an_unusable_reading_and_its_block_is_refused_by_index() {
    fn check<S: Stage<Output = f64> + Clone + PartialEq + core::fmt::Debug>(fresh: S) {
        let t: Vec<f64> = (0..40).map(|i| i as f64 * 0.1).collect();
        let rate: Vec<f64> = (0..40).map(|i| 0.01 * (i % 7) as f64).collect();
        let mut stage = fresh.clone();
        let outputs = run(&mut stage, &t[..20], &rate[..20]);
        for bad in [f64::NAN, f64::INFINITY, -MAX_READING, 1e300] {
            let before = stage.clone();
            let last = stage.update(t[20] - 0.05, bad);
            assert_eq!((last.to_bits(), &stage), (outputs[19].to_bits(), &before));
        }
        let clean = run(&mut fresh.clone(), &t, &rate);
        let mut dirty_t = t.clone();
        dirty_t.insert(25, t[24] + 0.05);
        let mut dirty_rate = rate.clone();
        dirty_rate.insert(25, f64::NAN);
        let mut dirty = run(&mut fresh.clone(), &dirty_t, &dirty_rate);
        dirty.remove(25);
        assert_eq!(clean, dirty);
        // a block: refused by the first bad sample's index, nothing processed
        let mut stage = fresh.clone();
        let mut out = vec![0.0; t.len()];
        let e = stage.process_block(&dirty_t[..30], &dirty_rate[..30], &mut out[..30]);
        assert!(
            matches!(
                e,
                Err(Error::NonFinite {
                    what: "rate",
                    index: 25,
                    ..
                })
            ),
            "{e:?}"
        );
        assert_eq!(stage, fresh);
        stage
            .process_block(&t[..10], &rate[..10], &mut out[..10])
            .unwrap();
        let before = stage.clone();
        let e = stage.process_block(&t[5..15], &rate[5..15], &mut out[..10]);
        assert!(
            matches!(e, Err(Error::NotIncreasing { index: 0, .. })),
            "{e:?}"
        );
        assert_eq!(stage, before);
    }
    check(Integrator::new(IntegratorConfig::default()).unwrap());
    check(Threshold::new(ThresholdConfig { threshold: 0.02 }).unwrap());
    check(LowPass::new(LowPassConfig { tau: 0.75 }).unwrap());
    check(DeLag::new(LowPassConfig { tau: 0.75 }).unwrap());
    check(Hdr::new(HdrConfig::table_iii()).unwrap());
}

/// Down-sampling leaves out a reading it cannot use (a NaN made its block's mean NaN), refuses
/// a bad block by index, and an interval beyond 2^40 s or below the smallest normal number.
#[test]
fn downsample_leaves_out_an_unusable_reading_and_refuses_a_bad_block() {
    let config = DownsampleConfig { interval: 1.0 };
    let mut d = Downsample::new(config).unwrap();
    let t = [0.0, 0.5, 0.75, 1.0, 2.0];
    let (mut ot, mut or) = ([0.0; 5], [0.0; 5]);
    let e = d.process_block(&t, &[1.0, f64::NAN, 1.0, 1.0, 1.0], &mut ot, &mut or);
    assert!(matches!(e, Err(Error::NonFinite { index: 1, .. })), "{e:?}");
    assert_eq!(d, Downsample::new(config).unwrap());
    let means = |d: &mut Downsample, t: &[f64], rate: &[f64]| -> Vec<_> {
        t.iter()
            .zip(rate)
            .filter_map(|(&t, &r)| d.update(t, r))
            .collect()
    };
    let rate = [1.0, f64::NAN, 2.0, 3.0, 4.0];
    let clean = means(
        &mut Downsample::new(config).unwrap(),
        &[0.0, 0.75, 1.0, 2.0],
        &[1.0, 2.0, 3.0, 4.0],
    );
    assert_eq!(means(&mut d, &t, &rate), clean);
    let e = d.process_block(&[1.5], &[1.0], &mut ot[..1], &mut or[..1]);
    assert!(
        matches!(e, Err(Error::NotIncreasing { index: 0, .. })),
        "{e:?}"
    );
    for interval in [1e300, 1e-320, f64::NAN] {
        assert!(
            Downsample::new(DownsampleConfig { interval }).is_err(),
            "{interval}"
        );
    }
}

/// `Streaming::step`, for a caller with its own clock, leaves the stage as it was for an
/// interval no two valid timestamps have (NaN, 0, negative, below 1 ps, infinite): a NaN or
/// negative one made the low-pass NaN for good, and a NaN one stopped HDR's steps.
#[test]
fn a_stage_stepped_by_a_bad_interval_stays_as_it_was() {
    fn check<K: kernel::Validated + Copy + PartialEq + core::fmt::Debug>(mut stage: Streaming<K>) {
        let first = stage.step(f64::NAN, 0.5);
        let mut last = stage.step(0.1, 0.25);
        for dt in [
            f64::NAN,
            0.0,
            -0.75,
            -1.0,
            1e-13,
            f64::INFINITY,
            3.0 * MAX_TIME,
        ] {
            let before = stage;
            assert_eq!(stage.step(dt, 2.0).to_bits(), last.to_bits(), "{dt}");
            assert_eq!(stage, before, "{dt}");
        }
        assert!(first.is_finite());
        for _ in 0..40 {
            last = stage.step(0.1, 0.001);
        }
        assert!(last.is_finite());
    }
    check(LowPass::new(LowPassConfig { tau: 0.75 }).unwrap());
    check(DeLag::new(LowPassConfig { tau: 0.75 }).unwrap());
    check(Integrator::new(IntegratorConfig::default()).unwrap());
    check(Hdr::new(HdrConfig::table_iii()).unwrap());
    check(Threshold::new(ThresholdConfig { threshold: 0.01 }).unwrap());
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

/// A correction or down-sampling read back is checked as `new` checks it: a scale of 0 or an
/// interval of -1 edited into a stored state ran (every rate 0; a block closed at every sample).
#[cfg(feature = "serde")]
#[test]
fn a_stage_read_back_is_checked_as_new_checks_it() {
    let mut c = Correction::new(CorrectionConfig::default()).unwrap();
    c.update(0.0, 0.1);
    let json = serde_json::to_string(&c).unwrap();
    assert_eq!(serde_json::from_str::<Correction>(&json).unwrap(), c);
    let e = serde_json::from_str::<Correction>(&json.replace("\"scale\":1.0", "\"scale\":0.0"));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("invalid parameter scale = 0"));
    let d = Downsample::new(DownsampleConfig { interval: 1.0 }).unwrap();
    let json = serde_json::to_string(&d).unwrap();
    assert_eq!(serde_json::from_str::<Downsample>(&json).unwrap(), d);
    let e =
        serde_json::from_str::<Downsample>(&json.replace("\"interval\":1.0", "\"interval\":-1.0"));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("invalid parameter interval = -1"));
}

/// A stand-alone stage read back is checked as `new` checks its settings: a low-pass `tau` of
/// -0.75 edited into a stored state gave NaN from its second sample on, and an HDR bound of -1
/// pinned the correction `I` at -1 rad/s.
#[cfg(feature = "serde")]
#[test]
fn a_streaming_stage_read_back_is_checked() {
    let mut l = LowPass::new(LowPassConfig { tau: 0.75 }).unwrap();
    l.update(0.0, 0.1);
    let json = serde_json::to_string(&l).unwrap();
    assert_eq!(serde_json::from_str::<LowPass>(&json).unwrap(), l);
    let e = serde_json::from_str::<LowPass>(&json.replace("\"tau\":0.75", "\"tau\":-0.75"));
    assert!(e.unwrap_err().to_string().contains("lowpass_tau = -0.75"));
    let h = Hdr::new(HdrConfig::table_iii()).unwrap();
    let json = serde_json::to_string(&h).unwrap();
    assert_eq!(serde_json::from_str::<Hdr>(&json).unwrap(), h);
    let e = serde_json::from_str::<Hdr>(&json.replace("\"bound\":\"inf\"", "\"bound\":-1.0"));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("hdr_max_correction = -1"));
    let e = serde_json::from_str::<Hdr>(&json.replace("\"c2\":1.8", "\"c2\":0.0"));
    assert!(e.unwrap_err().to_string().contains("hdr_c2"));
}

/// A stage's block checks its samples on the way (the pipeline's way) and exactly only where the
/// quick check may have failed: rates of 2 rad/s and more (which its bound takes for suspects)
/// and a first time of 2^40 - 1 s (where the first interval rounds to 0) give what `update`
/// gives, sample for sample, and a NaN in the last sample still refuses the block whole.
#[test]
fn a_stage_block_equals_update_where_its_quick_check_is_unsure() {
    let t: Vec<f64> = (0..50).map(|i| MAX_TIME - 1.0 - 50.0 + i as f64).collect();
    let rate: Vec<f64> = (0..50).map(|i| 3.0 * (i % 5) as f64 - 6.0).collect();
    let fresh = Hdr::new(HdrConfig::table_iii()).unwrap();
    let (mut a, mut b) = (fresh, fresh);
    let updates = run(&mut a, &t, &rate);
    let mut out = vec![0.0; t.len()];
    b.process_block(&t, &rate, &mut out).unwrap();
    assert_eq!((out, b), (updates, a));
    let mut bad = rate.clone();
    bad[49] = f64::NAN;
    let mut c = fresh;
    let e = c.process_block(&t, &bad, &mut vec![0.0; t.len()]);
    assert!(
        matches!(e, Err(Error::NonFinite { index: 49, .. })),
        "{e:?}"
    );
    assert_eq!(c, fresh);
}
