//! The gate's lock-out and the re-admission that ends it (`FusionConfig::readmit_after`,
//! rust/src/fixes.rs): a filter surer of itself than the fixes allow rejects every fix after it;
//! after `readmit_after` seconds of rejections the next fix within `READMIT_REACH` gate radii is
//! taken in again, while a lasting wrong course far beyond the gate stays rejected.

mod fix_drive;

use fix_drive::{config, drive, fixes, run, Run, BIAS};
use gyrocore::fixes::wrap_angle;
use gyrocore::{Fix, FixCounts, Fusion, FusionConfig, FusionOutputs};
use std::ops::Range;

/// The largest heading error \[deg\] at or after `from` \[s\].
fn worst_after(t: &[f64], heading: &[f64], psi: &[f64], from: f64) -> f64 {
    let errors = (0..t.len()).filter(|&k| t[k] >= from);
    let worst = errors.map(|k| wrap_angle(heading[k] - psi[k]).abs());
    worst.fold(0.0, f64::max).to_degrees()
}

/// A filter over the whole drive in one call: its estimates and its counts.
fn whole(config: FusionConfig, t: &[f64], rate: &[f64], fixes: &[Fix]) -> (Run, FixCounts) {
    let mut f = Fusion::new(config).unwrap();
    let (r, used) = run(&mut f, t, rate, fixes).unwrap();
    assert_eq!(used, fixes.len());
    (r, f.counts())
}

/// Sure of a bias of 0 (its sigma 5e-4 rad/s) where the gyro reads 0.01 rad/s (0.57 deg/s) at
/// rest, with honest 1 deg fixes a second: the heading runs away from the fixes between two of
/// them faster than the filter allows.
fn sure_of_a_wrong_bias() -> FusionConfig {
    FusionConfig {
        initial_bias_sigma: 5e-4,
        ..config()
    }
}

#[test]
fn a_filter_sure_of_a_wrong_bias_takes_the_fixes_in_again() {
    let (t, psi, rate) = drive(300.0);
    let fx = fixes(&t, &psi, 100, (0.0, 0.0));
    let never = FusionConfig {
        readmit_after: f64::INFINITY,
        ..sure_of_a_wrong_bias()
    };
    let (locked, counts) = whole(never, &t, &rate, &fx);
    assert!(counts.rejected > 200, "{counts:?}");
    assert_eq!(counts.readmitted, 0);
    let off = worst_after(&t, &locked.heading, &psi, 240.0);
    assert!(off > 30.0, "locked out: {off} deg");

    let (r, counts) = whole(sure_of_a_wrong_bias(), &t, &rate, &fx);
    assert!(counts.readmitted >= 1, "{counts:?}");
    assert!(counts.rejected < 50, "{counts:?}");
    let off = worst_after(&t, &r.heading, &psi, 240.0);
    assert!(off < 1.0, "re-admitted: {off} deg");
    let last = t.len() - 1;
    assert!((r.bias[last] - BIAS).abs() < 1e-3, "bias {}", r.bias[last]);
}

/// Honest fixes a second, then from 100 s on every fix `offset` \[deg\] off the true heading.
fn offset_from_100_s(t: &[f64], psi: &[f64], offset: f64) -> Vec<Fix> {
    let mut fx = fixes(t, psi, 100, (0.0, 0.0));
    for f in fx.iter_mut().filter(|f| f.t >= 100.0) {
        f.heading = wrap_angle(f.heading + offset.to_radians());
    }
    fx
}

/// The fixes' counts up to `until` \[s\] of a run over the drive's samples before it.
fn counts_until(config: FusionConfig, until: f64, offset: f64) -> FixCounts {
    let (t, psi, rate) = drive(200.0);
    let n = t.iter().take_while(|&&t| t < until).count();
    let fx = offset_from_100_s(&t, &psi, offset);
    let mut f = Fusion::new(config).unwrap();
    let mut h = vec![0.0; n];
    let out = FusionOutputs::heading(&mut h);
    f.process_block(&t[..n], &rate[..n], &fx, out).unwrap();
    f.counts()
}

