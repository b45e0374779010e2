//! The pipeline with heading fixes (rust/src/fused.rs): the same as the pipeline then the filter
//! by hand, bit-identical however samples and fixes are cut or copied (a bad block:
//! tests/fused_errors.rs).

mod fused_drive;

use fused_drive::{bits, block, chunked, columns, config, drive, fixes, Columns};
use gyrocore::{FusedOutputs, FusedPipeline, Fusion, FusionOutputs, Outputs, Pipeline, Samples};

#[test]
fn equals_the_pipeline_then_the_filter() {
    let (t, mut rate) = drive(120.0);
    rate[3000] = f64::NAN; // skipped by the pipeline: out of the filter, its row repeated
    rate[3001] = f64::NAN;
    let all = fixes(&t);
    let (c, f) = config();
    let mut cols = columns(t.len());
    let mut fused = FusedPipeline::new(c, f).unwrap();
    assert_eq!(
        block(&mut fused, &t, &rate, &all, &mut cols, 0).unwrap(),
        all.len()
    );

    let n = t.len();
    let mut pipeline = Pipeline::new(c).unwrap();
    let (mut h, mut r, mut d) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    pipeline
        .process_block(&t, &rate, None, Outputs::all(&mut h, &mut r, &mut d))
        .unwrap();
    assert_eq!(bits(&r), bits(&cols[4]));
    assert_eq!(bits(&d), bits(&cols[5]));
    let kept: Vec<usize> = (0..n).filter(|&k| r[k].is_finite()).collect();
    assert_eq!(kept.len(), n - 2);
    let (tk, rk): (Vec<f64>, Vec<f64>) = kept.iter().map(|&k| (t[k], r[k])).unzip();
    let mut filter = Fusion::new(f).unwrap();
    let mut est: [Vec<f64>; 4] = core::array::from_fn(|_| vec![0.0; kept.len()]);
    let [eh, es, eb, esc] = &mut est;
    let out = FusionOutputs::all(eh, es, eb, esc);
    assert_eq!(
        filter.process_block(&tk, &rk, &all, out).unwrap(),
        all.len()
    );
    for (j, &k) in kept.iter().enumerate() {
        for c in 0..4 {
            assert_eq!(
                cols[c][k].to_bits(),
                est[c][j].to_bits(),
                "column {c}, sample {k}"
            );
        }
    }
    // the skipped rows repeat the row before them
    for col in &cols[..4] {
        assert_eq!(col[3000].to_bits(), col[2999].to_bits());
        assert_eq!(col[3001].to_bits(), col[2999].to_bits());
    }
    assert_eq!(fused.counts(), filter.counts());
    assert_eq!(fused.counts().rejected, 1);
    // the fixes did their work: the filter's heading differs from the pipeline's
    assert!((cols[0][n - 1] - h[n - 1]).abs() > 1e-3);
}

#[test]
fn chunk_invariant_with_fixes_at_block_edges() {
    let (t, rate) = drive(60.0);
    let all = fixes(&t);
    let (whole, whole_state) = chunked(&t, &rate, &all, &[]);
    // cuts right after a fix's sample, right before it, at a fix exactly on a sample (index
    // 700 is 7 s: s % 7 == 0), in the rest window, and blocks of one sample
    let cut_sets: [&[usize]; 5] = [
        &[700, 701, 702, 1500],
        &[100, 101, 199, 200, 201],
        &[1, 2, 3, 499, 500, 501, 2000],
        &(1..60).map(|s| s * 100).collect::<Vec<_>>(),
        &(1..600).map(|s| s * 7 + 1).collect::<Vec<_>>(),
    ];
    for cuts in cut_sets {
        let (cols, state) = chunked(&t, &rate, &all, cuts);
        for c in 0..6 {
            assert_eq!(bits(&cols[c]), bits(&whole[c]), "column {c}, cuts {cuts:?}");
        }
        assert_eq!(state, whole_state);
    }
}

