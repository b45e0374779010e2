//! States read back (`serde` feature) by an embedding user: what valid input leaves reads back,
//! and a state no valid input leaves (a covariance that is not one, a heading or a reading beyond
//! what the limits of a sample allow, a clock beyond `MAX_TIME`) is refused naming its field.
#![cfg(feature = "serde")]

use gyrocore::*;
use serde_json::{json, Value};

/// A filter after a few fixes, its covariance correlated.
fn fusion() -> Fusion {
    let t: Vec<f64> = (0..500).map(|i| i as f64 * 0.01).collect();
    let rate = vec![0.2; t.len()];
    let fixes: Vec<Fix> = (0..5)
        .map(|s| Fix {
            t: s as f64 + 0.5,
            heading: 0.2 * (s as f64 + 0.5),
            sigma: 0.05,
        })
        .collect();
    let mut f = Fusion::new(FusionConfig::default()).unwrap();
    let mut h = vec![0.0; t.len()];
    f.process_block(&t, &rate, &fixes, FusionOutputs::heading(&mut h))
        .unwrap();
    f
}

/// The error reading `v` back as a `T`, which must be refused.
fn refused<T: serde::de::DeserializeOwned + core::fmt::Debug>(v: Value) -> String {
    serde_json::from_value::<T>(v).unwrap_err().to_string()
}

/// Reads a state back as one type, its error as text.
type Reader = fn(Value) -> Result<(), String>;

/// Reads `v` back as a `T` ([`Reader`]).
fn read<T: serde::de::DeserializeOwned>(v: Value) -> Result<(), String> {
    serde_json::from_value::<T>(v)
        .map(|_| ())
        .map_err(|e| e.to_string())
}

/// `v` with each `(pointer, value)` of `edits` set: a state edited by hand.
fn edited(v: &Value, edits: &[(&str, f64)]) -> Value {
    let mut e = v.clone();
    for &(at, value) in edits {
        *e.pointer_mut(at).unwrap() = json!(value);
    }
    e
}

/// Reading `v` with `edits` back as a `T` is refused, the error holding `message`.
fn refuses<T: serde::de::DeserializeOwned + core::fmt::Debug>(
    v: &Value,
    edits: &[(&str, f64)],
    message: &str,
) {
    let err = refused::<T>(edited(v, edits));
    assert!(err.contains(message), "{edits:?}: {err}");
}

/// Entry `(i, j)` of a covariance set to a value.
type Edit = (usize, usize, f64);

/// A covariance that is not one, read back: a negative scale or bias variance, a covariance
/// beyond the root of the product of its variances, three that together exceed them, or a scale
/// `s_bar` of 0. Each gave NaN or imaginary sigmas, or a NaN bias; each is refused naming it.
#[test]
fn a_covariance_that_is_not_one_is_refused() {
    let v = serde_json::to_value(fusion()).unwrap();
    let p: [[f64; 3]; 3] = serde_json::from_value(v["segment"]["p"].clone()).unwrap();
    let root = |i: usize, j: usize| (p[i][i] * p[j][j]).sqrt();
    let edits: [(&[Edit], &str); 6] = [
        (
            &[(1, 1, -1e-6)],
            "invalid parameter scale variance = -0.000001: must be >= 0",
        ),
        (
            &[(2, 2, -1.0)],
            "invalid parameter bias variance = -1: must be >= 0",
        ),
        (
            &[(0, 0, -1e-3)],
            "invalid parameter heading variance = -0.001",
        ),
        (
            &[(1, 2, 1.5 * root(1, 2)), (2, 1, 1.5 * root(1, 2))],
            "invalid parameter scale-bias covariance",
        ),
        (
            &[(1, 0, -p[0][1])],
            "invalid parameter heading-scale covariance",
        ),
        (
            // each pair within its bound, the three together not: correlations 0.9, 0.9, -0.9
            &[
                (0, 1, 0.9 * root(0, 1)),
                (1, 0, 0.9 * root(0, 1)),
                (0, 2, 0.9 * root(0, 2)),
                (2, 0, 0.9 * root(0, 2)),
                (1, 2, -0.9 * root(1, 2)),
                (2, 1, -0.9 * root(1, 2)),
            ],
            "invalid parameter filter covariance",
        ),
    ];
    for (edit, message) in edits {
        let mut e = v.clone();
        for &(i, j, value) in edit {
            e["segment"]["p"][i][j] = json!(value);
        }
        let err = refused::<Fusion>(e);
        assert!(err.contains(message), "{edit:?}: {err}");
    }
    let mut e = v.clone();
    e["segment"]["x"][1] = json!(0.0);
    let err = refused::<Fusion>(e);
    assert!(err.contains("invalid parameter filter scale = 0"), "{err}");
    // the filter leaves every variance >= 0: a heading variance a rounding below 0 is refused too
    let mut e = v.clone();
    e["segment"]["p"][0][0] = json!(-1e-30);
    for (i, j) in [(0, 1), (1, 0), (0, 2), (2, 0)] {
        e["segment"]["p"][i][j] = json!(0.0);
    }
    let err = refused::<Fusion>(e);
    assert!(
        err.contains("invalid parameter heading variance = -1e-30"),
        "{err}"
    );
}

