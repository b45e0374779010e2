//! The input policy: non-finite readings held or skipped, gaps bridged or reset, timestamps that do
//! not move forward never processed.

mod common;

use gyrocore::*;

fn config(non_finite: NonFinite) -> PipelineConfig {
    let mut c = Preset::Combined.config();
    c.correction.bias = StaticBias::Fixed(0.01);
    c.input.non_finite = non_finite;
    c
}

fn stream(n: usize) -> (Vec<f64>, Vec<f64>) {
    let t = (0..n).map(|i| 100.0 + i as f64 * 0.05).collect();
    let r = (0..n)
        .map(|i| 0.02 + 0.3 * ((i as f64) * 0.05).sin())
        .collect();
    (t, r)
}

fn block(p: &mut Pipeline, t: &[f64], r: &[f64]) -> Result<Vec<Output>, Error> {
    common::try_block(p, t, r)
}

fn same(a: &Output, b: &Output) -> bool {
    common::bits(&[*a]) == common::bits(&[*b])
}

#[test]
fn error_policy_rejects_a_block_with_a_nan_reading() {
    let (t, mut r) = stream(500);
    r[123] = f64::NAN;
    let err = block(
        &mut Pipeline::new(config(NonFinite::Error)).unwrap(),
        &t,
        &r,
    )
    .unwrap_err();
    assert!(matches!(
        err,
        Error::NonFinite {
            what: "rate",
            index: 123,
            ..
        }
    ));
}

#[test]
fn hold_uses_the_last_finite_reading() {
    let (t, mut r) = stream(500);
    let bad = [123usize, 124, 400];
    let mut filled = r.clone();
    for &i in &bad {
        r[i] = if i == 400 { f64::INFINITY } else { f64::NAN };
        filled[i] = filled[i - 1];
    }
    let mut p = Pipeline::new(config(NonFinite::Hold)).unwrap();
    let got = block(&mut p, &t, &r).unwrap();
    let want = block(
        &mut Pipeline::new(config(NonFinite::Hold)).unwrap(),
        &t,
        &filled,
    )
    .unwrap();
    assert!(got.iter().zip(&want).all(|(a, b)| same(a, b)));
    assert_eq!(p.report().held, 3);
    assert_eq!(p.report().skipped, 0);
}

#[test]
fn hold_with_nothing_to_hold_skips() {
    let (t, mut r) = stream(50);
    r[0] = f64::NAN;
    let mut p = Pipeline::new(config(NonFinite::Hold)).unwrap();
    let out = block(&mut p, &t, &r).unwrap();
    assert!(out[0].rate.is_nan() && out[0].heading == 0.0);
    assert_eq!((p.report().held, p.report().skipped), (0, 1));
}

#[test]
fn skip_equals_leaving_the_samples_out() {
    let (t, mut r) = stream(600);
    let bad = [0usize, 77, 78, 79, 300, 599];
    for &i in &bad {
        r[i] = f64::NAN;
    }
    let mut p = Pipeline::new(config(NonFinite::Skip)).unwrap();
    let got = block(&mut p, &t, &r).unwrap();
    let keep: Vec<usize> = (0..t.len()).filter(|i| !bad.contains(i)).collect();
    let kt: Vec<f64> = keep.iter().map(|&i| t[i]).collect();
    let kr: Vec<f64> = keep.iter().map(|&i| r[i]).collect();
    let want = block(
        &mut Pipeline::new(config(NonFinite::Skip)).unwrap(),
        &kt,
        &kr,
    )
    .unwrap();
    for (k, &i) in keep.iter().enumerate() {
        assert!(same(&got[i], &want[k]), "row {i}");
    }
    for &i in &bad[1..] {
        // A skipped row repeats the heading and drift of the row before, with no rate.
        assert!(got[i].rate.is_nan());
        assert_eq!(got[i].heading.to_bits(), got[i - 1].heading.to_bits());
        assert_eq!(got[i].drift.to_bits(), got[i - 1].drift.to_bits());
    }
    assert_eq!(p.report().skipped, bad.len() as u64);
}

#[test]
fn update_skips_timestamps_that_do_not_move_forward_without_touching_state() {
    let (t, r) = stream(200);
    let mut a = Pipeline::new(config(NonFinite::Error)).unwrap();
    let mut b = a.clone();
    for i in 0..t.len() {
        let oa = a.update(t[i], r[i]);
        let ob = b.update(t[i], r[i]);
        assert!(same(&oa, &ob));
        if i % 50 == 10 {
            // A duplicate, a step back and a NaN timestamp: skipped, state untouched.
            for bad_t in [t[i], t[i] - 1.0, f64::NAN] {
                let o = b.update(bad_t, 5.0);
                assert!(o.rate.is_nan() && o.heading.to_bits() == oa.heading.to_bits());
            }
        }
    }
    assert_eq!(b.report().skipped, 12);
    // NaN reading through `update` under the Error policy (update cannot fail): skipped.
    assert!(b.update(1e9, f64::NAN).rate.is_nan());
}

