//! Adversarial states read back (`serde` feature): a valid state written by `serde_json`, one
//! field changed to an extreme (1e308, -1e308, 0, -1, a subnormal, u64::MAX, i64::MIN, the
//! limits, "inf", "nan") or an array emptied, shortened or lengthened. The deserialiser refuses it
//! in the crate's words, or what it reads back runs without a panic or a hang and gives finite
//! outputs.
#![cfg(feature = "serde")]

mod serde_edit;
mod states;

use serde_edit::{edited, every_edit, read_and_run};

use gyrocore::*;
use proptest::prelude::*;
use serde_json::{json, Value};

fn model() -> GyroModel {
    let mut c = GyroModelConfig::ideal(100.0);
    (c.bias_instability, c.drift_step, c.rrw, c.arw) = (1e-4, 0.01, 1e-5, 1e-3);
    (c.drop_probability, c.jitter, c.bandwidth) = (0.5, 1e-3, 20.0);
    let mut m = GyroModel::new(c, 7).unwrap();
    for i in 0..50 {
        m.measure(i as f64 * 0.01, 0.1);
    }
    m
}

fn run_model(mut m: GyroModel) -> Result<(), String> {
    for t in [0.5, 0.51, 3.0, 1e6, 1e6 + 0.01] {
        let s = m.measure(t, 0.1);
        if !s.rate.is_finite() {
            return Err(format!("{s:?} at {t}"));
        }
    }
    Ok(())
}

fn run_sampler(s: gyrocore::sim::Sampler) -> Result<(), String> {
    let _ = s.take(100).count();
    Ok(())
}

/// A stored model whose count of flicker terms exceeds the most there are (it panicked on a
/// slice index at the next grid step), or whose drift grid index is u64::MAX (an overflow, a
/// panic in a debug build): the count is derived again from the configuration, the index
/// saturates. Every field of a model and of its sampler edited to every extreme: refused, or
/// readings and instants without a panic or a hang.
#[test]
fn an_edited_model_runs_on() {
    let m = model();
    every_edit(&m, run_model);
    every_edit(&m.sampler(0.0), run_sampler);
    let mut v = serde_json::to_value(&m).unwrap();
    v["terms"]["count"] = json!(17);
    let mut read: GyroModel = serde_json::from_value(v).unwrap();
    assert_eq!(read, m, "the derived terms are derived again");
    run_model(read.clone()).unwrap();
    let mut v = serde_json::to_value(&m).unwrap();
    v["slow"]["index"] = json!(u64::MAX);
    read = serde_json::from_value(v).unwrap();
    run_model(read).unwrap();
    let mut v = serde_json::to_value(&m).unwrap();
    v["config"]["rate_hz"] = json!(-1.0);
    let e = serde_json::from_value::<GyroModel>(v)
        .unwrap_err()
        .to_string();
    assert!(e.contains("invalid parameter rate_hz = -1"), "{e}");
}

/// A stored sampler whose generator is all zero (it then gives 0 for ever, and a sampler that
/// drops samples never returned from `next`) is refused; one at index u64::MAX (an overflow)
/// gives its instant.
#[test]
fn an_edited_sampler_is_refused_or_runs_on() {
    let s = model().sampler(0.0);
    let mut v = serde_json::to_value(&s).unwrap();
    v["rng"]["rng"]["s"] = json!([0, 0, 0, 0]);
    let e = serde_json::from_value::<gyrocore::sim::Sampler>(v)
        .unwrap_err()
        .to_string();
    assert!(e.contains("rng state"), "{e}");
    let mut v = serde_json::to_value(&s).unwrap();
    v["index"] = json!(u64::MAX);
    let mut read: gyrocore::sim::Sampler = serde_json::from_value(v).unwrap();
    assert!(read.next().is_some());
}

/// `n` samples from `t0` on: a rest, then turns back and forth.
fn drive(t0: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
    let t = (0..n).map(|i| t0 + i as f64 * 0.05).collect();
    let r = (0..n)
        .map(|i| match (i / 40) % 3 {
            0 => 1e-3 * (i as f64).sin(),
            1 => 0.3,
            _ => -0.2,
        })
        .collect();
    (t, r)
}

/// A pipeline of each preset (and a general chain) after some samples, its rest window still
/// open or over.
fn pipelines() -> Vec<Pipeline> {
    let mut general = Preset::Combined.config();
    (general.correction.c_cw, general.integrator.method) = (1.01, Method::Rectangle);
    let configs = Preset::ALL.iter().map(|p| p.config()).chain([general]);
    let mut out = Vec::new();
    for mut c in configs {
        c.correction.bias = StaticBias::Leading { duration: 3.0 };
        c.input.non_finite = NonFinite::Hold;
        for n in [0, 30, 200] {
            let mut p = Pipeline::new(c).unwrap();
            let (t, r) = drive(0.0, n);
            for (&x, &y) in t.iter().zip(&r) {
                p.update(x, y);
            }
            out.push(p);
        }
    }
    out
}

