//! Criterion bench of the heading-fix filter (rust/src/fixes.rs): 1,000,000 gyro samples at
//! 100 Hz without fixes and with a fix every second (10,000 fixes), reported as gyro samples per
//! second, and the whole-log smoother (forward pass storing its knots, the backward pass, and the
//! second forward pass writing the smoothed estimates);
//! then the recommended pipeline alone against the same pipeline with its fix stage and 1 Hz
//! fixes (`FusedPipeline`), with every output and with the heading alone, in criterion and in
//! interleaved rounds (issue 18: within 10 %); last, that fused pipeline fed in small blocks, each
//! with every fix still to come (the rest of the 10,000), as a caller holding them all may do.

use criterion::{criterion_group, BenchmarkId, Criterion, Throughput};
use gyrocore::fixes_smooth::Knot;
use gyrocore::{
    smooth, Fix, FusedOutputs, FusedPipeline, Fusion, FusionConfig, FusionOutputs, Outputs,
    Pipeline, PipelineConfig, Preset, Samples, StaticBias,
};
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
    FusionOutputs::all(heading, heading_sigma, bias, scale)
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
        let mut knots: Vec<Knot> = Vec::with_capacity(fixes.len() + 1);
        b.iter(|| {
            knots.clear();
            let mut f = Fusion::new(FusionConfig::default()).unwrap();
            let o = outputs(&mut out);
            f.process_block_recording(black_box(&t), black_box(&rate), &fixes, o, |k| {
                knots.push(k)
            })
            .unwrap();
            smooth(&mut knots);
            let mut again = Fusion::new(FusionConfig::default()).unwrap();
            let o = outputs(&mut out);
            again
                .process_block_smoothed(black_box(&t), black_box(&rate), &fixes, &knots, o)
                .unwrap()
        })
    });
    group.finish();
}

/// The recommended preset with a known bias, as benches/pipeline.rs runs the presets.
fn pipeline_config() -> PipelineConfig {
    let mut config = Preset::RECOMMENDED.config();
    config.correction.bias = StaticBias::Fixed(0.01);
    config
}

/// Six columns of N samples for [`fused_run`].
fn columns() -> [Vec<f64>; 6] {
    core::array::from_fn(|_| vec![0.0; N])
}

/// A fresh pipeline over the samples into `cols`: every output, or the heading alone.
fn pipeline_run(
    config: PipelineConfig,
    t: &[f64],
    rate: &[f64],
    all: bool,
    cols: &mut [Vec<f64>; 6],
) {
    let mut p = Pipeline::new(config).unwrap();
    let [h, r, d, ..] = cols;
    let out = if all {
        Outputs::all(h, r, d)
    } else {
        Outputs::heading(h)
    };
    p.process_block(black_box(t), black_box(rate), None, out)
        .unwrap();
}

/// A fresh fused pipeline over the samples with the fixes `given`, in blocks of `size` samples
/// (each handed every fix not used yet), into `cols`: every output, or the heading alone (with the
/// corrected rate, the filter's input). Every fix must be used.
fn fused_run(
    config: PipelineConfig,
    t: &[f64],
    rate: &[f64],
    given: &[Fix],
    all: bool,
    size: usize,
    cols: &mut [Vec<f64>; 6],
) {
    let mut p = FusedPipeline::new(config, FusionConfig::default()).unwrap();
    let [h, s, b, sc, r, d] = cols;
    let (mut start, mut used) = (0, 0);
    while start < t.len() {
        let block = start..(start + size).min(t.len());
        let out = FusedOutputs {
            heading: &mut h[block.clone()],
            heading_sigma: all.then(|| &mut s[block.clone()]),
            bias: all.then(|| &mut b[block.clone()]),
            scale: all.then(|| &mut sc[block.clone()]),
            rate: &mut r[block.clone()],
            drift: all.then(|| &mut d[block.clone()]),
        };
        let samples = Samples::new(
            black_box(&t[block.clone()]),
            black_box(&rate[block.clone()]),
        );
        used += p
            .process_block(samples, black_box(&given[used..]), out)
            .unwrap();
        start = block.end;
    }
    assert_eq!(used, given.len());
}

fn fused(c: &mut Criterion) {
    let (t, rate, fixes) = samples();
    let config = pipeline_config();
    // each run its own columns, as they alternate
    let mut cols: [[Vec<f64>; 6]; 5] = core::array::from_fn(|_| columns());
    let [c_alone, c_with, c_without, c_alone_h, c_with_h] = &mut cols;
    let mut alone = || pipeline_run(config, &t, &rate, true, c_alone);
    let mut with_fixes = || fused_run(config, &t, &rate, &fixes, true, N, c_with);
    let mut without = || fused_run(config, &t, &rate, &[], true, N, c_without);
    let mut alone_h = || pipeline_run(config, &t, &rate, false, c_alone_h);
    let mut with_fixes_h = || fused_run(config, &t, &rate, &fixes, false, N, c_with_h);
    let mut group = c.benchmark_group("fused_pipeline");
    group.throughput(Throughput::Elements(N as u64));
    group.bench_function("pipeline_alone", |b| b.iter(&mut alone));
    group.bench_function("fused_no_fixes", |b| b.iter(&mut without));
    group.bench_function("fused_fixes_1hz", |b| b.iter(&mut with_fixes));
    group.bench_function("pipeline_alone_heading", |b| b.iter(&mut alone_h));
    group.bench_function("fused_fixes_1hz_heading", |b| b.iter(&mut with_fixes_h));
    group.finish();
    if common::measuring() {
        let names = ["fused_fixes_1hz", "pipeline_alone"];
        common::interleaved(names, N, &mut with_fixes, &mut alone);
        let names = ["fused_fixes_1hz", "fused_no_fixes"];
        common::interleaved(names, N, &mut with_fixes, &mut without);
        let names = ["fused_fixes_1hz_heading", "pipeline_alone_heading"];
        common::interleaved(names, N, &mut with_fixes_h, &mut alone_h);
    }
}

fn streamed(c: &mut Criterion) {
    let (t, rate, fixes) = samples();
    let config = pipeline_config();
    let mut cols = columns();
    let mut group = c.benchmark_group("fused_streamed");
    group.throughput(Throughput::Elements(N as u64));
    group.sample_size(10);
    for size in [N, 1000, 100, 1] {
        group.bench_with_input(BenchmarkId::new("block", size), &size, |b, &size| {
            b.iter(|| fused_run(config, &t, &rate, &fixes, false, size, &mut cols))
        });
    }
    group.finish();
}

criterion_group!(benches, filter, fused, streamed);

fn main() {
    common::print_cpu_model();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
