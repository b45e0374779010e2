//! The heading-fix filter and its smoother (rust/src/fixes.rs, fixes_smooth.rs).

mod fix_drive;

use fix_drive::{config, drive, fixes, run, BIAS, SCALE};
use gyrocore::fixes::{wrap_angle, FixProblem};
use gyrocore::fixes_smooth::Knot;
use gyrocore::{smooth, Fix, Fusion, FusionConfig, FusionError, FusionOutputs};

#[test]
fn a_simulated_drive_with_known_bias_and_scale_converges() {
    let (t, psi, rate) = drive(600.0);
    let fx = fixes(&t, &psi, 100, (0.0, 0.0));
    // No gate: a gate also rejects about 0.1 % of good fixes, which would make counts random.
    let mut f = Fusion::new(FusionConfig {
        gate: f64::INFINITY,
        ..config()
    })
    .unwrap();
    let (r, used) = run(&mut f, &t, &rate, &fx).unwrap();
    assert_eq!(used, fx.len());
    assert_eq!(f.counts().applied, fx.len() as u64);
    assert_eq!(f.counts().rejected, 0);
    let last = t.len() - 1;
    assert!((r.bias[last] - BIAS).abs() < 2e-4, "bias {}", r.bias[last]);
    assert!(
        (r.scale[last] - SCALE).abs() < 2e-3,
        "scale {}",
        r.scale[last]
    );
    // After the first minute the heading stays within 3 of its own sigmas and within 0.5 deg.
    for k in 6000..t.len() {
        let e = wrap_angle(r.heading[k] - psi[k]);
        assert!(e.abs() < 0.5f64.to_radians(), "t = {}: error {e}", t[k]);
        assert!(
            e.abs() < 4.0 * r.sigma[k],
            "t = {}: error {e} sigma {}",
            t[k],
            r.sigma[k]
        );
    }
}

#[test]
fn chunked_and_snapshotted_runs_are_bit_identical_to_one_call() {
    let (t, psi, rate) = drive(120.0);
    let fx = fixes(&t, &psi, 37, (0.0, 0.0));
    let mut whole = Fusion::new(config()).unwrap();
    let (one, _) = run(&mut whole, &t, &rate, &fx).unwrap();
    let mut chunked = Fusion::new(config()).unwrap();
    let mut pending: &[Fix] = &fx;
    let mut heading = Vec::new();
    for (k, chunk) in [0..1, 1..500, 500..501, 501..4321, 4321..t.len()]
        .into_iter()
        .enumerate()
    {
        if k == 3 {
            // A copy taken mid-run carries on exactly as the original.
            chunked = Fusion::clone(&chunked);
        }
        let (r, used) = run(&mut chunked, &t[chunk.clone()], &rate[chunk], pending).unwrap();
        pending = &pending[used..];
        heading.extend(r.heading);
    }
    assert!(pending.is_empty());
    assert_eq!(whole, chunked);
    assert_eq!(
        one.heading.iter().map(|h| h.to_bits()).collect::<Vec<_>>(),
        heading.iter().map(|h| h.to_bits()).collect::<Vec<_>>()
    );
}

#[test]
fn a_fix_half_a_turn_off_is_rejected_and_counted() {
    let (t, psi, rate) = drive(120.0);
    let good = fixes(&t, &psi, 100, (0.0, 0.0));
    let mut fx = good.clone();
    fx[90].heading = wrap_angle(fx[90].heading + std::f64::consts::PI);
    let (mut clean, mut f) = (
        Fusion::new(config()).unwrap(),
        Fusion::new(config()).unwrap(),
    );
    let (expected, _) = run(&mut clean, &t, &rate, &good).unwrap();
    let (r, _) = run(&mut f, &t, &rate, &fx).unwrap();
    // Exactly one more rejection than without the bad fix, and the heading stays with the clean run's.
    assert_eq!(f.counts().rejected, clean.counts().rejected + 1);
    assert_eq!(f.counts().applied + 1, clean.counts().applied);
    let k = 9100;
    assert!(wrap_angle(r.heading[k] - psi[k]).abs() < 0.5f64.to_radians());
    assert!(wrap_angle(r.heading[k] - expected.heading[k]).abs() < 0.1f64.to_radians());
}