fn run_pipeline(p: Pipeline) -> Result<(), String> {
    let t0 = p.last_time().map_or(0.0, |t| t + 0.05);
    let (t, mut r) = drive(t0, 200);
    r[7] = f64::NAN; // held
    let mut a = p.clone();
    let mut b = p;
    let (mut h, mut rate, mut d) = (vec![0.0; 200], vec![0.0; 200], vec![0.0; 200]);
    let block = a.process_block(&t, &r, None, Outputs::all(&mut h, &mut rate, &mut d));
    b.update(t[0] - 1.0, 0.0); // skipped
    let updates: Vec<Output> = t.iter().zip(&r).map(|(&x, &y)| b.update(x, y)).collect();
    if block.is_ok() {
        if let Some(i) = h.iter().position(|x| !x.is_finite()) {
            return Err(format!("heading {} at {}", h[i], t[i]));
        }
    }
    match updates.iter().position(|o| !o.heading.is_finite()) {
        Some(i) => Err(format!("update {:?} at {}", updates[i], t[i])),
        None => Ok(()),
    }
}

/// Runs a filter read back, with fixes, through the smoother's passes: no panic.
fn run_fusion(f: Fusion) -> Result<(), String> {
    let t0 = f.last_time().map_or(0.0, |t| t + 0.05);
    let (t, r) = drive(t0, 200);
    let fixes: Vec<Fix> = (0..5)
        .map(|i| Fix {
            t: t0 + 2.0 * i as f64 + 0.01,
            heading: 0.1 * i as f64,
            sigma: 0.01,
        })
        .collect();
    let n = t.len();
    let mut h = vec![0.0; n];
    let mut knots = Vec::new();
    let mut a = f;
    let out = FusionOutputs::heading(&mut h);
    if a.process_block_recording(&t, &r, &fixes, out, |k| knots.push(k))
        .is_ok()
    {
        if let Some(i) = h.iter().position(|x| !x.is_finite()) {
            return Err(format!("heading {} at {}", h[i], t[i]));
        }
        smooth(&mut knots);
        let mut b = f;
        let _ = b.process_block_smoothed(&t, &r, &fixes, &knots, FusionOutputs::heading(&mut h));
    }
    Ok(())
}

/// A heading-fix filter, fresh and mid-stream, a pipeline measuring its rest window, one
/// tracking rests, and the stand-alone stages that remember, each field edited to each extreme:
/// refused (a stored rate integral or rate of 1e308 gave infinite or NaN headings, a variance of
/// -1e308 NaN ones, a de-lag's last input of 1e308 an infinite rate), or finite outputs.
#[test]
fn every_edit_is_refused_or_gives_finite_headings() {
    every_edit(&Fusion::new(FusionConfig::default()).unwrap(), run_fusion);
    every_edit(&states::fusion(), run_fusion);
    let all = pipelines();
    every_edit(&all[3 * 4 + 1], run_pipeline); // combined, measuring
    every_edit(&all[3 * 6 + 2], run_pipeline); // tracked, rests found
    let tau = LowPassConfig { tau: 0.75 };
    every_edit(&warm(DeLag::new(tau).unwrap()), run_stage);
    every_edit(&warm(LowPass::new(tau).unwrap()), run_stage);
    every_edit(&warm(Hdr::new(HdrConfig::table_iii()).unwrap()), run_stage);
    every_edit(
        &warm(Integrator::new(Default::default()).unwrap()),
        run_stage,
    );
}

/// `stage` after some samples.
fn warm<S: Stage<Output = f64>>(mut stage: S) -> S {
    let (t, r) = drive(0.0, 100);
    for (&x, &y) in t.iter().zip(&r) {
        stage.update(x, y);
    }
    stage
}

