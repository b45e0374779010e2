//! The heading-fix filter's state read back (`serde` feature): what valid input leaves reads
//! back, however tight its fixes or tiny its variances, and a covariance that is not one is
//! refused naming it.
#![cfg(feature = "serde")]

mod common;

use gyrocore::*;
use serde_json::json;

mod states;
use states::{fusion, refused};

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

/// Times that contradict each other: a knot after the time the filter stands at (the heading
/// sigma grew as if the time were ahead), a last fix or sample after it, a filter standing
/// 1005 s behind its last fix (the next block integrated it all as rate: a heading of 101.5 rad
/// where 1.0 was right). Each is refused naming it.
#[test]
fn a_filter_whose_times_are_out_of_order_is_refused() {
    let v = serde_json::to_value(fusion()).unwrap();
    for (at, value, name) in [
        ("/segment/t", 1000.0, "segment time"),
        ("/anchor/t", -1000.0, "last fix time"),
        ("/anchor/sample_t", 1000.0, "filter sample time"),
        ("/last_fix", 1000.0, "last fix time"),
    ] {
        let mut e = v.clone();
        *e.pointer_mut(at).unwrap() = json!(value);
        let err = refused::<Fusion>(e);
        assert!(err.contains(&format!("invalid parameter {name}")), "{err}");
    }
    let f: Fusion = serde_json::from_value(v).unwrap();
    assert!(f.last_time().is_some());
}

/// A fused pipeline whose filter stands elsewhere than its pipeline: behind, the next block
/// gave a heading of 101.5 rad where 1.0 was right; ahead, it refused the next valid fix.
#[test]
fn a_fused_pipeline_whose_filter_and_pipeline_disagree_on_time_is_refused() {
    let mut f = FusedPipeline::new(Preset::Raw.config(), FusionConfig::default()).unwrap();
    let fixes: Vec<Fix> = (0..5)
        .map(|s| Fix {
            t: s as f64 + 0.005,
            heading: 0.1 * s as f64,
            sigma: 0.01,
        })
        .collect();
    let t: Vec<f64> = (0..500).map(|i| i as f64 * 0.01).collect();
    let n = t.len();
    let (mut h, mut r) = (vec![0.0; n], vec![0.0; n]);
    let out = common::heading_and_rate(&mut h, &mut r);
    f.process_block(Samples::new(&t, &vec![0.1; n]), &fixes, out)
        .unwrap();
    let v = serde_json::to_value(&f).unwrap();
    for time in [1000.0, 4.98] {
        let mut e = v.clone();
        e["fusion"]["anchor"]["t"] = json!(time);
        e["fusion"]["anchor"]["sample_t"] = json!(time);
        let err = refused::<FusedPipeline>(e);
        assert!(err.contains("invalid parameter filter time"), "{err}");
    }
    let back: FusedPipeline = serde_json::from_value(v).unwrap();
    assert_eq!(back.fusion().last_time(), back.pipeline().last_time());
}

/// A run of rejected fixes read back: its first fix after the time the filter stands at, or a
/// run of no fix or of more fixes than were rejected, is refused naming it. A filter stored
/// before re-admission existed (no `readmit_after`, `readmitted` or `rejected_run`) reads back
/// as it ran: the gate alone.
#[test]
fn a_run_of_rejections_read_back_is_checked_and_an_older_state_reads_without_one() {
    let v = serde_json::to_value(fusion()).unwrap();
    let now = v["anchor"]["t"].as_f64().unwrap();
    let last_fix = v["last_fix"].as_f64().unwrap();
    assert_eq!(v["counts"]["rejected"], json!(0));
    for (run, name) in [
        (json!([now + 1.0, 1]), "first rejected fix time"),
        (json!([last_fix, 0]), "rejected run"),
        (json!([last_fix, 1]), "rejected run"),
    ] {
        let mut e = v.clone();
        e["rejected_run"] = run;
        let err = refused::<Fusion>(e);
        assert!(err.contains(&format!("invalid parameter {name}")), "{err}");
    }
    let mut older = v.clone();
    older.as_object_mut().unwrap().remove("rejected_run");
    older["counts"]
        .as_object_mut()
        .unwrap()
        .remove("readmitted");
    older["config"]
        .as_object_mut()
        .unwrap()
        .remove("readmit_after");
    let f: Fusion = serde_json::from_value(older).unwrap();
    assert_eq!(f.config().readmit_after, f64::INFINITY);
    assert_eq!(f.counts().readmitted, 0);
}