#[test]
fn the_fix_that_ends_a_run_of_readmit_after_seconds_and_three_rejections_is_taken_in() {
    // 8 deg off: beyond the gate (about 3.4 deg here), within its reach (about 14 deg).
    let at_once = FusionConfig {
        readmit_after: 0.0,
        ..config()
    };
    let readmitted_by = |config, until| counts_until(config, until, 8.0).readmitted;
    // the fixes of 100 s and 101 s rejected, the third re-admitted
    assert_eq!(readmitted_by(at_once, 101.5), 0);
    assert_eq!(readmitted_by(at_once, 102.5), 1);
    let after_three_seconds = FusionConfig {
        readmit_after: 3.0,
        ..config()
    };
    // 100, 101, 102 s rejected; 103 s is 3 s after the first
    assert_eq!(readmitted_by(after_three_seconds, 102.5), 0);
    assert_eq!(readmitted_by(after_three_seconds, 103.5), 1);
}

#[test]
fn a_lasting_wrong_course_beyond_reach_stays_rejected_and_one_within_it_is_taken_after_readmit_after(
) {
    let (t, psi, rate) = drive(200.0);
    // A course half a turn off for 30 s (a vehicle reversing): never re-admitted.
    let mut fx = fixes(&t, &psi, 100, (0.0, 0.0));
    for f in fx.iter_mut().filter(|f| (100.0..130.0).contains(&f.t)) {
        f.heading = wrap_angle(f.heading + core::f64::consts::PI);
    }
    let (r, counts) = whole(config(), &t, &rate, &fx);
    assert_eq!(counts.readmitted, 0, "{counts:?}");
    assert!(counts.rejected >= 30, "{counts:?}");
    let off = worst_after(&t, &r.heading, &psi, 90.0);
    assert!(off < 1.0, "{off} deg");
    // 8 deg off from 100 s on, lasting: taken after readmit_after (10 s here) ...
    let fx = offset_from_100_s(&t, &psi, 8.0);
    let (r, counts) = whole(config(), &t, &rate, &fx);
    assert_eq!(counts.readmitted, 1, "{counts:?}");
    let errors_at = |at: f64| {
        let k = t.iter().position(|&t| t >= at).unwrap();
        wrap_angle(r.heading[k] - psi[k]).to_degrees()
    };
    assert!(errors_at(105.0).abs() < 3.0, "{}", errors_at(105.0));
    assert!((errors_at(150.0) - 8.0).abs() < 1.0, "{}", errors_at(150.0));
    // ... and never by the gate alone
    let never = FusionConfig {
        readmit_after: f64::INFINITY,
        ..config()
    };
    let (_, counts) = whole(never, &t, &rate, &fx);
    assert_eq!(counts.readmitted, 0, "{counts:?}");
    assert!(counts.rejected >= 90, "{counts:?}");
}

#[test]
fn a_run_of_rejections_cut_into_blocks_or_stored_mid_way_carries_on_bit_for_bit() {
    let (t, psi, _) = drive(300.0);
    cut_and_stored_as_one_call(&fixes(&t, &psi, 100, (0.0, 0.0)));
    // in bursts, the outages left out of the runs' length carried on as well
    cut_and_stored_as_one_call(&at_10_hz_where(|t| (t % 10.0) < 1.0));
}

/// The filter sure of a wrong bias over `fx` in blocks, stored and read back at every cut, some
/// of them mid-run: bit-identical to one call.
fn cut_and_stored_as_one_call(fx: &[Fix]) {
    let (t, _, rate) = drive(300.0);
    let (one, counts) = whole(sure_of_a_wrong_bias(), &t, &rate, fx);
    assert!(counts.readmitted >= 1);
    let mut f = Fusion::new(sure_of_a_wrong_bias()).unwrap();
    let mut heading = vec![0.0; t.len()];
    let mut pending: &[Fix] = fx;
    let mut cuts: Vec<usize> = (0..t.len()).step_by(613).collect();
    cuts.extend([1, 1500, 1501, t.len()]);
    cuts.sort_unstable();
    #[cfg(feature = "serde")]
    let mut stored_mid_run = 0;
    for w in cuts.windows(2) {
        // stored and read back at every cut, some of them while the gate rejects every fix
        #[cfg(feature = "serde")]
        {
            let json = serde_json::to_string(&f).unwrap();
            stored_mid_run += usize::from(json.contains("\"rejected_run\":["));
            f = serde_json::from_str(&json).unwrap();
        }
        let (a, b) = (w[0], w[1]);
        let out = FusionOutputs::heading(&mut heading[a..b]);
        let used = f
            .process_block(&t[a..b], &rate[a..b], pending, out)
            .unwrap();
        pending = &pending[used..];
    }
    #[cfg(feature = "serde")]
    assert!(stored_mid_run >= 2, "{stored_mid_run}");
    assert_eq!(f.counts(), counts);
    let bits = |h: &[f64]| h.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&heading), bits(&one.heading));
}

