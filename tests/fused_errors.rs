//! The pipeline with heading fixes (rust/src/fused.rs) given a bad fix or sample: an error that
//! names it, nothing changed, and a run carried on after it as one run without it.

mod fused_drive;

use fused_drive::{bits, block, chunked, columns, config, drive, fixes, Columns};
// what a caller of FusedPipeline matches and reads, from the crate's root
use gyrocore::{Estimate, Fix, FixProblem, FusedPipeline, FusionError};

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
    let estimate: Estimate = fused.fusion().estimate();
    assert_eq!(estimate, snapshot.fusion().estimate());

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

/// Both error types are `core::error::Error` with or without the `std` feature, so that a
/// `no_std` embedder's `?` takes them alike (`cargo test --no-default-features --test
/// fused_errors`); a fix's extreme value prints in exponent form, as the core error's do.
#[test]
fn a_fusion_error_is_an_error_without_std_and_prints_extreme_values_short() {
    fn as_error<E: core::error::Error + 'static>(e: E) -> Box<dyn core::error::Error> {
        Box::new(e)
    }
    let e = FusionError::Fix {
        index: 2,
        what: "heading",
        value: 1e300,
        problem: FixProblem::OutOfRange,
    };
    let text = as_error(e).to_string();
    assert_eq!(
        text,
        "fix 2: heading = 1e300 is beyond +-2^20 rad; check the unit (radians)"
    );
    assert!(as_error(gyrocore::Error::MissingTemperature)
        .to_string()
        .contains("temperature"));
}
