//! The drive, fixes and configuration the fused pipeline's tests share (tests/fused.rs,
//! tests/fused_errors.rs), and running it block by block.
#![allow(dead_code)] // each test binary uses its own subset

use gyrocore::{
    Fix, FusedOutputs, FusedPipeline, FusionConfig, FusionError, NonFinite, PipelineConfig, Preset,
    Samples, StaticBias,
};

/// The true yaw rate at `t` of the drives below: 5 s at rest, then turning both ways.
pub fn true_rate(t: f64) -> f64 {
    let s = t - 105.0;
    if s > 0.0 {
        0.3 * (0.05 * s).sin() + 0.2 * (0.13 * s).cos() - 0.2
    } else {
        0.0
    }
}

/// A 100 Hz drive of `seconds` from t = 100 s: (t, gyro reading with a bias, a scale error and
/// a deterministic wiggle for noise).
pub fn drive(seconds: f64) -> (Vec<f64>, Vec<f64>) {
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
pub fn fixes(t: &[f64]) -> Vec<Fix> {
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

pub fn config() -> (PipelineConfig, FusionConfig) {
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
pub type Columns = [Vec<f64>; 6];

pub fn columns(n: usize) -> Columns {
    core::array::from_fn(|_| vec![0.0; n])
}

/// Runs `fused` over one block, writing into `cols[from..]`.
pub fn block(
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

/// Runs `fused` over one block (`t`, `rate`, `fixes`): the first heading, heading sigma, bias or
/// scale that is not finite, named with its column and time (None: all finite), or the block's
/// error.
pub fn first_nonfinite(
    fused: &mut FusedPipeline,
    t: &[f64],
    rate: &[f64],
    fixes: &[Fix],
) -> Result<Option<String>, FusionError> {
    let mut cols = columns(t.len());
    block(fused, t, rate, fixes, &mut cols, 0)?;
    let names = ["heading", "heading sigma", "bias", "scale"];
    Ok(names.iter().zip(&cols).find_map(|(name, col)| {
        let i = col.iter().position(|x| !x.is_finite())?;
        Some(format!("{name}: {} at {}", col[i], t[i]))
    }))
}

/// The whole drive cut at `cuts` (sample indices), each block with the fixes up to its end and
/// the ones left over from before.
pub fn chunked(t: &[f64], rate: &[f64], all: &[Fix], cuts: &[usize]) -> (Columns, FusedPipeline) {
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

pub fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}
