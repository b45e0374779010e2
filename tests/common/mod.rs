//! Helpers shared by the integration tests.
#![allow(dead_code)] // each test binary uses its own subset of the helpers

use gyrocore::{
    Error, FusedOutputs, GyroModel, GyroSample, Output, Outputs, Pipeline, PipelineConfig, Preset,
    Stage, StaticBias,
};

/// Feeds `(t, rate)` through a stand-alone stage sample by sample, returning its outputs.
pub fn run<S: Stage<Output = f64>>(stage: &mut S, t: &[f64], rate: &[f64]) -> Vec<f64> {
    t.iter()
        .zip(rate)
        .map(|(&ti, &ri)| stage.update(ti, ri))
        .collect()
}

/// Feeds one block through `p`, returning the per-sample outputs.
pub fn try_block(p: &mut Pipeline, t: &[f64], r: &[f64]) -> Result<Vec<Output>, Error> {
    try_block_with_speed(p, t, r, None)
}

/// [`try_block`] with a speed per sample (`None`: no speed).
pub fn try_block_with_speed(
    p: &mut Pipeline,
    t: &[f64],
    r: &[f64],
    speed: Option<&[f64]>,
) -> Result<Vec<Output>, Error> {
    let n = t.len();
    let (mut h, mut ra, mut d) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let out = Outputs::all(&mut h, &mut ra, &mut d);
    p.process_block_with_speed(t, r, None, speed, out)?;
    Ok((0..n)
        .map(|i| Output {
            heading: h[i],
            rate: ra[i],
            drift: d[i],
        })
        .collect())
}

/// The outputs as bits, so that comparisons are exact (and NaN equals NaN).
pub fn bits(o: &[Output]) -> Vec<[u64; 3]> {
    o.iter()
        .map(|o| [o.heading.to_bits(), o.rate.to_bits(), o.drift.to_bits()])
        .collect()
}

/// `x` degrees in radians.
pub fn deg(x: f64) -> f64 {
    x.to_radians()
}

/// Readings of `model` at rest at `n` samples of `1 / rate_hz` seconds.
pub fn at_rest(model: &mut GyroModel, n: usize) -> Vec<GyroSample> {
    let dt = 1.0 / model.config().rate_hz;
    (0..n).map(|i| model.measure(i as f64 * dt, 0.0)).collect()
}

/// A fused pipeline's outputs of the heading and the rate alone, written into `heading` and `rate`.
pub fn heading_and_rate<'a>(heading: &'a mut [f64], rate: &'a mut [f64]) -> FusedOutputs<'a> {
    FusedOutputs {
        heading,
        heading_sigma: None,
        bias: None,
        scale: None,
        rate,
        drift: None,
    }
}

/// `preset`'s configuration with its static bias measured over the rest window `[start, end]` \[s\].
pub fn with_window(preset: Preset, start: f64, end: f64) -> PipelineConfig {
    let mut c = preset.config();
    c.correction.bias = StaticBias::Window { start, end };
    c
}