/// Runs a stand-alone stage read back on from its last sample: finite outputs.
fn run_stage<S: Stage<Output = f64>>(mut stage: S) -> Result<(), String> {
    let (t, r) = drive(stage.last_time().map_or(0.0, |t| t + 0.05), 100);
    for (&x, &y) in t.iter().zip(&r) {
        let out = stage.update(x, y);
        if !out.is_finite() {
            return Err(format!("{out} at {x}"));
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// A pipeline read back after an edit runs without a panic, and its headings are finite.
    #[test]
    fn an_edited_pipeline(which in any::<usize>(), pick in any::<usize>(), how in any::<usize>()) {
        let all = pipelines();
        let (what, v) = edited(&all[which % all.len()], pick, how);
        read_and_run(what, v, run_pipeline)?;
    }
}

/// Every count of a stored pipeline and filter at `u64::MAX` (a state edited by hand, or one
/// that counted that far): the counts stay there, where each overflowed (a panic in a debug
/// build).
#[test]
fn counts_at_their_largest_saturate() {
    fn set_counts(v: &mut Value) {
        match v {
            Value::Object(o) => {
                for (k, x) in o.iter_mut() {
                    let count = [
                        "count",
                        "differences",
                        "samples",
                        "blocks",
                        "found",
                        "held",
                        "skipped",
                        "gaps",
                        "applied",
                        "rejected",
                        "before_start",
                    ];
                    if count.contains(&k.as_str()) && x.is_u64() {
                        *x = json!(u64::MAX);
                    } else {
                        set_counts(x);
                    }
                }
            }
            Value::Array(a) => a.iter_mut().for_each(set_counts),
            _ => {}
        }
    }
    for p in pipelines() {
        let mut v = serde_json::to_value(&p).unwrap();
        set_counts(&mut v);
        let read: Pipeline = serde_json::from_value(v).unwrap();
        run_pipeline(read.clone()).unwrap();
        let mut q = read;
        q.update(-1e9, 0.0);
        assert_eq!(q.report().skipped, u64::MAX);
    }
    let mut v = serde_json::to_value(states::fusion()).unwrap();
    set_counts(&mut v);
    let read: Fusion = serde_json::from_value(v).unwrap();
    run_fusion(read).unwrap();
    let mut f = read;
    let fix = Fix {
        t: 20.0,
        heading: 0.0,
        sigma: 0.01,
    };
    let mut h = [0.0; 2];
    f.process_block(
        &[20.0, 20.1],
        &[0.0; 2],
        &[fix],
        FusionOutputs::heading(&mut h),
    )
    .unwrap();
    let counts = f.counts();
    assert_eq!((counts.applied, counts.rejected), (u64::MAX, u64::MAX));
}

/// A stored value that valid input never reaches, where the next samples made it infinite: the
/// rest window's integral, HDR's `I`, the correction the de-lag applied last, the rest tracker's
/// filtered bias, a window bound, the integrator's heading and last rate, a de-lag's last input.
/// Each is refused naming it; each edited to a value valid input reaches (0) reads back and runs,
/// but for those another field must agree with (the bias with its integral, the window with the
/// configured one, the chain's bias with the tracker's).
#[test]
fn stored_values_beyond_reach_are_refused() {
    let cases = [
        ("/bias/integral", "bias integral"),
        ("/bias/window/1", "bias_window"),
        ("/engine/Hdr/state/2/inner/integrator", "hdr integrator"),
        ("/engine/Hdr/state/2/applied", "applied correction"),
        ("/engine/General/state/3/inner/integrator", "hdr integrator"),
        ("/engine/Tracked/state/tracker/bias", "rest tracker bias"),
        (
            "/engine/Tracked/state/state/3/applied",
            "applied correction",
        ),
        ("/engine/Hdr/state/3/previous", "previous rate"),
        ("/engine/Plain/state/2/heading", "heading"),
    ];
    let mut seen = [false; 9];
    for p in pipelines() {
        let v = serde_json::to_value(&p).unwrap();
        for (k, (at, name)) in cases.iter().enumerate() {
            if v.pointer(at).is_none() {
                continue;
            }
            seen[k] = true;
            for value in [1e308, -1e308] {
                let mut e = v.clone();
                *e.pointer_mut(at).unwrap() = json!(value);
                let err = serde_json::from_value::<Pipeline>(e)
                    .unwrap_err()
                    .to_string();
                assert!(
                    err.contains(&format!("invalid parameter {name} = ")),
                    "{at}: {err}"
                );
            }
            let tied = [
                "/bias/integral",
                "/bias/window/1",
                "/engine/Tracked/state/tracker/bias",
            ];
            if tied.contains(at) {
                continue;
            }
            let mut e = v.clone();
            *e.pointer_mut(at).unwrap() = json!(0.0);
            run_pipeline(serde_json::from_value(e).unwrap()).unwrap();
        }
    }
    assert_eq!(seen, [true; 9]);
    // The stand-alone stages: a correction measuring its window, and HDR.
    let (t, r) = drive(0.0, 100);
    let mut c = Correction::new(CorrectionConfig {
        bias: StaticBias::Leading { duration: 100.0 },
        ..Default::default()
    })
    .unwrap();
    let mut h = Hdr::new(HdrConfig::table_iii()).unwrap();
    for (&x, &y) in t.iter().zip(&r) {
        c.update(x, y);
        h.update(x, y);
    }
    let mut v = serde_json::to_value(&c).unwrap();
    v["bias"]["integral"] = json!(1e308);
    let err = serde_json::from_value::<Correction>(v)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("invalid parameter bias integral = 1e308"),
        "{err}"
    );
    let mut v = serde_json::to_value(h).unwrap();
    v["state"]["integrator"] = json!(-1e308);
    let err = serde_json::from_value::<Hdr>(v).unwrap_err().to_string();
    assert!(
        err.contains("invalid parameter hdr integrator = -1e308"),
        "{err}"
    );
    let mut i = Integrator::new(IntegratorConfig::default()).unwrap();
    i.update(0.0, 1.0);
    let mut v = serde_json::to_value(i).unwrap();
    v["state"]["previous"] = json!(1e308);
    let err = serde_json::from_value::<Integrator>(v)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("invalid parameter previous rate = 1e308"),
        "{err}"
    );
    let mut d = DeLag::new(LowPassConfig { tau: 0.75 }).unwrap();
    d.update(0.0, 1.0);
    let mut v = serde_json::to_value(d).unwrap();
    v["state"] = json!(-1e308);
    let err = serde_json::from_value::<DeLag>(v).unwrap_err().to_string();
    assert!(
        err.contains("invalid parameter filter state = -1e308"),
        "{err}"
    );
}
