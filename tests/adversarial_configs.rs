//! Configurations at and beyond their validation edges (`serde` feature, to reach every field):
//! each number of a preset's pipeline configuration and of the filter's set to an extreme (0, -1,
//! a subnormal, the limits, 1e308, inf, nan). `new` refuses it naming the field, or the pipeline
//! (and the fused pipeline with fixes) runs without a panic or a hang and with finite outputs.
#![cfg(feature = "serde")]

mod fused_drive;
mod serde_edit;

use fused_drive::first_nonfinite;
use gyrocore::*;
use serde_edit::every_edit;

/// A rest, then turns back and forth at 20 Hz, with a gap of 3 s and a NaN reading.
fn drive() -> (Vec<f64>, Vec<f64>) {
    let mut t: Vec<f64> = (0..400).map(|i| i as f64 * 0.05).collect();
    for x in &mut t[300..] {
        *x += 3.0;
    }
    let mut r: Vec<f64> = (0..400)
        .map(|i| match (i / 40) % 3 {
            0 => 2e-3,
            1 => 0.3,
            _ => -0.2,
        })
        .collect();
    r[150] = f64::NAN;
    (t, r)
}

fn run(config: PipelineConfig) -> Result<(), String> {
    let Ok(mut p) = Pipeline::new(config) else {
        return Ok(());
    };
    let (t, r) = drive();
    let n = t.len();
    let mut a = p.clone();
    let (mut h, mut rate, mut d) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let temperature = vec![25.0; n];
    let out = Outputs::all(&mut h, &mut rate, &mut d);
    if a.process_block(&t, &r, Some(&temperature), out).is_ok() {
        if let Some(i) = h.iter().position(|x| !x.is_finite()) {
            return Err(format!("heading {} at {}", h[i], t[i]));
        }
    }
    for (&x, &y) in t.iter().zip(&r) {
        let o = p.update_with_temperature(x, y, Some(25.0));
        if !o.heading.is_finite() {
            return Err(format!("update {o:?} at {x}"));
        }
    }
    Ok(())
}

fn run_fused(config: FusionConfig) -> Result<(), String> {
    let mut pipeline = Preset::Hdr.config();
    pipeline.input.non_finite = NonFinite::Hold;
    let Ok(mut p) = FusedPipeline::new(pipeline, config) else {
        return Ok(());
    };
    let (t, r) = drive();
    let fixes: Vec<Fix> = (0..10)
        .map(|i| Fix {
            t: 2.0 * i as f64,
            heading: if i == 6 { 3.0 } else { 0.0 },
            sigma: 0.01,
        })
        .collect();
    match first_nonfinite(&mut p, &t, &r, &fixes) {
        Err(e) => Err(e.to_string()),
        Ok(bad) => bad.map_or(Ok(()), Err),
    }
}

#[test]
fn a_pipeline_configuration_at_any_edge_is_refused_or_runs() {
    for preset in Preset::ALL {
        let mut c = preset.config();
        c.input.non_finite = NonFinite::Hold;
        every_edit(&c, run);
    }
    let mut c = Preset::Combined.config();
    c.correction.bias = StaticBias::Window {
        start: 1.0,
        end: 4.0,
    };
    c.correction.temperature = Some(correction::TemperatureScale {
        slope: 1e-3,
        offset: 1.0,
    });
    every_edit(&c, run);
}

#[test]
fn a_filter_configuration_at_any_edge_is_refused_or_runs() {
    every_edit(&FusionConfig::default(), run_fused);
}