#[test]
fn two_stray_fixes_before_an_outage_and_one_after_it_do_not_reset_the_heading() {
    // Honest fixes a second, none from 100 s to 160 s (a tunnel); the last two before it and the
    // first after it 8 deg off (beyond the gate, within its reach). Counted across the outage,
    // the three were a run of readmit_after seconds and the third reset the heading to itself.
    let (t, psi, rate) = drive(200.0);
    let fx = fixes(&t, &psi, 100, (100.0, 160.0));
    let after = fx.iter().position(|f| f.t >= 160.0).unwrap();
    let off = strays_rejected(&t, &psi, &rate, fx, after - 2..after + 1);
    assert!(off < 1.5, "{off} deg");
    // A lock-out of the same fixes with no outage between them is still ended.
    let fx = offset_from_100_s(&t, &psi, 8.0);
    let (_, counts) = whole(config(), &t, &rate, &fx);
    assert_eq!(counts.readmitted, 1, "{counts:?}");
}

#[test]
fn stray_fixes_between_two_tunnels_and_one_after_them_do_not_reset_the_heading() {
    // Honest fixes a second, none from 100 s to 130 s nor from 133 s to 163 s; the three between
    // the tunnels and the first after the second 8 deg off. Each outage counts in the run as the
    // longest gap (5 s): 2 + 5 s of rejections, under readmit_after. (A pace that followed the
    // last intervals, grown by the first tunnel, counted most of the second one: re-admitted.)
    let (t, psi, rate) = drive(200.0);
    let mut fx = fixes(&t, &psi, 100, (100.0, 130.0));
    fx.retain(|f| !(133.0..163.0).contains(&f.t));
    let between = fx.iter().position(|f| f.t >= 130.0).unwrap();
    let off = strays_rejected(&t, &psi, &rate, fx, between..between + 4);
    assert!(off < 2.0, "{off} deg");
}

/// The fixes `fx` with those of `strays` 8 deg off (beyond the gate, within its reach), fused
/// whole: none re-admitted, each stray rejected beyond what the honest fixes had rejected; the
/// heading's worst error from 90 s on [deg].
fn strays_rejected(
    t: &[f64],
    psi: &[f64],
    rate: &[f64],
    mut fx: Vec<Fix>,
    strays: Range<usize>,
) -> f64 {
    let (_, honest) = whole(config(), t, rate, &fx);
    let count = strays.len() as u64;
    for f in &mut fx[strays] {
        f.heading = wrap_angle(f.heading + 8f64.to_radians());
    }
    let (r, counts) = whole(config(), t, rate, &fx);
    assert_eq!(counts.readmitted, 0, "{counts:?}");
    assert_eq!(
        counts.rejected,
        honest.rejected + count,
        "{counts:?} {honest:?}"
    );
    worst_after(t, &r.heading, psi, 90.0)
}

/// The drive's gyro reading `extra` rad/s more, to a filter sure (its bias sigma 1e-4 rad/s)
/// that the bias is 0: the heading runs away from the fixes at about 3 deg/s, past the reach of
/// re-admission (about 14 deg here) before `readmit_after`.
fn far_too_sure(extra: f64, readmit_after: f64) -> (f64, FixCounts, f64) {
    let (t, psi, rate) = drive(300.0);
    let rate: Vec<f64> = rate.iter().map(|r| r + extra).collect();
    let fx = fixes(&t, &psi, 100, (0.0, 0.0));
    let sure = FusionConfig {
        initial_bias_sigma: 1e-4,
        readmit_after,
        ..config()
    };
    let (r, counts) = whole(sure, &t, &rate, &fx);
    let last = t.len() - 1;
    (
        worst_after(&t, &r.heading, &psi, 240.0),
        counts,
        r.bias[last],
    )
}