/// Initial sigmas far below the fixes' (1e-80 rad/s on the bias: valid settings) leave variances
/// whose product lies below the smallest normal double: the bound on their covariance, the root
/// of that product, came out 0 and refused the filter's own state read back (`heading-bias
/// covariance = 1.8e-159`), and the filter's rebuild of a covariance set such ones to 0.
#[test]
fn a_filter_with_tiny_variances_reads_back() {
    for (bias_sigma, scale_sigma) in [
        (1e-80, 0.01),
        (0.01, 1e-80),
        (1e-150, 1e-100),
        (1e-160, 0.01),
    ] {
        let config = FusionConfig {
            arw: 0.0,
            bias_walk: 0.0,
            scale_walk: 0.0,
            initial_heading_sigma: 0.1,
            initial_bias_sigma: bias_sigma,
            initial_scale_sigma: scale_sigma,
            gate: f64::INFINITY,
            ..FusionConfig::default()
        };
        let t: Vec<f64> = (0..100).map(|i| i as f64).collect();
        let r: Vec<f64> = (0..100)
            .map(|i| 0.5 * ((i as f64 * 0.05).sin() + 0.3))
            .collect();
        let fixes: Vec<Fix> = (0..100)
            .step_by(3)
            .map(|i| Fix {
                t: t[i] + 0.25,
                heading: 0.1 * i as f64,
                sigma: 1e-12,
            })
            .collect();
        let mut f = Fusion::new(config).unwrap();
        in_blocks(&mut f, (&t, &r), &fixes, 25, |f, k, _, _| {
            let json = serde_json::to_string(f).unwrap();
            serde_json::from_str::<Fusion>(&json)
                .map(|_| ())
                .map_err(|e| format!("{bias_sigma:e} {scale_sigma:e} at {k}: {e}"))
        })
        .unwrap();
    }
}

/// `(p11, p22, worst correlation)` of a filter's stored covariance.
fn variances_and_correlation(f: &Fusion) -> (f64, f64, f64) {
    let v = serde_json::to_value(f).unwrap();
    let p: [[f64; 3]; 3] = serde_json::from_value(v["segment"]["p"].clone()).unwrap();
    let mut worst = 0.0f64;
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        // the product of the deviations: that of the variances underflows below 1e-308
        let bound = p[i][i].max(0.0).sqrt() * p[j][j].max(0.0).sqrt();
        worst = worst.max(if p[i][j] == 0.0 {
            0.0
        } else {
            p[i][j].abs() / bound
        });
    }
    (p[1][1], p[2][2], worst)
}

/// Fixes far tighter than the gyro's noise, without process noise: the update cancelled below
/// what float64 resolves and left a negative scale or bias variance and correlations beyond 1
/// (a bias variance of -8e-13 beside 3e-11 rad fixes). The filter keeps its covariance one, so
/// every state it leaves reads back, and its sigmas stay finite.
#[test]
fn fixes_far_tighter_than_the_gyro_leave_a_covariance() {
    let cases = [
        // arw, bias_walk, initial heading, bias and scale sigmas, fix sigma, dt, rate
        (
            1.41e-8, 2.97e-7, 0.104, 25.8, 8.6e-7, 2.86e-11, 0.0147, 234.6,
        ),
        (0.0, 0.0, 17.35, 9.7e-5, 1.25e-8, 3.68e-11, 5.69, 2.7e-3),
        (0.0, 0.0, 0.0376, 906.5, 1.49e-4, 3.93e-10, 7.57, 3.4e-3),
    ];
    for (arw, bias_walk, heading_sigma, bias_sigma, scale_sigma, sigma, dt, rate) in cases {
        let config = FusionConfig {
            arw,
            bias_walk,
            scale_walk: 0.0,
            initial_heading_sigma: heading_sigma,
            initial_bias_sigma: bias_sigma,
            initial_scale_sigma: scale_sigma,
            gate: f64::INFINITY,
            ..FusionConfig::default()
        };
        let n = 400;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
        let r: Vec<f64> = (0..n)
            .map(|i| rate * ((i as f64 * 0.05).sin() + 0.3))
            .collect();
        let fixes: Vec<Fix> = (0..n)
            .step_by(3)
            .map(|i| Fix {
                t: t[i] + 0.25 * dt,
                heading: (0.1 * i as f64) % 1e6,
                sigma,
            })
            .collect();
        let mut f = Fusion::new(config).unwrap();
        in_blocks(&mut f, (&t, &r), &fixes, 37, |f, k, _, s| {
            assert!(s.iter().all(|s| s.is_finite()), "{s:?}");
            let (p11, p22, correlation) = variances_and_correlation(f);
            assert!(
                p11 >= 0.0 && p22 >= 0.0 && correlation <= 1.0 + 1e-12,
                "sigma {sigma}, at {k}: scale {p11:e}, bias {p22:e}, correlation {correlation}"
            );
            let json = serde_json::to_string(f).unwrap();
            serde_json::from_str::<Fusion>(&json).unwrap();
            Ok::<(), ()>(())
        })
        .unwrap();
    }
}

