//! Adversarial states read back (`serde` feature), the types tests/adversarial_serde.rs leaves
//! out: the down-sampler with a block open, the correction stage learning its bias, the
//! threshold stage, the fused pipeline mid-drive with fixes, and the smoother's knots. Each field
//! edited to each extreme: refused in the crate's words, or it runs on without a panic or a hang
//! and with finite outputs.
#![cfg(feature = "serde")]

mod fused_drive;
mod serde_edit;

use fused_drive::first_nonfinite;
use gyrocore::*;
use serde_edit::every_edit;

/// `n` samples from `t0` on at 20 Hz: a rest, then turns back and forth.
fn drive(t0: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
    let t = (0..n).map(|i| t0 + i as f64 * 0.05).collect();
    let r = (0..n)
        .map(|i| match (i / 40) % 3 {
            0 => 2e-3,
            1 => 0.3,
            _ => -0.2,
        })
        .collect();
    (t, r)
}

fn fixes(t0: f64) -> Vec<Fix> {
    (0..5)
        .map(|i| Fix {
            t: t0 + 2.0 * i as f64 + 0.01,
            heading: 0.1 * i as f64,
            sigma: 0.01,
        })
        .collect()
}

/// Runs a down-sampler read back from just after its samples, and from near the largest time
/// (after any clock an edit stored): finite blocks.
fn run_downsample(d: Downsample) -> Result<(), String> {
    for t0 in [1.55, MAX_TIME * 0.99] {
        let mut d = d.clone();
        let (t, r) = drive(t0, 100);
        for (&x, &y) in t.iter().zip(&r) {
            if let Some((tb, mean)) = d.update(x, y) {
                if !(tb.is_finite() && mean.is_finite()) {
                    return Err(format!("block ({tb}, {mean}) at {x}"));
                }
            }
        }
    }
    Ok(())
}

fn run_correction(mut c: Correction) -> Result<(), String> {
    let t0 = c.last_time().map_or(0.0, |t| t + 0.05);
    let (t, r) = drive(t0, 100);
    for (&x, &y) in t.iter().zip(&r) {
        let out = c.update(x, y);
        if !out.is_finite() || !c.bias().is_finite() {
            return Err(format!("{out} (bias {}) at {x}", c.bias()));
        }
    }
    Ok(())
}

fn run_threshold(mut s: Threshold) -> Result<(), String> {
    let t0 = s.last_time().map_or(0.0, |t| t + 0.05);
    let (t, r) = drive(t0, 50);
    match t
        .iter()
        .zip(&r)
        .map(|(&x, &y)| s.update(x, y))
        .find(|o| !o.is_finite())
    {
        Some(o) => Err(format!("rate {o}")),
        None => Ok(()),
    }
}

fn run_fused(mut p: FusedPipeline) -> Result<(), String> {
    let t0 = p.pipeline().last_time().map_or(0.0, |t| t + 0.05);
    let (t, r) = drive(t0, 200);
    match first_nonfinite(&mut p, &t, &r, &fixes(t0)) {
        Ok(Some(bad)) => Err(bad),
        _ => Ok(()),
    }
}

/// The knots of a short forward run with `knot` edited in, smoothed and used by the second pass:
/// no panic or hang (knots that are not the forward run's give wrong estimates, as documented).
fn run_knot(knot: Knot) -> Result<(), String> {
    let (t, r) = drive(0.0, 200);
    let fx = fixes(0.0);
    let mut knots = Vec::new();
    let mut h = vec![0.0; t.len()];
    let config = FusionConfig::default();
    Fusion::new(config)
        .unwrap()
        .process_block_recording(&t, &r, &fx, FusionOutputs::heading(&mut h), |k| {
            knots.push(k)
        })
        .map_err(|e| e.to_string())?;
    knots[1] = knot;
    smooth(&mut knots);
    let out = FusionOutputs::heading(&mut h);
    let _ = Fusion::new(config)
        .unwrap()
        .process_block_smoothed(&t, &r, &fx, &knots, out);
    Ok(())
}

#[test]
fn every_edit_of_the_other_states_is_refused_or_runs_on() {
    let mut d = Downsample::new(DownsampleConfig { interval: 1.0 }).unwrap();
    let (t, r) = drive(0.0, 30);
    for (&x, &y) in t.iter().zip(&r) {
        d.update(x, y);
    }
    every_edit(&d, run_downsample);

    for bias in [
        StaticBias::Leading { duration: 3.0 },
        StaticBias::Window {
            start: 0.5,
            end: 4.0,
        },
    ] {
        let config = CorrectionConfig {
            bias,
            ..CorrectionConfig::default()
        };
        let mut c = Correction::new(config).unwrap();
        for (&x, &y) in t.iter().zip(&r) {
            c.update(x, y);
        }
        every_edit(&c, run_correction);
    }

    let mut s = Threshold::new(ThresholdConfig { threshold: 0.005 }).unwrap();
    for (&x, &y) in t.iter().zip(&r) {
        s.update(x, y);
    }
    every_edit(&s, run_threshold);
}

#[test]
fn every_edit_of_a_fused_pipeline_mid_drive_is_refused_or_runs_on() {
    let mut config = Preset::Tracked.config();
    config.correction.bias = StaticBias::Leading { duration: 3.0 };
    let mut p = FusedPipeline::new(config, FusionConfig::default()).unwrap();
    let (t, r) = drive(0.0, 300);
    let n = t.len();
    let (mut h, mut rate) = (vec![0.0; n], vec![0.0; n]);
    let out = FusedOutputs {
        heading: &mut h,
        heading_sigma: None,
        bias: None,
        scale: None,
        rate: &mut rate,
        drift: None,
    };
    p.process_block(Samples::new(&t, &r), &fixes(0.0), out)
        .unwrap();
    every_edit(&p, run_fused);
}

#[test]
fn every_edit_of_a_knot_gives_no_panic() {
    let (t, r) = drive(0.0, 100);
    let mut knots = Vec::new();
    let mut h = vec![0.0; t.len()];
    Fusion::new(FusionConfig::default())
        .unwrap()
        .process_block_recording(&t, &r, &fixes(0.0), FusionOutputs::heading(&mut h), |k| {
            knots.push(k)
        })
        .unwrap();
    every_edit(&knots[1], run_knot);
}
