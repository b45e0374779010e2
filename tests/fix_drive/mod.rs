//! The drive, fixes and filter runs the heading-fix filter's tests share (tests/fixes.rs,
//! tests/fixes_readmit.rs).
#![allow(dead_code)] // each test binary uses its own subset

use gyrocore::fixes::wrap_angle;
use gyrocore::{Fix, Fusion, FusionConfig, FusionError, FusionOutputs};

/// A deterministic normal generator (xorshift64* and Box-Muller), so the tests need no crate.
pub struct Normal(u64);

impl Normal {
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    pub fn next(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

pub const BIAS: f64 = 0.01;
pub const SCALE: f64 = 0.02;

/// A drive at 100 Hz turning both ways: (t, true heading, gyro reading with Hong eq 1's error).
pub fn drive(seconds: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut noise = Normal(0x9E37_79B9_7F4A_7C15);
    let n = (seconds * 100.0) as usize;
    let t: Vec<f64> = (0..n).map(|k| k as f64 * 0.01).collect();
    let true_rate = |t: f64| 0.3 * (0.05 * t).sin() + 0.2 * (0.13 * t).cos();
    // The integral of true_rate, so the true heading is exact.
    let heading =
        |t: f64| 0.3 / 0.05 * (1.0 - (0.05 * t).cos()) + 0.2 / 0.13 * (0.13 * t).sin() + 1.0;
    let psi = t.iter().map(|&t| heading(t)).collect();
    let rate = t
        .iter()
        .map(|&t| (1.0 + SCALE) * true_rate(t) + BIAS + 1e-3 * noise.next())
        .collect();
    (t, psi, rate)
}

/// Fixes every `every` seconds with 1 deg noise, none inside `outage` (start, end).
pub fn fixes(t: &[f64], psi: &[f64], every: usize, outage: (f64, f64)) -> Vec<Fix> {
    let mut noise = Normal(7);
    let sigma = 1f64.to_radians();
    (0..t.len())
        .step_by(every)
        .filter(|&k| t[k] < outage.0 || t[k] >= outage.1)
        .map(|k| Fix {
            t: t[k] + 0.003,
            heading: wrap_angle(psi[k] + sigma * noise.next()),
            sigma,
        })
        .collect()
}

pub fn config() -> FusionConfig {
    FusionConfig {
        arw: 1e-3 * 0.1,
        bias_walk: 1e-5,
        // the re-admission tests count seconds of rejections from this, not from the default
        readmit_after: 10.0,
        ..FusionConfig::default()
    }
}

pub struct Run {
    pub heading: Vec<f64>,
    pub sigma: Vec<f64>,
    pub bias: Vec<f64>,
    pub scale: Vec<f64>,
}

pub fn run(
    fusion: &mut Fusion,
    t: &[f64],
    rate: &[f64],
    fixes: &[Fix],
) -> Result<(Run, usize), FusionError> {
    let n = t.len();
    let mut r = Run {
        heading: vec![0.0; n],
        sigma: vec![0.0; n],
        bias: vec![0.0; n],
        scale: vec![0.0; n],
    };
    let out = FusionOutputs::all(&mut r.heading, &mut r.sigma, &mut r.bias, &mut r.scale);
    let used = fusion.process_block(t, rate, fixes, out)?;
    Ok((r, used))
}
