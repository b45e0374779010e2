//! Arbitrary configurations and samples (NaN, infinities, huge and negative values, timestamps out
//! of order) through the pipeline. Nothing may panic; a rejected block must leave the state as it
//! was; a valid block must equal the same samples fed one `update` at a time.
#![no_main]

use arbitrary::Arbitrary;
use gyrocore::*;
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
struct Input {
    bias: (u8, f64, f64),
    scale: f64,
    offset: f64,
    c_cw: f64,
    c_ccw: f64,
    temperature: Option<(f64, f64)>,
    threshold: Option<f64>,
    lowpass: Option<f64>,
    delag: bool,
    hdr: Option<(f64, f64, f64, f64, f64, f64, f64)>,
    noise_scaled: (Option<f64>, Option<f64>),
    #[allow(clippy::type_complexity)]
    rest_tracker: Option<(f64, f64, f64, f64, f64, f64, f64, Option<f64>)>,
    rectangle: bool,
    initial_heading: f64,
    non_finite: u8,
    gap_limit: f64,
    reset_on_gap: bool,
    samples: Vec<(f64, f64, f64)>,
    split: u16,
}

fn config(i: &Input) -> PipelineConfig {
    PipelineConfig {
        correction: CorrectionConfig {
            bias: match i.bias.0 % 3 {
                0 => StaticBias::Fixed(i.bias.1),
                1 => StaticBias::Window {
                    start: i.bias.1,
                    end: i.bias.2,
                },
                _ => StaticBias::Leading { duration: i.bias.1 },
            },
            scale: i.scale,
            offset: i.offset,
            c_cw: i.c_cw,
            c_ccw: i.c_ccw,
            temperature: i
                .temperature
                .map(|(slope, offset)| TemperatureScale { slope, offset }),
        },
        threshold: i.threshold.map(|threshold| ThresholdConfig { threshold }),
        lowpass: i.lowpass.map(|tau| LowPassConfig { tau }),
        delag: i.delag,
        hdr: i.hdr.map(
            |(increment, turn_threshold, c1, c2, interval, tau, max_correction)| HdrConfig {
                increment,
                turn_threshold,
                c1,
                c2,
                interval,
                tau,
                max_correction,
            },
        ),
        integrator: IntegratorConfig {
            method: if i.rectangle {
                Method::Rectangle
            } else {
                Method::Trapezoid
            },
            initial_heading: i.initial_heading,
        },
        input: InputPolicy {
            non_finite: match i.non_finite % 3 {
                0 => NonFinite::Error,
                1 => NonFinite::Hold,
                _ => NonFinite::Skip,
            },
            gap_limit: i.gap_limit,
            gap_action: if i.reset_on_gap {
                GapAction::Reset
            } else {
                GapAction::Bridge
            },
        },
        noise_scaled: NoiseScaled {
            threshold_sigmas: i.noise_scaled.0,
            hdr_bound_sigmas: i.noise_scaled.1,
        },
        rest_tracker: i.rest_tracker.map(
            |(
                block,
                min_duration,
                noise_ratio,
                change_sigmas,
                speed_threshold,
                bias_walk,
                gate_sigmas,
                noise,
            )| {
                RestTrackerConfig {
                    block,
                    min_duration,
                    noise_ratio,
                    change_sigmas,
                    speed_threshold,
                    bias_walk,
                    gate_sigmas,
                    noise,
                }
            },
        ),
    }
}

fn run_block(
    p: &mut Pipeline,
    t: &[f64],
    r: &[f64],
    temp: Option<&[f64]>,
) -> Result<Vec<[u64; 3]>, Error> {
    let n = t.len();
    let (mut h, mut ra, mut d) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    p.process_block(t, r, temp, Outputs::all(&mut h, &mut ra, &mut d))?;
    Ok((0..n)
        .map(|k| [h[k].to_bits(), ra[k].to_bits(), d[k].to_bits()])
        .collect())
}

fuzz_target!(|input: Input| {
    let Ok(mut pipeline) = Pipeline::new(config(&input)) else {
        return;
    };
    let t: Vec<f64> = input.samples.iter().map(|s| s.0).collect();
    let r: Vec<f64> = input.samples.iter().map(|s| s.1).collect();
    let temp: Vec<f64> = input.samples.iter().map(|s| s.2).collect();
    let temp = input.temperature.map(|_| temp.as_slice());

    // Per-sample updates never panic, whatever the input.
    let mut by_update = pipeline.clone();
    let updates: Vec<[u64; 3]> = (0..t.len())
        .map(|k| {
            let o = by_update.update_with_temperature(t[k], r[k], temp.map(|x| x[k]));
            [o.heading.to_bits(), o.rate.to_bits(), o.drift.to_bits()]
        })
        .collect();

    // A block is either rejected whole, leaving the state untouched, or equals the updates.
    let before = pipeline.clone();
    match run_block(&mut pipeline, &t, &r, temp) {
        Err(_) => assert_eq!(format!("{pipeline:?}"), format!("{before:?}")),
        Ok(out) => {
            assert_eq!(out, updates);
            // Every heading and drift of an accepted block is finite (a skipped sample's rate is
            // NaN by design).
            let finite = |bits: u64| f64::from_bits(bits).is_finite();
            assert!(out.iter().all(|o| finite(o[0]) && finite(o[2])), "{out:?}");
            // And any split into two blocks gives the same bits.
            let mut split = before.clone();
            let at = usize::from(input.split) % (t.len() + 1);
            let mut joined =
                run_block(&mut split, &t[..at], &r[..at], temp.map(|x| &x[..at])).unwrap();
            joined
                .extend(run_block(&mut split, &t[at..], &r[at..], temp.map(|x| &x[at..])).unwrap());
            assert_eq!(joined, out);
        }
    }
});
