//! The heading-fix filter where fixes are far tighter than the gyro's noise: its variances
//! round below 0, and its sigmas and read-back states must stay usable.

use gyrocore::fixes::wrap_angle;
use gyrocore::fixes_smooth::Knot;
use gyrocore::{smooth, Fix, Fusion, FusionConfig, FusionOutputs};

/// 20 s at 100 Hz of a steady turn of 0.1 rad/s, and a filter without process noise or gate.
fn noiseless_without_gate() -> (Vec<f64>, Vec<f64>, FusionConfig) {
    let t: Vec<f64> = (0..2000).map(|i| i as f64 * 0.01).collect();
    let rate = vec![0.1; t.len()];
    let settings = FusionConfig {
        arw: 0.0,
        bias_walk: 0.0,
        scale_walk: 0.0,
        gate: f64::INFINITY,
        ..FusionConfig::default()
    };
    (t, rate, settings)
}

/// A fix of 1e-12 rad every second of that turn, off by `jump` \[rad\] alternately up and down.
fn tight_fixes(jump: f64) -> Vec<Fix> {
    (1..19)
        .map(|s| Fix {
            t: s as f64,
            heading: 0.1 * s as f64 + if s % 2 == 0 { jump } else { -jump },
            sigma: 1e-12,
        })
        .collect()
}

#[test]
fn fixes_far_tighter_than_the_gyro_leave_finite_sigmas() {
    // No noise on the gyro, 1e-12 rad fixes, no gate: the heading variance's terms cancel below
    // what float64 resolves, and every sigma after the second fix was NaN, causal and smoothed.
    // Fixes that agree with the gyro pin the heading to what the numbers resolve (once two fixes
    // give the bias); fixes that contradict each other by 1 rad give wild estimates, but finite
    // sigmas. A state left so (a variance rounded below 0) is read back.
    let (t, rate, settings) = noiseless_without_gate();
    // a third set: 40 fixes at uneven times, 1e-10 rad, scattered by up to 0.3 rad
    let scattered: Vec<Fix> = (0..40)
        .map(|k| {
            let t = 0.05 + 0.49 * k as f64 + 0.1 * (k as f64 * 2.3).sin();
            Fix {
                t,
                heading: 0.1 * t + 0.3 * (k as f64 * 12.9898).sin(),
                sigma: 1e-10,
            }
        })
        .collect();
    for jump in [0.0, 0.5, f64::NAN] {
        let fixes: Vec<Fix> = if jump.is_nan() {
            scattered.clone()
        } else {
            tight_fixes(jump)
        };
        let mut fusion = Fusion::new(settings).unwrap();
        let n = t.len();
        let (mut h, mut s, mut b, mut sc) =
            (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let mut knots: Vec<Knot> = Vec::new();
        let out = FusionOutputs::all(&mut h, &mut s, &mut b, &mut sc);
        assert_eq!(
            fusion.process_block_recording(&t, &rate, &fixes, out, |k| knots.push(k)),
            Ok(fixes.len())
        );
        smooth(&mut knots);
        let (mut sh, mut ss, mut sb, mut ssc) =
            (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let out = FusionOutputs::all(&mut sh, &mut ss, &mut sb, &mut ssc);
        let smoothed = Fusion::new(settings)
            .unwrap()
            .process_block_smoothed(&t, &rate, &fixes, &knots, out);
        assert_eq!(smoothed, Ok(fixes.len()));
        for (what, sigma) in [("causal", &s), ("smoothed", &ss)] {
            let bad: Vec<(usize, f64)> = sigma
                .iter()
                .copied()
                .enumerate()
                .filter(|(_, s)| !(s.is_finite() && *s >= 0.0))
                .collect();
            assert!(
                bad.is_empty(),
                "jump {jump}, {what}: {:?}",
                &bad[..bad.len().min(5)]
            );
            if jump == 0.0 {
                let most = sigma[200..].iter().fold(0.0f64, |m, s| m.max(*s));
                assert!(most < 1e-6, "{what}: {most}");
            }
        }
        assert!(h.iter().chain(&sh).all(|h| h.is_finite()));
        #[cfg(feature = "serde")]
        for cut in (0..n).step_by(37) {
            let mut part = Fusion::new(settings).unwrap();
            let (mut ph, mut ps, mut pb, mut psc) = (
                vec![0.0; cut],
                vec![0.0; cut],
                vec![0.0; cut],
                vec![0.0; cut],
            );
            let out = FusionOutputs::all(&mut ph, &mut ps, &mut pb, &mut psc);
            part.process_block(&t[..cut], &rate[..cut], &fixes, out)
                .unwrap();
            let json = serde_json::to_string(&part).unwrap();
            let back: Result<Fusion, _> = serde_json::from_str(&json);
            assert!(back.is_ok(), "jump {jump}, cut {cut}: {back:?}");
        }
    }
}

/// With no gate (`gate = inf`), no fix is refused: where fixes of 1e-12 rad are far tighter than
/// a gyro without noise, the heading variance predicted at a fix rounds below minus the fix's
/// own variance, and 4 of 18 fixes were refused as outliers (an innovation variance below 0
/// times an infinite gate).
#[test]
fn no_gate_refuses_no_fix_where_the_heading_variance_rounds_below_0() {
    let (t, rate, settings) = noiseless_without_gate();
    for jump in [0.0, 0.5] {
        let fixes = tight_fixes(jump);
        let mut fusion = Fusion::new(settings).unwrap();
        let n = t.len();
        let (mut h, mut s, mut b, mut sc) =
            (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let out = FusionOutputs::all(&mut h, &mut s, &mut b, &mut sc);
        fusion.process_block(&t, &rate, &fixes, out).unwrap();
        let counts = fusion.counts();
        assert_eq!((counts.applied, counts.rejected), (18, 0), "jump {jump}");
        assert!(
            [&h, &s, &b, &sc]
                .iter()
                .all(|c| c.iter().all(|v| v.is_finite())),
            "jump {jump}"
        );
        if jump == 0.0 {
            assert!((h[n - 1] - 0.1 * t[n - 1]).abs() < 1e-6, "{}", h[n - 1]);
        }
    }
}

/// `wrap_angle` keeps its range (-pi, pi] for every finite angle: near an odd multiple of pi the
/// rounding of `a - 2 pi ceil(...)` gave 3.1415926535897967 for 23 pi and 3.1415926535901235
/// for -3829.6 rad (above pi), and beyond 2^53 it gave 0 whatever the angle.
#[test]
fn wrap_angle_stays_within_minus_pi_and_pi() {
    use std::f64::consts::PI;
    let near = |x: f64| {
        [
            x,
            f64::from_bits(x.to_bits() + 1),
            f64::from_bits(x.to_bits() - 1),
        ]
    };
    for k in (1..2000).step_by(2) {
        for x in near(k as f64 * PI)
            .into_iter()
            .chain(near(-(k as f64) * PI))
        {
            let w = wrap_angle(x);
            assert!(w > -PI && w <= PI, "{x:e} -> {w:e}");
        }
    }
    for x in [-3829.6014447259577, 1e10, 1e20, -1e300, f64::MAX] {
        let w = wrap_angle(x);
        assert!(w > -PI && w <= PI, "{x:e} -> {w:e}");
    }
    assert_eq!(wrap_angle(-PI), PI);
    assert_eq!(wrap_angle(0.5), 0.5);
}
