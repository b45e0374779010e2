//! How a new stage is added: one kernel (a validated `Copy` config, a small `Copy` state, one
//! `step`), composed with the crate's kernels by putting it in a tuple. This file defines one
//! outside the crate, a rate limit, and runs it in a chain and on its own; inside the crate the
//! stage would be a file in `rust/src` and one more element in a tuple of
//! `rust/src/pipeline/engine.rs`.

use gyrocore::integrate::TrapezoidKernel;
use gyrocore::kernel::{Kernel, Signal, Validated};
use gyrocore::threshold::ThresholdKernel;
use gyrocore::{Error, IntegratorConfig, Stage, Streaming, ThresholdConfig};

/// The stage's settings: the largest rate it passes [rad/s]. (With the `serde` feature, configs
/// and states serialise, so that a pipeline can be stored and resumed.)
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct RateLimitConfig {
    limit: f64,
}

impl RateLimitConfig {
    /// Every stage checks its settings once, when it is built, naming what is wrong.
    fn validate(&self) -> Result<(), Error> {
        if self.limit > 0.0 {
            Ok(())
        } else {
            Err(Error::InvalidParameter {
                name: "rate_limit",
                value: self.limit,
                valid: "> 0",
            })
        }
    }
}

/// Limits the rate to `[-limit, limit]` (a sensor's measuring range) and counts the samples it
/// limited: its state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct RateLimitKernel;

impl Kernel for RateLimitKernel {
    type Config = RateLimitConfig;
    type State = u64;

    fn start(_config: &RateLimitConfig) -> u64 {
        0
    }

    fn first(config: &RateLimitConfig, limited: &mut u64, x: Signal) -> Signal {
        Self::step(config, limited, 0.0, x)
    }

    #[inline(always)]
    fn step(config: &RateLimitConfig, limited: &mut u64, _dt: f64, x: Signal) -> Signal {
        let rate = x.rate.clamp(-config.limit, config.limit);
        *limited += u64::from(rate != x.rate);
        Signal { rate, ..x }
    }
}

/// What makes the kernel a stand-alone stage too (`Streaming<RateLimitKernel>`).
impl Validated for RateLimitKernel {
    type Settings = RateLimitConfig;

    fn configure(settings: RateLimitConfig) -> Result<RateLimitConfig, Error> {
        settings.validate()?;
        Ok(settings)
    }
}

/// A chain with the new stage between the dead band and the trapezoid rule: the tuple is itself
/// a kernel, with one config and one state.
type Chain = (ThresholdKernel, RateLimitKernel, TrapezoidKernel);

/// Runs `C` over `(t, rate)` samples as the pipeline's driver does: `first`, then `step` with
/// the interval; returns the headings and the final state.
fn run<C: Kernel>(config: &C::Config, samples: &[(f64, f64)]) -> (Vec<f64>, C::State) {
    let mut state = C::start(config);
    let mut headings = Vec::new();
    let mut previous = None;
    for &(t, rate) in samples {
        let x = Signal::reading(rate, f64::NAN);
        let y = match previous {
            None => C::first(config, &mut state, x),
            Some(p) => C::step(config, &mut state, t - p, x),
        };
        previous = Some(t);
        headings.push(y.heading);
    }
    (headings, state)
}

fn samples() -> Vec<(f64, f64)> {
    (0..1000)
        .map(|i| (i as f64 * 0.01, 2.0 * (i as f64 * 0.02).sin()))
        .collect()
}

#[test]
fn the_new_stage_runs_in_a_chain() {
    let threshold = ThresholdConfig { threshold: 0.01 };
    let integrator = IntegratorConfig::default();
    let limit = RateLimitConfig { limit: 1.5 };
    let samples = samples();
    let (headings, (_, limited, _)) = run::<Chain>(&(threshold, limit, integrator), &samples);

    // The same heading by hand: dead band, limit, trapezoid rule.
    let rates: Vec<f64> = samples
        .iter()
        .map(|&(_, r)| {
            if r.abs() < 0.01 {
                0.0
            } else {
                r.clamp(-1.5, 1.5)
            }
        })
        .collect();
    let mut heading = 0.0;
    for i in 1..samples.len() {
        heading += 0.5 * (rates[i] + rates[i - 1]) * (samples[i].0 - samples[i - 1].0);
        assert_eq!(headings[i], heading, "sample {i}");
    }
    let expected = samples.iter().filter(|&&(_, r)| r.abs() > 1.5).count();
    assert!(expected > 0);
    assert_eq!(limited, expected as u64);

    // A limit above every rate leaves the chain's heading as it is without the stage.
    let wide = RateLimitConfig { limit: 10.0 };
    let (with, _) = run::<Chain>(&(threshold, wide, integrator), &samples);
    let (without, _) =
        run::<(ThresholdKernel, TrapezoidKernel)>(&(threshold, integrator), &samples);
    assert_eq!(with, without);
}

#[test]
fn the_new_stage_stands_alone_and_checks_its_settings() {
    let mut stage = Streaming::<RateLimitKernel>::new(RateLimitConfig { limit: 1.0 }).unwrap();
    assert_eq!(stage.update(0.0, 3.0), 1.0);
    assert_eq!(stage.update(0.1, -0.5), -0.5);
    assert_eq!(stage.update(0.2, -2.0), -1.0);
    let err = Streaming::<RateLimitKernel>::new(RateLimitConfig { limit: 0.0 }).unwrap_err();
    assert!(err.to_string().contains("rate_limit"), "{err}");
}