#[test]
fn a_copy_resumes_bit_identically() {
    let (t, rate) = drive(40.0);
    let all = fixes(&t);
    let (whole, _) = chunked(&t, &rate, &all, &[]);
    let (c, f) = config();
    let mut first = FusedPipeline::new(c, f).unwrap();
    let mut cols = columns(t.len());
    let used = block(&mut first, &t[..2345], &rate[..2345], &all, &mut cols, 0).unwrap();
    #[cfg(feature = "serde")]
    let mut resumed: FusedPipeline =
        serde_json::from_str(&serde_json::to_string(&first).unwrap()).unwrap();
    #[cfg(not(feature = "serde"))]
    let mut resumed = first.clone();
    assert_eq!(resumed, first);
    block(
        &mut resumed,
        &t[2345..],
        &rate[2345..],
        &all[used..],
        &mut cols,
        2345,
    )
    .unwrap();
    for c in 0..6 {
        assert_eq!(bits(&cols[c]), bits(&whole[c]), "column {c}");
    }
    // reset returns to the state of a new one
    resumed.reset();
    assert_eq!(resumed, FusedPipeline::new(c, f).unwrap());
}

#[test]
fn without_a_drift_output_and_with_wrong_lengths() {
    let (t, rate) = drive(20.0);
    let all = fixes(&t);
    let (whole, _) = chunked(&t, &rate, &all, &[]);
    let (c, f) = config();
    let mut fused = FusedPipeline::new(c, f).unwrap();
    let n = t.len();
    let mut cols = columns(n);
    let [h, s, b, sc, r, _] = &mut cols;
    let mut short = vec![0.0; n - 1];
    let out = FusedOutputs {
        heading: h,
        heading_sigma: Some(s),
        bias: Some(&mut short),
        scale: Some(sc),
        rate: r,
        drift: None,
    };
    let e = fused
        .process_block(Samples::new(&t, &rate), &all, out)
        .unwrap_err();
    assert!(e.to_string().contains("bias"), "{e}");
    assert_eq!(fused, FusedPipeline::new(c, f).unwrap());
    let out = FusedOutputs {
        heading: h,
        heading_sigma: Some(s),
        bias: Some(b),
        scale: Some(sc),
        rate: r,
        drift: None,
    };
    fused
        .process_block(Samples::new(&t, &rate), &all, out)
        .unwrap();
    for c in 0..5 {
        assert_eq!(bits(&cols[c]), bits(&whole[c]), "column {c}");
    }
}

