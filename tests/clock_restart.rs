//! A clock that jumps back (a time sync, a sensor's counter restarted, a log stitched from two
//! sessions): refused in words that name `restart_clock()`, after which the stream goes on from
//! the next sample on a new time base with everything it had learned, integrating nothing
//! across the jump.

mod common;

use common::{bits, try_block};
use gyrocore::*;

/// `n` samples at 128 Hz from `t0` (whole seconds: every time and interval exact), a turn whose
/// rate passes through the bias (0.01 rad/s) at the first and the last sample: there the
/// corrected rate is 0.
fn drive(t0: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
    let t = (0..n).map(|i| t0 + i as f64 / 128.0).collect();
    let mut r: Vec<f64> = (0..n)
        .map(|i| 0.01 + 0.2 * (core::f64::consts::PI * i as f64 / (n - 1) as f64).sin())
        .collect();
    (r[0], r[n - 1]) = (0.01, 0.01); // sin(pi) is not 0 in floats
    (t, r)
}

/// A fix of heading 0 at `t`, of sigma 0.05 rad.
fn fix_at(t: f64) -> Fix {
    Fix {
        t,
        heading: 0.0,
        sigma: 0.05,
    }
}

fn fixed_bias(preset: Preset) -> PipelineConfig {
    let mut c = preset.config();
    c.correction.bias = StaticBias::Fixed(0.01);
    c
}

#[test]
fn a_step_back_names_the_way_on_and_a_duplicate_does_not() {
    let mut p = Pipeline::new(fixed_bias(Preset::Hdr)).unwrap();
    let (t, r) = drive(100.0, 50);
    try_block(&mut p, &t, &r).unwrap();
    let before = p.clone();
    let e = try_block(&mut p, &[50.0, 50.01], &[0.0, 0.0]).unwrap_err();
    assert_eq!(
        e,
        Error::ClockStepsBack {
            index: 0,
            previous: 100.0 + 49.0 / 128.0,
            value: 50.0
        }
    );
    let words = e.to_string();
    assert!(
        words.contains("(sort the log and drop duplicate timestamps)"),
        "{words}"
    );
    assert!(words.contains("call restart_clock()"), "{words}");
    assert_eq!(p, before, "a refused block changes nothing");
    // within a block too, its index named
    let e = try_block(&mut p, &[101.0, 102.0, 60.0], &[0.0; 3]).unwrap_err();
    assert!(matches!(e, Error::ClockStepsBack { index: 2, .. }), "{e:?}");
    // a duplicate is no jump of the clock
    let e = try_block(&mut p, &[t[49]], &[0.0]).unwrap_err();
    assert!(matches!(e, Error::NotIncreasing { index: 0, .. }), "{e:?}");
    assert!(!e.to_string().contains("restart_clock"));
}

/// A whole series (a log, a file) given to a stream is reported as a series: its step back is
/// [`Error::NotIncreasing`], in the words a stream's error begins with, without `restart_clock()`.
#[test]
fn a_step_back_of_a_whole_series_is_reported_without_the_streams_way_on() {
    let mut p = Pipeline::new(fixed_bias(Preset::Hdr)).unwrap();
    let e = try_block(&mut p, &[1.0, 2.0, 1.5], &[0.0; 3]).unwrap_err();
    let series = e.of_series();
    assert_eq!(
        series,
        Error::NotIncreasing {
            index: 2,
            previous: 2.0,
            value: 1.5
        }
    );
    let (stream, log) = (e.to_string(), series.to_string());
    assert_eq!(
        log,
        "timestamps must strictly increase: t[2] = 1.5 follows 2 (sort the log and drop \
         duplicate timestamps)"
    );
    assert!(
        stream.starts_with(&log) && stream.len() > log.len(),
        "{stream}"
    );
    assert!(
        stream[log.len()..].starts_with("; where the clock jumped back"),
        "{stream}"
    );
    let duplicate = Error::NotIncreasing {
        index: 1,
        previous: 2.0,
        value: 2.0,
    };
    assert_eq!(
        duplicate.of_series(),
        duplicate,
        "any other error is itself"
    );
}

