//! A run of rejected fixes (`rejected_run`, the gate's lock-out) read back from an edited state
//! (`serde` feature): its first fix is one the filter processed, so no later than the last fix and
//! within the times a filter keeps (+-2^40 s).
#![cfg(feature = "serde")]

use gyrocore::*;
use serde_json::{json, Value};

mod states;
use states::{fusion, refused};

/// The stored filter of `states::fusion` (last fix at 4.5 s, standing at 4.99 s) with three fixes
/// rejected and `rejected_run` set to `run`.
fn with_run(run: Value) -> Value {
    let mut v = serde_json::to_value(fusion()).unwrap();
    assert_eq!(v["last_fix"], json!(4.5));
    v["counts"]["rejected"] = json!(3);
    v["rejected_run"] = run;
    v
}

#[test]
fn a_run_that_began_before_any_time_or_after_the_last_fix_is_refused() {
    // Before, each was read back: a run begun at -1e300 s had lasted any readmit_after, and the
    // filter re-admitted the next fix beyond the gate at once; one begun at 4.7 s (no fix was
    // processed after 4.5 s) or with no fix processed at all described no run there could be.
    let ok: Fusion = serde_json::from_value(with_run(json!([4.5, 3]))).unwrap();
    assert_eq!(ok.counts().rejected, 3);
    for run in [json!([-1e300, 3]), json!([-1.2e12, 1]), json!([4.7, 1])] {
        let err = refused::<Fusion>(with_run(run.clone()));
        assert!(
            err.contains("invalid parameter first rejected fix time"),
            "{run}: {err}"
        );
    }
    let mut no_fix = with_run(json!([4.5, 1]));
    no_fix["last_fix"] = Value::Null;
    let err = refused::<Fusion>(no_fix);
    assert!(
        err.contains("invalid parameter first rejected fix time"),
        "{err}"
    );
}

#[test]
fn the_fixes_interval_reads_back_and_a_state_without_it_is_one_that_saw_none() {
    // Stored before the interval was kept (the outage rule of `READMIT_GAP`): read back as a
    // filter that has seen no two fixes, so no gap ends a run until it has.
    let mut old = with_run(json!([4.5, 3]));
    assert!(old.get("fix_interval").is_some());
    old.as_object_mut().unwrap().remove("fix_interval");
    let f: Fusion = serde_json::from_value(old).unwrap();
    let again = serde_json::to_value(f).unwrap();
    assert_eq!(again["fix_interval"], json!("inf"));
    for bad in [json!(0.0), json!(-1.0), json!("nan"), json!("-inf")] {
        let mut v = with_run(json!([4.5, 3]));
        v["fix_interval"] = bad.clone();
        let err = refused::<Fusion>(v);
        assert!(
            err.contains("invalid parameter fix interval"),
            "{bad}: {err}"
        );
    }
}

#[test]
fn a_runs_drift_reads_back_and_a_state_without_it_is_judged_by_the_reach_alone() {
    // A run stored before its drift was kept reads back (the run is judged by its reach alone);
    // one with a sum of squares below 0 (an edit: no run gives one) is refused.
    let mut old = with_run(json!([4.5, 3]));
    old["drift"] = Value::Null;
    let f: Fusion = serde_json::from_value(old).unwrap();
    assert_eq!(f.counts().rejected, 3);
    let mut missing = with_run(json!([4.5, 3]));
    missing.as_object_mut().unwrap().remove("drift");
    serde_json::from_value::<Fusion>(missing).unwrap();
    let drift = json!({
        "sum_t": 1.0, "sum_tt": 1.0, "sum_y": 0.1, "sum_ty": 0.1, "sum_yy": 0.01, "last": 0.1
    });
    let mut ok = with_run(json!([4.5, 3]));
    ok["drift"] = drift.clone();
    serde_json::from_value::<Fusion>(ok).unwrap();
    for square in ["sum_tt", "sum_yy"] {
        let mut bad = with_run(json!([4.5, 3]));
        bad["drift"] = drift.clone();
        bad["drift"][square] = json!(-1.0);
        let err = refused::<Fusion>(bad);
        assert!(
            err.contains("invalid parameter rejected run drift"),
            "{err}"
        );
    }
}

#[test]
fn a_runs_outages_read_back_within_its_span_and_a_state_without_them_has_none() {
    // The outages left out of a run's length (`READMIT_GAP`): a state stored before they were
    // kept has none; more than the run's span (an edit) made it last readmit_after at once or
    // never, and is refused, as is any without a run.
    let mut old = with_run(json!([4.0, 3]));
    assert_eq!(old["run_outages"], json!(0.0));
    old.as_object_mut().unwrap().remove("run_outages");
    serde_json::from_value::<Fusion>(old).unwrap();
    let mut ok = with_run(json!([4.0, 3]));
    ok["run_outages"] = json!(0.5);
    serde_json::from_value::<Fusion>(ok).unwrap();
    let mut without = with_run(Value::Null);
    without["counts"]["rejected"] = json!(0);
    for (mut v, bad) in [
        (with_run(json!([4.0, 3])), json!(0.6)),
        (with_run(json!([4.0, 3])), json!(-1.0)),
        (without, json!(1.0)),
    ] {
        v["run_outages"] = bad.clone();
        let err = refused::<Fusion>(v);
        assert!(
            err.contains("invalid parameter run outages"),
            "{bad}: {err}"
        );
    }
}