#[test]
fn bad_fixes_are_named() {
    let (t, psi, rate) = drive(10.0);
    let good = fixes(&t, &psi, 100, (0.0, 0.0));
    let cases: [(usize, Fix, &str, FixProblem); 7] = [
        (
            3,
            Fix {
                sigma: 0.0,
                ..good[3]
            },
            "sigma",
            FixProblem::NotPositive,
        ),
        (
            4,
            Fix {
                heading: f64::NAN,
                ..good[4]
            },
            "heading",
            FixProblem::NonFinite,
        ),
        (
            5,
            Fix {
                t: good[3].t - 1.0,
                ..good[5]
            },
            "t",
            FixProblem::OutOfOrder {
                previous: good[4].t,
            },
        ),
        (
            2,
            Fix {
                sigma: -1.0,
                ..good[2]
            },
            "sigma",
            FixProblem::NotPositive,
        ),
        // Wrapped, 1e17 rad is 0: it would pass for a fix that agrees exactly.
        (
            6,
            Fix {
                heading: 1e17,
                ..good[6]
            },
            "heading",
            FixProblem::OutOfRange,
        ),
        // Its square is 0: two such fixes at one time divide 0 by 0.
        (
            7,
            Fix {
                sigma: 1e-200,
                ..good[7]
            },
            "sigma",
            FixProblem::OutOfRange,
        ),
        (
            1,
            Fix {
                sigma: 1e7,
                ..good[1]
            },
            "sigma",
            FixProblem::OutOfRange,
        ),
    ];
    for (index, bad, what, problem) in cases {
        let mut fx = good.clone();
        fx[index] = bad;
        let mut f = Fusion::new(config()).unwrap();
        let before = f;
        let err = run(&mut f, &t, &rate, &fx).err().unwrap();
        let FusionError::Fix {
            index: i,
            what: w,
            problem: p,
            ..
        } = err
        else {
            panic!("{err:?}")
        };
        assert_eq!((i, w, p), (index, what, problem));
        assert!(
            err.to_string()
                .starts_with(&format!("fix {index}: {what} = ")),
            "{err}"
        );
        assert_eq!(f, before, "nothing is processed from a bad block");
    }
    // A fix older than a sample already processed cannot be applied at its time.
    let mut f = Fusion::new(config()).unwrap();
    run(&mut f, &t[..500], &rate[..500], &[]).unwrap();
    let err = run(&mut f, &t[500..], &rate[500..], &good[..1])
        .err()
        .unwrap();
    assert!(
        matches!(
            err,
            FusionError::Fix {
                index: 0,
                problem: FixProblem::Late { .. },
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn fixes_before_the_first_sample_are_counted_and_skipped() {
    let (t, psi, rate) = drive(10.0);
    let mut fx = fixes(&t, &psi, 100, (0.0, 0.0));
    fx.insert(
        0,
        Fix {
            t: -2.0,
            heading: 3.0,
            sigma: 0.01,
        },
    );
    fx.insert(
        1,
        Fix {
            t: -1.0,
            heading: 3.0,
            sigma: 0.01,
        },
    );
    let mut f = Fusion::new(config()).unwrap();
    let (_, used) = run(&mut f, &t, &rate, &fx).unwrap();
    assert_eq!(used, fx.len());
    assert_eq!(f.counts().before_start, 2);
    assert_eq!(f.counts().applied, fx.len() as u64 - 2);
}

#[test]
fn bad_settings_are_named() {
    for (name, config) in [
        (
            "arw",
            FusionConfig {
                arw: -1.0,
                ..config()
            },
        ),
        (
            "gate",
            FusionConfig {
                gate: 0.0,
                ..config()
            },
        ),
        (
            "initial_scale_sigma",
            FusionConfig {
                initial_scale_sigma: 0.9,
                ..config()
            },
        ),
        (
            "initial_heading_sigma",
            FusionConfig {
                initial_heading_sigma: f64::NAN,
                ..config()
            },
        ),
        // Squares of these overflowed: every estimate NaN after the first fix.
        (
            "bias_walk",
            FusionConfig {
                bias_walk: 1e200,
                ..config()
            },
        ),
        (
            "initial_bias_sigma",
            FusionConfig {
                initial_bias_sigma: 1e200,
                ..config()
            },
        ),
    ] {
        let err = Fusion::new(config).unwrap_err();
        assert!(err.to_string().contains(name), "{err}");
    }
}

/// The filter's initial heading has the pipeline's limit and words (`IntegratorConfig`): at 2^40
/// rad a double's spacing (2.4e-4 rad) swallowed every increment below it.
#[test]
fn an_initial_heading_beyond_2_pow_20_rad_is_refused_as_the_pipeline_refuses_it() {
    let pipeline = gyrocore::IntegratorConfig {
        initial_heading: 2f64.powi(30),
        ..Default::default()
    }
    .validate()
    .unwrap_err()
    .to_string();
    for heading in [2f64.powi(30), -2f64.powi(21), f64::INFINITY, f64::NAN] {
        let err = Fusion::new(FusionConfig {
            initial_heading: heading,
            ..config()
        })
        .unwrap_err()
        .to_string();
        assert!(err.contains("initial_heading"), "{err}");
        if heading.is_finite() {
            assert!(err.contains("within +-2^20 rad"), "{err}");
        }
    }
    let fusion = Fusion::new(FusionConfig {
        initial_heading: 2f64.powi(30),
        ..config()
    })
    .unwrap_err()
    .to_string();
    assert_eq!(fusion, pipeline);
    for heading in [2f64.powi(20), -2f64.powi(20)] {
        assert!(Fusion::new(FusionConfig {
            initial_heading: heading,
            ..config()
        })
        .is_ok());
    }
}

#[test]
fn the_smoother_beats_the_filter_inside_an_outage() {
    let (t, psi, rate) = drive(600.0);
    let outage = (300.0, 420.0);
    let fx = fixes(&t, &psi, 100, outage);
    let mut f = Fusion::new(config()).unwrap();
    let n = t.len();
    let (mut h, mut s, mut b, mut sc) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let out = FusionOutputs::all(&mut h, &mut s, &mut b, &mut sc);
    let mut knots: Vec<Knot> = Vec::new();
    f.process_block_recording(&t, &rate, &fx, out, |k| knots.push(k))
        .unwrap();
    // one at the first sample, one per fix applied
    assert_eq!(knots.len() as u64, 1 + f.counts().applied);
    assert_eq!(smooth(&mut knots), 0);
    let (mut sh, mut ss, mut sb, mut ssc) =
        (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let out = FusionOutputs::all(&mut sh, &mut ss, &mut sb, &mut ssc);
    let mut again = Fusion::new(config()).unwrap();
    assert_eq!(
        again.process_block_smoothed(&t, &rate, &fx, &knots, out),
        Ok(fx.len())
    );
    let inside: Vec<usize> = (0..n)
        .filter(|&k| t[k] >= outage.0 && t[k] < outage.1)
        .collect();
    let mean_abs = |e: &dyn Fn(usize) -> f64| {
        inside.iter().map(|&k| e(k).abs()).sum::<f64>() / inside.len() as f64
    };
    let causal = mean_abs(&|k| wrap_angle(h[k] - psi[k]));
    let smooth_err = mean_abs(&|k| wrap_angle(sh[k] - psi[k]));
    assert!(
        smooth_err < 0.5 * causal,
        "smoothed {smooth_err} vs causal {causal}"
    );
    // The smoother is also more certain inside the outage.
    let mid = inside[inside.len() / 2];
    assert!(ss[mid] < s[mid]);
}

/// An initial bias sigma beyond the bias's own range (1000 rad/s) is refused: 1e6 rad/s beside
/// an unknown heading (sigma 2^20 rad) left the covariance to rounding at the first fix, and the
/// heading sigma was NaN from there on, without an error. At the limit every estimate is finite.
#[test]
fn an_initial_bias_sigma_beyond_the_bias_range_is_refused() {
    let wide = |initial_bias_sigma| FusionConfig {
        initial_heading_sigma: 1048576.0,
        initial_bias_sigma,
        gate: f64::INFINITY,
        ..config()
    };
    let err = Fusion::new(wide(1e6)).unwrap_err().to_string();
    assert!(err.contains("initial_bias_sigma = 1000000"), "{err}");
    let mut fusion = Fusion::new(wide(1e3)).unwrap();
    let n = 3000;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.01).collect();
    let rate = vec![0.1; n];
    let fixes: Vec<Fix> = (1..150)
        .map(|k| Fix {
            t: k as f64 * 0.2 + 0.003,
            heading: 0.02 * k as f64,
            sigma: 1e-6,
        })
        .collect();
    let mut cols = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let [h, s, b, sc] = &mut cols;
    fusion
        .process_block(&t, &rate, &fixes, FusionOutputs::all(h, s, b, sc))
        .unwrap();
    assert!(cols.iter().flatten().all(|x| x.is_finite()));
}
