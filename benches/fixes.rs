//! Criterion bench of the heading-fix filter (rust/src/fixes.rs): 1,000,000 gyro samples at
//! 100 Hz without fixes and with a fix every second (10,000 fixes), reported as gyro samples per
//! second, and the whole-log smoother (forward pass storing its steps, then the backward pass).

use criterion::{criterion_group, BenchmarkId, Criterion, Throughput};
use gyrocore::fixes_smooth::Step;
use gyrocore::{smooth, Fix, Fusion, FusionConfig, FusionOutputs};
use std::hint::black_box;

mod common;

const N: usize = 1_000_000;

fn samples() -> (Vec<f64>, Vec<f64>, Vec<Fix>) {
    let t: Vec<f64> = (0..N).map(|i| 1.65e9 + i as f64 * 0.01).collect();
    let rate: Vec<f64> = (0..N)
        .map(|i| 0.01 + 0.2 * ((i as f64) * 1e-3).sin())
        .collect();
    let fixes = (0..N)
        .step_by(100)
        .map(|i| Fix {
            t: t[i] + 0.005,
            heading: 0.2 * (1.0 - ((i as f64) * 1e-3).cos()),
            sigma: 0.02,
        })
        .collect();
    (t, rate, fixes)
}

/// The four output columns as the filter writes them.
fn outputs(out: &mut [Vec<f64>; 4]) -> FusionOutputs<'_> {
    let [heading, heading_sigma, bias, scale] = out;
    FusionOutputs {
        heading,
        heading_sigma,
        bias,
        scale,
    }
}

fn filter(c: &mut Criterion) {
    let (t, rate, fixes) = samples();
    let mut out = [vec![0.0; N], vec![0.0; N], vec![0.0; N], vec![0.0; N]];
    let mut group = c.benchmark_group("fixes_filter");
    group.throughput(Throughput::Elements(N as u64));
    for (name, given) in [("no_fixes", &fixes[..0]), ("fixes_1hz", &fixes[..])] {
        group.bench_with_input(BenchmarkId::from_parameter(name), given, |b, given| {
            b.iter(|| {
                let mut f = Fusion::new(FusionConfig::default()).unwrap();
                let o = outputs(&mut out);
                f.process_block(black_box(&t), black_box(&rate), black_box(given), o)
                    .unwrap()
            })
        });
    }
    group.bench_function("smoothed_fixes_1hz", |b| {
        let mut steps: Vec<Step> = Vec::with_capacity(N + fixes.len());
        b.iter(|| {
            steps.clear();
            let mut f = Fusion::new(FusionConfig::default()).unwrap();
            let o = outputs(&mut out);
            f.process_block_recording(black_box(&t), black_box(&rate), &fixes, o, |s| {
                steps.push(s)
            })
            .unwrap();
            smooth(&mut steps)
        })
    });
    group.finish();
}

criterion_group!(benches, filter);

fn main() {
    common::print_cpu_model();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