#[test]
fn gaps_are_counted_and_reset_restarts_hdr_only() {
    let mut t: Vec<f64> = (0..400).map(|i| i as f64 * 0.1).collect();
    t.extend((0..400).map(|i| 100.0 + i as f64 * 0.1));
    let r = vec![0.004; t.len()]; // a drift HDR works on (below the turn and dead-band thresholds)
    for (action, expect_reset) in [(GapAction::Bridge, false), (GapAction::Reset, true)] {
        let mut c = Preset::Hdr.config();
        c.input.gap_action = action;
        let mut p = Pipeline::new(c).unwrap();
        let out = block(&mut p, &t, &r).unwrap();
        assert_eq!(p.report().gaps, 1);
        assert!((p.report().longest_gap - 60.1).abs() < 1e-9);
        let before = out[399];
        let after = out[400];
        assert!(before.drift != 0.0);
        assert_eq!(after.drift == 0.0, expect_reset, "{action:?}");
        // The heading carries on across the gap either way (bridged by the integration rule).
        assert!(after.heading >= before.heading);
    }
    let mut c = Preset::Hdr.config();
    c.input.gap_limit = 0.0;
    assert!(matches!(
        Pipeline::new(c),
        Err(Error::InvalidParameter {
            name: "gap_limit",
            ..
        })
    ));
}

/// An interval of exactly the gap limit is not a gap, one just over it is, and a gap between two
/// blocks counts as one: in one block, in blocks cut at the gap, and sample by sample alike.
#[test]
fn gaps_are_counted_at_the_limit_and_between_blocks() {
    // Quarter-second steps, so that every interval is exact: 2.0 (the limit), 2.25 and 7.0.
    let mut t = vec![0.0];
    for (k, step) in (1..3000).map(|k| (k, 0.25)) {
        let extra = match k {
            1000 => 1.75,
            2000 => 2.0,
            2500 => 6.75,
            _ => 0.0,
        };
        t.push(t[k - 1] + step + extra);
    }
    let r: Vec<f64> = (0..t.len()).map(|i| 0.01 * ((i % 7) as f64)).collect();
    for gap_action in [GapAction::Bridge, GapAction::Reset] {
        let mut c = Preset::Combined.config();
        c.input.gap_action = gap_action;
        let mut a = Pipeline::new(c).unwrap();
        let updates: Vec<Output> = t.iter().zip(&r).map(|(&x, &y)| a.update(x, y)).collect();
        assert_eq!((a.report().gaps, a.report().longest_gap), (2, 7.0));
        for cut in [t.len(), 2000, 2500] {
            let mut b = Pipeline::new(c).unwrap();
            let mut out = block(&mut b, &t[..cut], &r[..cut]).unwrap();
            out.extend(block(&mut b, &t[cut..], &r[cut..]).unwrap());
            assert_eq!(b.report(), a.report(), "{gap_action:?}, cut at {cut}");
            assert_eq!(common::bits(&out), common::bits(&updates), "{gap_action:?}");
        }
    }
}

/// Long blocks with gaps and bad readings here and there, some next to each other: the block
/// equals repeated `update` for every preset and policy, whole and cut in two.
#[test]
fn long_blocks_with_gaps_and_bad_readings_equal_updates() {
    let (mut t, clean) = stream(13_000);
    for &k in &[4095, 4096, 4097, 8191, 12_288] {
        for x in &mut t[k..] {
            *x += 5.0; // beyond the 2 s gap limit
        }
    }
    let mut faulty = clean.clone();
    for &k in &[1, 4094, 4096, 8192, 8193, 12_999] {
        faulty[k] = f64::NAN;
    }
    for preset in Preset::ALL {
        for (r, policies) in [
            (&clean, &[NonFinite::Error][..]),
            (&faulty, &[NonFinite::Hold, NonFinite::Skip][..]),
        ] {
            for &non_finite in policies {
                for gap_action in [GapAction::Bridge, GapAction::Reset] {
                    let mut c = preset.config();
                    c.correction.bias = StaticBias::Fixed(0.01);
                    c.input.non_finite = non_finite;
                    c.input.gap_action = gap_action;
                    let mut a = Pipeline::new(c).unwrap();
                    let updates: Vec<Output> =
                        t.iter().zip(r).map(|(&x, &y)| a.update(x, y)).collect();
                    let mut b = Pipeline::new(c).unwrap();
                    let mut blocks = block(&mut b, &t[..6000], &r[..6000]).unwrap();
                    blocks.extend(block(&mut b, &t[6000..], &r[6000..]).unwrap());
                    let mut whole = Pipeline::new(c).unwrap();
                    let one = block(&mut whole, &t, r).unwrap();
                    let what = format!("{preset:?} {non_finite:?} {gap_action:?}");
                    assert_eq!(common::bits(&blocks), common::bits(&updates), "{what}");
                    assert_eq!(common::bits(&one), common::bits(&updates), "{what}");
                    assert_eq!(b.report(), a.report(), "{what}");
                    assert_eq!(b, a, "{what}");
                }
            }
        }
    }
}
