//! Criterion benches: the full pipeline and each stage over 1,000,000-sample blocks, and one
//! `update`, reported as elements per second; beside them, the `combined` algorithm written as
//! one straightforward loop (no validation, gaps or options), the yardstick of
//! `benches/compare.py`'s Numba version.

use criterion::{criterion_group, BenchmarkId, Criterion, Throughput};
use gyrocore::*;
use std::hint::black_box;

mod common;

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
    // `tuned` under the rest tracker (the general chain wrapped in `Tracked`), no speed.
    let tracked = PipelineConfig {
        rest_tracker: Some(RestTrackerConfig::default()),
        ..Preset::Tuned.config()
    };
    let configs = Preset::ALL
        .iter()
        .map(|p| (p.name(), p.config()))
        .chain([("combined_cw_ccw", split), ("tuned_track_rests", tracked)]);
    for (name, mut config) in configs {
        config.correction.bias = StaticBias::Fixed(0.01);
        let (mut h, mut r, mut d) = (vec![0.0; N], vec![0.0; N], vec![0.0; N]);
        group.bench_with_input(BenchmarkId::from_parameter(name), &config, |b, &config| {
            b.iter(|| run_pipeline(config, &t, &rate, Outputs::all(&mut h, &mut r, &mut d)))
        });
    }
    let mut config = Preset::Combined.config();
    config.correction.bias = StaticBias::Fixed(0.01);
    let (mut h, mut r, mut d) = (vec![0.0; N], vec![0.0; N], vec![0.0; N]);
    let (mut sh, mut sr, mut sd) = (vec![0.0; N], vec![0.0; N], vec![0.0; N]);
    run_pipeline(config, &t, &rate, Outputs::all(&mut h, &mut r, &mut d));
    for closed in [false, true] {
        let run = [
            straightforward_combined::<false>,
            straightforward_combined::<true>,
        ][closed as usize];
        run(&t, &rate, &mut sh, &mut sr, &mut sd, &config);
        let worst = h
            .iter()
            .zip(&sh)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-9,
            "the straightforward loop (closed form: {closed}) differs by {worst} rad"
        );
    }
    let (mut ch, mut cr, mut cd) = (vec![0.0; N], vec![0.0; N], vec![0.0; N]);
    let mut plain = || {
        straightforward_combined::<false>(
            black_box(&t),
            black_box(&rate),
            &mut sh,
            &mut sr,
            &mut sd,
            &config,
        )
    };
    let mut closed = || {
        straightforward_combined::<true>(
            black_box(&t),
            black_box(&rate),
            &mut ch,
            &mut cr,
            &mut cd,
            &config,
        )
    };
    group.bench_function("straightforward_combined", |b| b.iter(&mut plain));
    group.bench_function("straightforward_combined_closed_form", |b| {
        b.iter(&mut closed)
    });
    group.finish();
    let mut engine = || run_pipeline(config, &t, &rate, Outputs::all(&mut h, &mut r, &mut d));
    if common::measuring() {
        let names = ["combined", "straightforward_combined"];
        common::interleaved(names, N, &mut engine, &mut plain);
        let names = ["combined", "straightforward_combined_closed_form"];
        common::interleaved(names, N, &mut engine, &mut closed);
    }

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

/// One block through a fresh pipeline of `config`, into `out`: what each pipeline bench times.
fn run_pipeline(config: PipelineConfig, t: &[f64], rate: &[f64], out: Outputs<'_>) {
    let mut p = Pipeline::new(config).unwrap();
    p.process_block(black_box(t), black_box(rate), None, out)
        .unwrap();
}

