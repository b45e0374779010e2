//! The pipeline with heading fixes (rust/src/fused.rs): the same as the pipeline then the filter
//! by hand, bit-identical however samples and fixes are cut, unchanged by a bad block.

use gyrocore::fixes::FixProblem;
use gyrocore::{
    Fix, FusedOutputs, FusedPipeline, Fusion, FusionConfig, FusionError, FusionOutputs, NonFinite,
    Outputs, Pipeline, PipelineConfig, Preset, Samples, StaticBias,
};

/// The true yaw rate at `t` of the drives below: 5 s at rest, then turning both ways.
fn true_rate(t: f64) -> f64 {
    let s = t - 105.0;
    if s > 0.0 {
        0.3 * (0.05 * s).sin() + 0.2 * (0.13 * s).cos() - 0.2
    } else {
        0.0
    }
}

/// A 100 Hz drive of `seconds` from t = 100 s: (t, gyro reading with a bias, a scale error and
/// a deterministic wiggle for noise).
fn drive(seconds: f64) -> (Vec<f64>, Vec<f64>) {
    let n = (seconds * 100.0) as usize;
    let t: Vec<f64> = (0..n).map(|k| 100.0 + k as f64 * 0.01).collect();
    let rate = t
        .iter()
        .enumerate()
        .map(|(k, &t)| 1.02 * true_rate(t) + 0.01 + 1e-3 * ((k as f64) * 1.7).sin())
        .collect();
    (t, rate)
}

/// Fixes of the true heading (from 0.5 rad) every second, half a sample after one (exactly at
/// one every seventh second), with one outlier in the middle.
fn fixes(t: &[f64]) -> Vec<Fix> {
    let mut heading = vec![0.5; t.len()];
    for k in 1..t.len() {
        let dt = t[k] - t[k - 1];
        heading[k] = heading[k - 1] + 0.5 * dt * (true_rate(t[k - 1]) + true_rate(t[k]));
    }
    let mut f: Vec<Fix> = (1..(t.len() / 100))
        .map(|s| Fix {
            t: t[s * 100] + if s % 7 == 0 { 0.0 } else { 0.005 },
            heading: heading[s * 100],
            sigma: 0.02,
        })
        .collect();
    let middle = f.len() / 2;
    f[middle].heading += 3.0; // rejected by the gate
    f
}

fn config() -> (PipelineConfig, FusionConfig) {
    let mut c = Preset::Hdr.config();
    c.correction.bias = StaticBias::Leading { duration: 5.0 };
    c.input.non_finite = NonFinite::Skip;
    let f = FusionConfig {
        initial_heading: 0.5,
        ..FusionConfig::default()
    };
    (c, f)
}

/// Heading, heading sigma, bias, scale, rate and drift per sample.
type Columns = [Vec<f64>; 6];

fn columns(n: usize) -> Columns {
    core::array::from_fn(|_| vec![0.0; n])
}

/// Runs `fused` over one block, writing into `cols[from..]`.
fn block(
    fused: &mut FusedPipeline,
    t: &[f64],
    rate: &[f64],
    fixes: &[Fix],
    cols: &mut Columns,
    from: usize,
) -> Result<usize, FusionError> {
    let n = t.len();
    let [h, s, b, sc, r, d] = cols;
    let out = FusedOutputs {
        heading: &mut h[from..from + n],
        heading_sigma: Some(&mut s[from..from + n]),
        bias: Some(&mut b[from..from + n]),
        scale: Some(&mut sc[from..from + n]),
        rate: &mut r[from..from + n],
        drift: Some(&mut d[from..from + n]),
    };
    fused.process_block(Samples::new(t, rate), fixes, out)
}