#[test]
fn a_filter_far_too_sure_of_a_wrong_bias_is_taken_back_where_the_fixes_drift_away_steadily() {
    let (off, counts, _) = far_too_sure(0.04, f64::INFINITY);
    assert!(off > 30.0, "the gate alone: {off} deg, {counts:?}");
    // Before, the fixes lay beyond the reach when readmit_after had passed: locked out as with
    // the gate alone, every fix from the first rejected on.
    let (off, counts, bias) = far_too_sure(0.04, 10.0);
    assert!(counts.readmitted >= 1, "{counts:?}");
    assert!(counts.rejected < 60, "{counts:?}");
    assert!(off < 2.0, "{off} deg, {counts:?}");
    assert!((bias - (BIAS + 0.04)).abs() < 2e-3, "bias {bias}");
}

#[test]
fn a_lasting_wrong_course_far_beyond_reach_stays_rejected_however_long() {
    // 45 deg off from 100 s on: a steady offset, not a drift (its innovations' slope is the
    // filter's own small bias error): never taken in.
    let (t, psi, rate) = drive(300.0);
    let fx = offset_from_100_s(&t, &psi, 45.0);
    let (r, counts) = whole(config(), &t, &rate, &fx);
    assert_eq!(counts.readmitted, 0, "{counts:?}");
    assert!(counts.rejected >= 190, "{counts:?}");
    let off = worst_after(&t, &r.heading, &psi, 100.0);
    assert!(off < 3.0, "{off} deg");
}

/// Sure of a wrong bias (`sure_of_a_wrong_bias`), with honest fixes `fx` at an uneven pace:
/// the worst heading error \[deg\] from 240 s on, and the counts.
fn locked_out_at_an_uneven_pace(fx: &[Fix]) -> (f64, FixCounts) {
    let (t, psi, rate) = drive(300.0);
    let (r, counts) = whole(sure_of_a_wrong_bias(), &t, &rate, fx);
    (worst_after(&t, &r.heading, &psi, 240.0), counts)
}

/// Honest fixes at 10 Hz where `keep` holds for their time.
fn at_10_hz_where(keep: impl Fn(f64) -> bool) -> Vec<Fix> {
    let (t, psi, _) = drive(300.0);
    let mut fx = fixes(&t, &psi, 10, (0.0, 0.0));
    fx.retain(|f| keep(f.t));
    fx
}

#[test]
fn a_lock_out_ends_where_the_fixes_pace_falls_after_a_burst() {
    // 10 Hz for the first 10 s, then one fix every 10 s. Before, the pace was the shortest
    // interval (0.1 s), every later gap of 10 s an outage that ended the run of rejections: the
    // run never lasted readmit_after, nothing was re-admitted, and the heading ended 142 deg off.
    let fx = at_10_hz_where(|t| t < 10.0 || (t % 10.0) < 0.05);
    let (off, counts) = locked_out_at_an_uneven_pace(&fx);
    assert!(counts.readmitted >= 1, "{counts:?}");
    assert!(off < 2.0, "{off} deg, {counts:?}");
}

#[test]
fn a_lock_out_ends_where_the_fixes_come_in_bursts() {
    // 10 Hz for 1 s in every 10 s: each gap of 9 s is counted up to the longest gap a run spans
    // (5 s), so the rejections of a few bursts last readmit_after (before, each gap ended the
    // run: nothing re-admitted, 119 deg off).
    let fx = at_10_hz_where(|t| (t % 10.0) < 1.0);
    let (off, counts) = locked_out_at_an_uneven_pace(&fx);
    assert!(counts.readmitted >= 1, "{counts:?}");
    assert!(off < 2.0, "{off} deg, {counts:?}");
}

#[test]
fn a_lock_out_ends_after_a_first_interval_of_a_nanosecond() {
    // Fixes every 10 s, the first given twice 1 ns apart (two receivers): before, the pace stayed
    // at 1 ns for good, every gap of 10 s was an outage, and the lock-out was never ended.
    let mut fx = at_10_hz_where(|t| (t % 10.0) < 0.05);
    fx.insert(
        1,
        Fix {
            t: fx[0].t + 1e-9,
            ..fx[0]
        },
    );
    let (off, counts) = locked_out_at_an_uneven_pace(&fx);
    assert!(counts.readmitted >= 1, "{counts:?}");
    assert!(off < 2.0, "{off} deg, {counts:?}");
}