/// `benches/reference.py` (static bias, Hong eq 3 and 12, HDR eq 7-13, trapezoid rule) as a
/// plain Rust loop, statement for statement: what the pipeline would be without validation, gap
/// handling, a rest window or stages that may be off. Checked against the pipeline above.
/// `CLOSED`: eq 7 and 13 in closed form as the pipeline computes them (`rust/src/lag_free.rs`;
/// `reference.combined(..., lag_free=True)`), the de-lag's division out of line.
fn straightforward_combined<const CLOSED: bool>(
    t: &[f64],
    rate: &[f64],
    heading_out: &mut [f64],
    rate_out: &mut [f64],
    drift_out: &mut [f64],
    config: &PipelineConfig,
) {
    let c = &config.correction;
    let StaticBias::Fixed(bias) = c.bias else {
        panic!("a fixed bias")
    };
    let threshold = config.threshold.unwrap().threshold;
    let tau = config.lowpass.unwrap().tau;
    let hdr = config.hdr.unwrap();
    let (mut last_t, mut lp_prev, mut dl_prev, mut integ_prev, mut heading) =
        (0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut integ, mut step_sum, mut step_duration, mut elapsed, mut dec_prev) =
        (0.0f64, 0.0, 0.0, 0.0, 0.0);
    let (mut dec_started, mut prev_sign, mut reps) = (false, 2i32, 0i32);
    let n = t.len();
    let (rate, heading_out, rate_out, drift_out) = (
        &rate[..n],
        &mut heading_out[..n],
        &mut rate_out[..n],
        &mut drift_out[..n],
    );
    for i in 0..n {
        let dt = if i == 0 { 0.0 } else { t[i] - last_t };
        last_t = t[i];
        let mut r = c.scale * (rate[i] - bias) + c.offset;
        r *= c.c_ccw;
        if r.abs() < threshold {
            r = 0.0;
        }
        let corrected = r;
        let lp = if i == 0 || CLOSED {
            corrected
        } else {
            let inv = 1.0 / (dt + tau);
            corrected * (dt * inv) + lp_prev * (tau * inv)
        };
        lp_prev = lp;
        let applied = integ;
        step_sum += corrected * dt;
        step_duration += dt;
        elapsed += dt;
        if step_duration > 0.0 && elapsed >= hdr.interval - 0.5 * dt {
            let mean = step_sum / step_duration;
            let duration = step_duration;
            let carry = elapsed - hdr.interval;
            step_sum = 0.0;
            step_duration = 0.0;
            elapsed = if carry.abs() < 0.5 * hdr.interval {
                carry
            } else {
                0.0
            };
            let filtered = if dec_started {
                let inv = 1.0 / (duration + hdr.tau);
                mean * (duration * inv) + dec_prev * (hdr.tau * inv)
            } else {
                dec_started = true;
                mean
            };
            dec_prev = filtered;
            let w = filtered + integ;
            let s = if w > 0.0 {
                1
            } else if w < 0.0 {
                -1
            } else {
                0
            };
            reps = if s == prev_sign { reps + 1 } else { 1 };
            prev_sign = s;
            if filtered.abs() < hdr.turn_threshold {
                let att = (1.0 + hdr.c1) / (1.0 + hdr.c1 * f64::from(reps).powf(hdr.c2));
                integ -= f64::from(s) * att * hdr.increment;
            }
        }
        let w = lp + applied;
        let out = if i == 0 || (CLOSED && applied == dl_prev) {
            w
        } else if CLOSED {
            w + delagged_step(tau, dt, applied - dl_prev)
        } else {
            w + tau / dt * (w - dl_prev)
        };
        dl_prev = if CLOSED { applied } else { w };
        if i > 0 {
            heading += 0.5 * (out + integ_prev) * dt;
        }
        integ_prev = out;
        heading_out[i] = heading;
        rate_out[i] = out;
        drift_out[i] = -applied;
    }
}

/// Eq 13's `tau / T_i jump`, out of line: taken once per HDR step at most (inline, the compiler
/// divides on every sample and selects).
#[cold]
#[inline(never)]
fn delagged_step(tau: f64, dt: f64, jump: f64) -> f64 {
    tau / dt * jump
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

fn main() {
    common::print_cpu_model();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
