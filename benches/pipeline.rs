//! Criterion benches: the full pipeline and each stage over 1,000,000-sample blocks, and one
//! `update`, reported as elements per second.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use gyrocore::*;
use std::hint::black_box;

const N: usize = 1_000_000;

fn samples() -> (Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = (0..N).map(|i| 1.65e9 + i as f64 * 0.01).collect();
    let rate: Vec<f64> = (0..N)
        .map(|i| 0.01 + 0.2 * ((i as f64) * 1e-3).sin())
        .collect();
    (t, rate)
}

fn pipeline(c: &mut Criterion) {
    let (t, rate) = samples();
    let mut group = c.benchmark_group("pipeline_block");
    group.throughput(Throughput::Elements(N as u64));
    // The presets, and `combined` with a factor per turn direction (FOG eq 3-4), which compiles
    // to another loop (see `Correction::apply_directed`).
    let mut split = Preset::Combined.config();
    split.correction.c_cw = 1.01;
    let configs = Preset::ALL
        .iter()
        .map(|p| (p.name(), p.config()))
        .chain([("combined_cw_ccw", split)]);
    for (name, mut config) in configs {
        config.correction.bias = StaticBias::Fixed(0.01);
        let (mut h, mut r, mut d) = (vec![0.0; N], vec![0.0; N], vec![0.0; N]);
        group.bench_with_input(BenchmarkId::from_parameter(name), &config, |b, &config| {
            b.iter(|| {
                let mut p = Pipeline::new(config).unwrap();
                let out = Outputs {
                    heading: &mut h,
                    rate: &mut r,
                    drift: &mut d,
                };
                p.process_block(black_box(&t), black_box(&rate), None, out)
                    .unwrap();
            })
        });
    }
    group.finish();

    let mut group = c.benchmark_group("pipeline_update");
    group.throughput(Throughput::Elements(1));
    let mut p = Pipeline::new(Preset::Combined.config()).unwrap();
    let mut now = 0.0;
    group.bench_function("combined", |b| {
        b.iter(|| {
            now += 0.01;
            black_box(p.update(black_box(now), black_box(0.01)))
        })
    });
    group.finish();
}

fn stages(c: &mut Criterion) {
    let (t, rate) = samples();
    let mut out = vec![0.0; N];
    let mut group = c.benchmark_group("stage_block");
    group.throughput(Throughput::Elements(N as u64));
    macro_rules! bench {
        ($name:expr, $make:expr) => {
            group.bench_function($name, |b| {
                b.iter(|| {
                    let mut s = $make;
                    s.process_block(black_box(&t), black_box(&rate), &mut out)
                        .unwrap();
                })
            });
        };
    }
    bench!(
        "correction",
        Correction::new(CorrectionConfig {
            bias: StaticBias::Fixed(0.01),
            ..Default::default()
        })
        .unwrap()
    );
    bench!(
        "threshold",
        Threshold::new(ThresholdConfig { threshold: 0.005 }).unwrap()
    );
    bench!(
        "lowpass",
        LowPass::new(LowPassConfig { tau: 0.75 }).unwrap()
    );
    bench!("delag", DeLag::new(LowPassConfig { tau: 0.75 }).unwrap());
    bench!("hdr", Hdr::new(HdrConfig::table_iii()).unwrap());
    bench!(
        "integrator",
        Integrator::new(IntegratorConfig::default()).unwrap()
    );
    group.finish();
}

criterion_group!(benches, pipeline, stages);
criterion_main!(benches);