/// After `restart_clock` the outputs are those of a run whose second part follows a gap instead
/// of the jump, where nothing turned across the gap (the corrected rate 0 at both its ends: the
/// gap then adds nothing to the heading), under either gap action.
#[test]
fn a_restart_runs_as_a_gap_the_vehicle_stood_still_in() {
    for action in [GapAction::Bridge, GapAction::Reset] {
        let mut c = fixed_bias(Preset::StaticBias);
        c.input.gap_action = action;
        let (ta, ra) = drive(100.0, 300);
        let (tb, rb) = drive(20.0, 300);
        let mut jumped = Pipeline::new(c).unwrap();
        try_block(&mut jumped, &ta, &ra).unwrap();
        jumped.restart_clock().unwrap();
        let after_jump = try_block(&mut jumped, &tb, &rb).unwrap();

        let mut gap = Pipeline::new(c).unwrap();
        try_block(&mut gap, &ta, &ra).unwrap();
        let shifted: Vec<f64> = tb.iter().map(|t| t + 1000.0).collect();
        let after_gap = try_block(&mut gap, &shifted, &rb).unwrap();
        assert_eq!(bits(&after_jump), bits(&after_gap), "{action:?}");
        assert_eq!(gap.report().gaps, 1);
        assert_eq!(jumped.report().gaps, 0, "a jump is no gap");
        assert_eq!(jumped.clock_restarts(), 1);
        assert_eq!(jumped.last_time(), Some(tb[299]));
    }
}

#[test]
fn a_restart_keeps_the_heading_the_bias_and_every_estimate() {
    let mut c = Preset::Tracked.config();
    c.correction.bias = StaticBias::Fixed(0.0);
    c.input.gap_action = GapAction::Bridge;
    let mut p = Pipeline::new(c).unwrap();
    // at rest for 40 s on a bias of 0.004 rad/s, then a turn that HDR corrects
    let n = 6000;
    let t: Vec<f64> = (0..n).map(|i| 500.0 + i as f64 * 0.01).collect();
    let r: Vec<f64> = (0..n)
        .map(|i| 0.004 + if i < 4000 { 0.0 } else { 0.001 })
        .collect();
    let speed: Vec<f64> = (0..n).map(|i| if i < 4000 { 0.0 } else { 5.0 }).collect();
    let before = common::try_block_with_speed(&mut p, &t, &r, Some(&speed)).unwrap();
    let last = before[n - 1];
    assert_ne!(last.drift, 0.0, "HDR corrects the turn's bias");
    let tracker = *p.rest_tracker().unwrap();
    assert!(tracker.rests_found() > 0);
    p.restart_clock().unwrap();
    let first = p.update(3.0, 0.004 + 0.001);
    assert_eq!(
        first.heading, last.heading,
        "nothing integrated across the jump"
    );
    assert_eq!(
        first.drift.to_bits(),
        last.drift.to_bits(),
        "HDR's correction kept"
    );
    let now = p.rest_tracker().unwrap();
    assert_eq!(now.bias(), tracker.bias());
    assert_eq!(now.rests_found(), tracker.rests_found());
    // the next interval is the new clock's
    let next = p.update(3.01, 0.1 + 0.004);
    assert!(next.heading > first.heading && next.heading < first.heading + 0.01);
}

#[test]
fn chunks_and_single_samples_after_a_restart_give_the_same_outputs() {
    let c = fixed_bias(Preset::Combined);
    let (ta, ra) = drive(100.0, 400);
    let (tb, rb) = drive(-5.0, 400);
    let mut whole = Pipeline::new(c).unwrap();
    try_block(&mut whole, &ta, &ra).unwrap();
    let mut chunked = whole.clone();
    let mut single = whole.clone();
    whole.restart_clock().unwrap();
    let expected = try_block(&mut whole, &tb, &rb).unwrap();
    chunked.restart_clock().unwrap();
    let mut got = Vec::new();
    for (t, r) in tb.chunks(7).zip(rb.chunks(7)) {
        got.extend(try_block(&mut chunked, t, r).unwrap());
    }
    assert_eq!(bits(&got), bits(&expected));
    single.restart_clock().unwrap();
    let one: Vec<Output> = tb
        .iter()
        .zip(&rb)
        .map(|(&t, &r)| single.update(t, r))
        .collect();
    assert_eq!(bits(&one), bits(&expected));
    assert_eq!(chunked, whole);
}

#[test]
fn update_skips_a_step_back_until_the_clock_is_restarted() {
    let mut p = Pipeline::new(fixed_bias(Preset::Raw)).unwrap();
    let (t, r) = drive(100.0, 20);
    for (&t, &r) in t.iter().zip(&r) {
        p.update(t, r);
    }
    assert!(p.update(1.0, 0.5).rate.is_nan());
    assert_eq!(p.report().skipped, 1);
    p.restart_clock().unwrap();
    assert!(!p.update(1.0, 0.5).rate.is_nan());
    assert!(
        p.update(1.0, 0.5).rate.is_nan(),
        "the new clock must increase"
    );
}