#[test]
fn estimates_not_asked_for_are_left_alone_and_change_nothing() {
    let (t, mut rate) = drive(40.0);
    rate[1234] = f64::NAN; // skipped: every estimate asked for repeats the row before it
    let all = fixes(&t);
    let (whole, whole_state) = chunked(&t, &rate, &all, &[]);
    let (c, f) = config();
    let n = t.len();
    // each subset of (heading sigma, bias, scale), in two blocks cut between fixes
    for wanted in 0..8u8 {
        let on = |bit: u8| wanted & (1 << bit) != 0;
        let mut fused = FusedPipeline::new(c, f).unwrap();
        // columns not asked for keep the marker they start with
        let mut cols: Columns = core::array::from_fn(|_| vec![-7.0; n]);
        let mut pending = 0;
        for (start, end) in [(0, 1550), (1550, n)] {
            let [h, s, b, sc, r, _] = &mut cols;
            let out = FusedOutputs {
                heading: &mut h[start..end],
                heading_sigma: on(0).then_some(&mut s[start..end]),
                bias: on(1).then_some(&mut b[start..end]),
                scale: on(2).then_some(&mut sc[start..end]),
                rate: &mut r[start..end],
                drift: None,
            };
            let samples = Samples::new(&t[start..end], &rate[start..end]);
            pending += fused.process_block(samples, &all[pending..], out).unwrap();
        }
        assert_eq!(pending, all.len());
        assert_eq!(fused, whole_state, "outputs {wanted:03b}");
        for (col, asked) in [(0, true), (1, on(0)), (2, on(1)), (3, on(2)), (4, true)] {
            if asked {
                assert_eq!(bits(&cols[col]), bits(&whole[col]), "column {col}");
                if col < 4 {
                    assert_eq!(cols[col][1234].to_bits(), cols[col][1233].to_bits());
                }
            } else {
                assert!(cols[col].iter().all(|&v| v == -7.0), "column {col} written");
            }
        }
    }

    // the filter alone: the heading by itself is the heading of all four
    let (tk, rk): (Vec<f64>, Vec<f64>) = (0..n)
        .filter(|&k| rate[k].is_finite())
        .map(|k| (t[k], rate[k]))
        .unzip();
    let m = tk.len();
    let mut four: [Vec<f64>; 4] = core::array::from_fn(|_| vec![0.0; m]);
    let [h, s, b, sc] = &mut four;
    let mut full = Fusion::new(f).unwrap();
    full.process_block(&tk, &rk, &all, FusionOutputs::all(h, s, b, sc))
        .unwrap();
    let mut alone = vec![0.0; m];
    let mut lean = Fusion::new(f).unwrap();
    lean.process_block(&tk, &rk, &all, FusionOutputs::heading(&mut alone))
        .unwrap();
    assert_eq!(bits(&alone), bits(&four[0]));
    assert_eq!(lean, full);
    // an estimate asked for with the wrong length is named, and nothing moved
    let mut short = vec![0.0; m - 1];
    let out = FusionOutputs {
        scale: Some(&mut short),
        ..FusionOutputs::heading(&mut alone)
    };
    let e = Fusion::new(f)
        .unwrap()
        .process_block(&tk, &rk, &all, out)
        .unwrap_err();
    assert!(e.to_string().contains("scale"), "{e}");
}

#[test]
fn samples_skipped_before_the_first_one_taken_hold_the_prior() {
    let (t, mut rate) = drive(10.0);
    rate[0] = f64::NAN;
    rate[1] = f64::NAN;
    let all = fixes(&t);
    let (c, f) = config();
    let mut fused = FusedPipeline::new(c, f).unwrap();
    let mut cols = columns(t.len());
    block(&mut fused, &t, &rate, &all, &mut cols, 0).unwrap();
    let prior = [
        f.initial_heading,
        f.initial_heading_sigma,
        f.initial_bias,
        0.0,
    ];
    for k in 0..2 {
        let row: Vec<f64> = cols[..4].iter().map(|col| col[k]).collect();
        assert_eq!(bits(&row), bits(&prior), "row {k}");
    }
    // the samples taken after them reach the fixes
    assert!(cols[1][t.len() - 1] < 0.1, "{}", cols[1][t.len() - 1]);
}

/// A filter read back is checked as `Fusion::new` checks its configuration, alone and inside a
/// fused pipeline: a gate of -1 edited into a stored state rejected every fix without a word.
#[cfg(feature = "serde")]
#[test]
fn a_filter_read_back_is_checked_as_new_checks_it() {
    let (c, f) = config();
    let fused = FusedPipeline::new(c, f).unwrap();
    let json = serde_json::to_string(&fused).unwrap();
    let gate = format!("\"gate\":{}", f.gate);
    assert!(json.contains(&gate));
    let e = serde_json::from_str::<FusedPipeline>(&json.replace(&gate, "\"gate\":-1.0"));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("invalid parameter gate = -1"));
    let alone = serde_json::to_string(fused.fusion()).unwrap();
    let e = serde_json::from_str::<Fusion>(&alone.replace("\"arw\":", "\"arw\":-1.0,\"x\":"));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("invalid parameter arw = -1"));
    assert_eq!(
        serde_json::from_str::<Fusion>(&alone).unwrap(),
        *fused.fusion()
    );
}
