//! The fix filter's smoother across `restart_clock()`: a restart is a step of no time, the state
//! and covariance carried over, so the smoothed estimates are those of one clock on which the
//! second part follows the first at once (the fixes after the jump correct the samples before
//! it too).

use gyrocore::*;

/// `n` samples at 128 Hz from `t0`, of the rate `0.01 + 0.2 sin` (the bias of 0.01 rad/s that
/// the filter learns from the fixes), and the true heading from `heading0` on.
fn drive(t0: f64, n: usize, heading0: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = (0..n).map(|i| t0 + i as f64 / 128.0).collect();
    let rate: Vec<f64> = (0..n)
        .map(|i| 0.01 + 0.2 * (i as f64 / 200.0).sin())
        .collect();
    let mut heading = vec![heading0; n];
    for k in 1..n {
        let turn = 0.5 * (rate[k - 1] + rate[k] - 0.02) * (t[k] - t[k - 1]);
        heading[k] = heading[k - 1] + turn;
    }
    (t, rate, heading)
}

/// Fixes of the true heading at the samples `at` (sigma 0.02 rad).
fn fixes_at(t: &[f64], heading: &[f64], at: &[usize]) -> Vec<Fix> {
    at.iter()
        .map(|&k| Fix {
            t: t[k],
            heading: heading[k],
            sigma: 0.02,
        })
        .collect()
}

type Columns = [Vec<f64>; 4];

/// The smoothed estimates of the blocks `(t, rate, fixes)`, the clock restarted before each
/// block after the first when `restart`: a forward pass recording the knots, the backward pass,
/// and the second forward pass of a fresh filter, restarted alike.
fn smoothed(blocks: &[(Vec<f64>, Vec<f64>, Vec<Fix>)], restart: bool) -> (Columns, FixCounts) {
    let n: usize = blocks.iter().map(|b| b.0.len()).sum();
    let mut cols: Columns = core::array::from_fn(|_| vec![0.0; n]);
    let mut knots: Vec<Knot> = Vec::new();
    let mut forward = Fusion::new(FusionConfig::default()).unwrap();
    let mut start = 0;
    for (i, (t, rate, fixes)) in blocks.iter().enumerate() {
        if restart && i > 0 {
            forward.restart_clock();
        }
        let out = FusionOutputs::heading(&mut cols[0][start..start + t.len()]);
        let used = forward
            .process_block_recording(t, rate, fixes, out, |k| knots.push(k))
            .unwrap();
        assert_eq!(used, fixes.len());
        start += t.len();
    }
    assert_eq!(smooth(&mut knots), 0);
    let mut again = Fusion::new(FusionConfig::default()).unwrap();
    let [h, s, b, sc] = &mut cols;
    let mut start = 0;
    for (i, (t, rate, fixes)) in blocks.iter().enumerate() {
        if restart && i > 0 {
            again.restart_clock();
        }
        let range = start..start + t.len();
        let out = FusionOutputs::all(
            &mut h[range.clone()],
            &mut s[range.clone()],
            &mut b[range.clone()],
            &mut sc[range],
        );
        again
            .process_block_smoothed(t, rate, fixes, &knots, out)
            .unwrap();
        start += t.len();
    }
    (cols, forward.counts())
}

#[test]
fn the_smoother_runs_across_a_restart_as_across_a_step_of_no_time() {
    let n = 2560;
    let (ta, ra, ha) = drive(100.0, n, 0.3);
    // the new clock reads 3 s; the heading goes on from where it was
    let (tb, rb, hb) = drive(3.0, n, ha[n - 1]);
    let (fa, fb) = (
        fixes_at(&ta, &ha, &[200, 700]),
        fixes_at(&tb, &hb, &[900, 1600, 2400]),
    );
    let (got, counts) = smoothed(
        &[
            (ta.clone(), ra.clone(), fa.clone()),
            (tb.clone(), rb.clone(), fb),
        ],
        true,
    );
    assert_eq!((counts.applied, counts.rejected), (5, 0));
    // one clock, the second part 1e-9 s after the first: the step between them moves the heading
    // by 1e-9 s times the rate (~1e-11 rad; the estimates differed by 1e-11 at most) and its variance by as little
    let shift = ta[n - 1] + 1e-9 - tb[0];
    let tb1: Vec<f64> = tb.iter().map(|&t| t + shift).collect();
    let fb1 = fixes_at(&tb1, &hb, &[900, 1600, 2400]);
    let (one_clock, _) = smoothed(&[(ta, ra, fa), (tb1, rb, fb1)], false);
    for (name, (got, expected)) in ["heading", "sigma", "bias", "scale"]
        .iter()
        .zip(got.iter().zip(&one_clock))
    {
        for (k, (g, e)) in got.iter().zip(expected).enumerate() {
            assert!(
                (g - e).abs() <= 1e-10,
                "{name}[{k}]: {g} across the restart, {e} on one clock"
            );
        }
    }
    // the fixes after the jump reach back: at the end of the first part, 4 s after its last fix,
    // the smoothed heading is within a fix's sigma of the truth
    assert!(
        (got[0][n - 1] - ha[n - 1]).abs() < 0.02,
        "{} vs {}",
        got[0][n - 1],
        ha[n - 1]
    );
}