#[test]
fn a_restart_within_the_rest_window_is_refused_and_changes_nothing() {
    let mut p = Pipeline::new(common::with_window(Preset::StaticBias, 0.0, 1.0)).unwrap();
    p.restart_clock().unwrap(); // before the first sample: nothing to restart
    let (t, r) = drive(0.0, 50);
    try_block(&mut p, &t, &r).unwrap();
    let before = p.clone();
    let e = p.restart_clock().unwrap_err();
    assert_eq!(
        e,
        Error::ClockRestartInWindow {
            start: 0.0,
            end: 1.0
        }
    );
    assert!(e.to_string().contains("once the window is over"));
    assert_eq!(p, before);
    let (t, r) = drive(0.5, 100);
    try_block(&mut p, &t, &r).unwrap();
    assert!(!p.bias_learning());
    p.restart_clock().unwrap();
}

/// The fused pipeline over a block with `fixes`: its heading, and how many fixes it used.
fn fused_block(f: &mut FusedPipeline, t: &[f64], r: &[f64], fixes: &[Fix]) -> (Vec<f64>, usize) {
    let (mut heading, mut rate) = (vec![0.0; t.len()], vec![0.0; t.len()]);
    let out = common::heading_and_rate(&mut heading, &mut rate);
    let used = f.process_block(Samples::new(t, r), fixes, out).unwrap();
    (heading, used)
}

/// Fixes on the new clock: accepted even before the last fix on the old one, and the filter's
/// estimate carried across the jump.
#[test]
fn a_fused_pipeline_restarts_both_clocks() {
    let mut f = FusedPipeline::new(fixed_bias(Preset::Hdr), FusionConfig::default()).unwrap();
    let (t, r) = drive(100.0, 500);
    let fixes: Vec<Fix> = (0..4).map(|s| fix_at(100.0 + s as f64)).collect();
    assert_eq!(fused_block(&mut f, &t, &r, &fixes).1, 4);
    let estimate = f.fusion().estimate();
    let reached = f.counts().applied + f.counts().rejected;
    f.restart_clock().unwrap();
    let (tb, rb) = drive(10.0, 200);
    let new = [fix_at(9.5), fix_at(10.5)];
    let (hb, used) = fused_block(&mut f, &tb, &rb, &new);
    assert_eq!(used, 2);
    assert_eq!(
        hb[0], estimate.heading,
        "the estimate crosses the jump unchanged"
    );
    let counts = f.counts();
    assert_eq!(counts.applied + counts.rejected, reached + 1);
    assert_eq!(
        f.counts().before_start,
        1,
        "the fix before the new clock's first sample"
    );
}

#[cfg(feature = "serde")]
#[test]
fn a_restart_survives_a_snapshot_before_and_after_the_next_sample() {
    let c = common::with_window(Preset::StaticBias, 100.0, 101.0);
    let (ta, ra) = drive(100.0, 300);
    let (tb, rb) = drive(50.0, 300);
    let mut p = Pipeline::new(c).unwrap();
    try_block(&mut p, &ta, &ra).unwrap();
    p.restart_clock().unwrap();
    let json = serde_json::to_string(&p).unwrap();
    let mut q: Pipeline = serde_json::from_str(&json).unwrap();
    assert_eq!(q, p);
    let expected = try_block(&mut p, &tb, &rb).unwrap();
    assert_eq!(bits(&try_block(&mut q, &tb, &rb).unwrap()), bits(&expected));
    // after it, its times before the window's end on the old clock
    let json = serde_json::to_string(&p).unwrap();
    let back: Pipeline = serde_json::from_str(&json).unwrap();
    assert_eq!(back, p);
    let bytes = postcard::to_allocvec(&p).unwrap();
    assert_eq!(postcard::from_bytes::<Pipeline>(&bytes).unwrap(), p);
    // a pending restart without one counted is an edited state
    let edited = serde_json::to_string(&q)
        .unwrap()
        .replace("\"clock_restarted\":false", "\"clock_restarted\":true")
        .replace("\"clock_restarts\":1", "\"clock_restarts\":0");
    assert!(serde_json::from_str::<Pipeline>(&edited).is_err());

    let mut f = FusedPipeline::new(fixed_bias(Preset::Raw), FusionConfig::default()).unwrap();
    let (mut h, mut rate) = (vec![0.0; 300], vec![0.0; 300]);
    let out = common::heading_and_rate(&mut h, &mut rate);
    f.process_block(Samples::new(&ta, &ra), &[], out).unwrap();
    f.restart_clock().unwrap();
    let json = serde_json::to_string(&f).unwrap();
    assert_eq!(serde_json::from_str::<FusedPipeline>(&json).unwrap(), f);
}