/// The filter `f` over the samples `(t, rate)` with `fixes`, in blocks of `cut` samples (each
/// given the fixes not used yet); after each block, `check(f, samples so far, its headings, their
/// sigmas)`.
fn in_blocks<E>(
    f: &mut Fusion,
    (t, rate): (&[f64], &[f64]),
    fixes: &[Fix],
    cut: usize,
    mut check: impl FnMut(&Fusion, usize, &[f64], &[f64]) -> Result<(), E>,
) -> Result<(), E> {
    let (mut used, mut k) = (0, 0);
    while k < t.len() {
        let m = cut.min(t.len() - k);
        let (mut h, mut s) = (vec![0.0; m], vec![0.0; m]);
        let out = FusionOutputs {
            heading: &mut h,
            heading_sigma: Some(&mut s),
            bias: None,
            scale: None,
        };
        used += f
            .process_block(&t[k..k + m], &rate[k..k + m], &fixes[used..], out)
            .unwrap();
        k += m;
        check(f, k, &h, &s)?;
    }
    Ok(())
}

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

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(200))]

    /// Any filter's noise, from none to much, fixes from the tightest (1e-12 rad) to loose ones
    /// that agree with the gyro or scatter, any sample interval and rate: after every block the
    /// stored covariance is one (variances >= 0, correlations within 1), the state reads back,
    /// and every sigma is finite.
    #[test]
    fn every_state_a_filter_leaves_reads_back(
        noise in proptest::array::uniform3(-10.0f64..0.0),
        none in proptest::array::uniform3(proptest::bool::ANY),
        heading_initial in -8.0f64..2.0,
        // down to 1e-160: variances whose products lie below the smallest normal double
        initial in proptest::array::uniform2(-160.0f64..2.0),
        sigma in -12.0f64..0.0,
        dt in -4.0f64..1.0,
        rate in -3.0f64..5.0,
        every in 1usize..20,
        scatter in 0.0f64..1.0,
        cut in 1usize..80,
    ) {
        let walk = |i: usize| if none[i] { 0.0 } else { 10f64.powf(noise[i]) };
        let config = FusionConfig {
            arw: walk(0),
            bias_walk: walk(1),
            scale_walk: walk(2),
            initial_heading_sigma: 10f64.powf(heading_initial),
            initial_bias_sigma: 10f64.powf(initial[0]).min(1e3),
            initial_scale_sigma: 10f64.powf(initial[1]).min(0.5),
            gate: f64::INFINITY,
            ..FusionConfig::default()
        };
        let (dt, rate, sigma) = (10f64.powf(dt), 10f64.powf(rate), 10f64.powf(sigma));
        let n = 300;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
        let r: Vec<f64> = (0..n).map(|i| rate * ((i as f64 * 0.05).sin() + 0.3)).collect();
        let fixes: Vec<Fix> = (0..n)
            .step_by(every)
            .map(|i| Fix {
                t: t[i] + 0.3 * dt,
                heading: (0.1 * i as f64 + scatter * (i as f64 * 12.9898).sin()) % 1e6,
                sigma,
            })
            .collect();
        let mut f = Fusion::new(config).unwrap();
        in_blocks(&mut f, (&t, &r), &fixes, cut, |f, k, h, s| {
            proptest::prop_assert!(s.iter().chain(h).all(|x| x.is_finite()));
            let (p11, p22, correlation) = variances_and_correlation(f);
            proptest::prop_assert!(
                p11 >= 0.0 && p22 >= 0.0 && correlation <= 1.0 + 1e-12,
                "at {}: scale {:e}, bias {:e}, correlation {}", k, p11, p22, correlation
            );
            let json = serde_json::to_string(f).unwrap();
            let back = serde_json::from_str::<Fusion>(&json);
            proptest::prop_assert!(back.is_ok(), "at {}: {:?}", k, back);
            Ok(())
        })?;
    }
}