/// The whole drive cut at `cuts` (sample indices), each block with the fixes up to its end and
/// the ones left over from before.
fn chunked(t: &[f64], rate: &[f64], all: &[Fix], cuts: &[usize]) -> (Columns, FusedPipeline) {
    let (c, f) = config();
    let mut fused = FusedPipeline::new(c, f).unwrap();
    let mut cols = columns(t.len());
    let (mut start, mut given, mut pending) = (0, 0, 0);
    for &end in cuts.iter().chain([&t.len()]) {
        // hand over the fixes up to the block's last sample, plus one more past it when there is
        let last = t[end - 1];
        let upto = all.partition_point(|f| f.t <= last);
        let upto = (upto + 1).min(all.len()).max(given);
        let used = block(
            &mut fused,
            &t[start..end],
            &rate[start..end],
            &all[pending..upto],
            &mut cols,
            start,
        )
        .unwrap();
        pending += used;
        given = upto;
        start = end;
    }
    (cols, fused)
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Runs the block `(t, rate)` (written from sample `from`) with its sample `bad`'s time
/// repeating the one before: it must fail naming that sample by its index in the block, and leave
/// `fused` as it was.
fn fails_on_sample(
    fused: &mut FusedPipeline,
    (t, rate): (&[f64], &[f64]),
    fixes: &[Fix],
    cols: &mut Columns,
    (from, bad): (usize, usize),
) {
    let before = fused.clone();
    let mut bad_t = t.to_vec();
    bad_t[bad] = bad_t[bad - 1];
    match block(fused, &bad_t, rate, fixes, cols, from).unwrap_err() {
        FusionError::Gyro(g) => assert_eq!(g.index(), Some(bad), "{g}"),
        other => panic!("expected a sample error, got {other:?}"),
    }
    assert_eq!(*fused, before, "sample {bad}");
}

/// Runs the block of 10-20 s with `fixes`: it must fail on fix `index`'s field `what` with
/// `problem`, and leave `fused` as it was.
fn fails_on_fix(
    fused: &mut FusedPipeline,
    (t, rate): (&[f64], &[f64]),
    fixes: &[Fix],
    cols: &mut Columns,
    (index, what, problem): (usize, &str, FixProblem),
) {
    let before = fused.clone();
    let e = block(fused, &t[1000..2000], &rate[1000..2000], fixes, cols, 1000).unwrap_err();
    match e {
        FusionError::Fix {
            index: i,
            what: w,
            problem: p,
            ..
        } => assert_eq!((i, w, p), (index, what, problem), "{e:?}"),
        other => panic!("expected a fix error, got {other:?}"),
    }
    assert_eq!(*fused, before);
}

/// Runs the rest of the drive from sample `from` (the fixes from `used` on) after errors that
/// changed nothing: every column must be what one uninterrupted run writes.
fn carries_on_as_one_run(
    fused: &mut FusedPipeline,
    (t, rate): (&[f64], &[f64]),
    all: &[Fix],
    used: usize,
    cols: &mut Columns,
    from: usize,
) {
    let rest = block(fused, &t[from..], &rate[from..], &all[used..], cols, from).unwrap();
    assert_eq!(used + rest, all.len());
    let (whole, _) = chunked(t, rate, all, &[]);
    for c in 0..6 {
        assert_eq!(bits(&cols[c]), bits(&whole[c]), "column {c}");
    }
}

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
fn a_bad_fix_or_sample_changes_nothing_and_is_named() {
    let (t, rate) = drive(30.0);
    let all = fixes(&t);
    let (c, f) = config();
    let mut fused = FusedPipeline::new(c, f).unwrap();
    let mut cols = columns(t.len());
    let used = block(
        &mut fused,
        &t[..1000],
        &rate[..1000],
        &all[..12],
        &mut cols,
        0,
    )
    .unwrap();
    assert_eq!(used, 9); // fixes 1..9 s lie within the first 10 s
    let snapshot = fused.clone();

    let mut bad = all[used..].to_vec();
    bad[2].sigma = 0.0;
    let sigma = (2, "sigma", FixProblem::NotPositive);
    fails_on_fix(&mut fused, (&t, &rate), &bad, &mut cols, sigma);

    let block_of = (&t[1000..2000], &rate[1000..2000]);
    fails_on_sample(&mut fused, block_of, &all[used..], &mut cols, (1000, 500));
    assert_eq!(fused, snapshot);

    // carrying on after both errors gives what an uninterrupted run gives
    carries_on_as_one_run(&mut fused, (&t, &rate), &all, used, &mut cols, 1000);
}

#[test]
fn a_bad_sample_deep_in_a_long_block_changes_nothing_and_is_named() {
    // An error anywhere in a long block, early or late, undoes the whole block.
    let (t, rate) = drive(60.0);
    let all = fixes(&t);
    let (c, f) = config();
    let mut fused = FusedPipeline::new(c, f).unwrap();
    let mut cols = columns(t.len());
    let used = block(&mut fused, &t[..500], &rate[..500], &all, &mut cols, 0).unwrap();
    for bad in [1023, 1024, 2500, 5499] {
        let block_of = (&t[500..6000], &rate[500..6000]);
        fails_on_sample(&mut fused, block_of, &all[used..], &mut cols, (500, bad));
    }
    carries_on_as_one_run(&mut fused, (&t, &rate), &all, used, &mut cols, 500);
}

#[test]
fn every_waiting_fix_may_ride_along_and_a_bad_one_fails_the_block_that_reaches_it() {
    // A caller may hand over every fix still to come with each block, here one sample a block:
    // one call's result, bit for bit. A block checks the fixes it reaches (and the first past
    // it), so that such a caller pays per block for those, not for all that wait.
    let (t, rate) = drive(30.0);
    let all = fixes(&t);
    let (whole, whole_state) = chunked(&t, &rate, &all, &[]);
    let (c, f) = config();
    let mut fused = FusedPipeline::new(c, f).unwrap();
    let mut cols = columns(t.len());
    let mut used = 0;
    for i in 0..t.len() {
        let one = i..i + 1;
        used += block(
            &mut fused,
            &t[one.clone()],
            &rate[one],
            &all[used..],
            &mut cols,
            i,
        )
        .unwrap();
    }
    assert_eq!(used, all.len());
    for c in 0..6 {
        assert_eq!(bits(&cols[c]), bits(&whole[c]), "column {c}");
    }
    assert_eq!(fused, whole_state);

    // a bad fix at 16 s rides along unread with the first 10 s, and fails the block that reaches it
    let mut bad = all.clone();
    bad[15].heading = f64::NAN;
    let mut fused = FusedPipeline::new(c, f).unwrap();
    let used = block(&mut fused, &t[..1000], &rate[..1000], &bad, &mut cols, 0).unwrap();
    assert_eq!(used, 9);
    let heading = (6, "heading", FixProblem::NonFinite);
    fails_on_fix(&mut fused, (&t, &rate), &bad[used..], &mut cols, heading);
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
