//! The invariants every stage and the pipeline keep (DESIGN.md): a block equals repeated
//! `update`, any chunking gives bit-identical output, `reset` equals a fresh stage, a clone (and a
//! serde snapshot) taken mid-stream continues identically. Checked on random irregular streams.

mod common;

use common::bits;
use gyrocore::*;
use proptest::prelude::*;

/// Irregular, strictly increasing timestamps starting at a large (epoch-like) offset, and rates.
fn stream() -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
    (1usize..400, any::<u64>()).prop_map(|(n, seed)| {
        let mut s = seed | 1;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut t = Vec::with_capacity(n);
        let mut now = 1.65e9;
        for _ in 0..n {
            now += 0.001 + 0.3 * next();
            t.push(now);
        }
        let rate = (0..n)
            .map(|_| (next() - 0.5) * 0.2 + if next() < 0.1 { 1.5 } else { 0.0 })
            .collect();
        (t, rate)
    })
}

fn configs() -> Vec<PipelineConfig> {
    let mut out: Vec<PipelineConfig> = Preset::ALL.iter().map(|p| p.config()).collect();
    let mut measured = Preset::Combined.config();
    measured.correction.bias = StaticBias::Leading { duration: 3.0 };
    measured.correction.c_cw = 1.01;
    measured.integrator.method = Method::Rectangle;
    out.push(measured);
    // Noise-scaled dead band and bound, and the settings that may be infinite.
    let mut scaled = measured;
    scaled.noise_scaled = NoiseScaled {
        threshold_sigmas: Some(0.5),
        hdr_bound_sigmas: Some(2.0),
    };
    scaled.input.gap_limit = f64::INFINITY;
    scaled.hdr = Some(HdrConfig {
        turn_threshold: f64::INFINITY,
        max_correction: 1e-3,
        ..HdrConfig::table_iii()
    });
    out.push(scaled);
    // A low-pass with no lag: its weight on the previous output, and the de-lag's on the
    // difference, are 0 (a non-finite reading must still reach the heading: 0 * inf is NaN).
    // HDR's step means take the same tau (the rule of `PipelineConfig::validate`).
    out.push(PipelineConfig {
        lowpass: Some(LowPassConfig { tau: 0.0 }),
        hdr: Some(HdrConfig {
            tau: 0.0,
            ..HdrConfig::table_iii()
        }),
        ..Preset::Combined.config()
    });
    out
}

fn run_updates(p: &mut Pipeline, t: &[f64], r: &[f64]) -> Vec<Output> {
    t.iter().zip(r).map(|(&a, &b)| p.update(a, b)).collect()
}

fn run_block(p: &mut Pipeline, t: &[f64], r: &[f64]) -> Vec<Output> {
    common::try_block(p, t, r).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn block_equals_update_and_chunking_is_bit_identical((t, r) in stream(), cuts in proptest::collection::vec(0usize..400, 0..6)) {
        for config in configs() {
            let whole = bits(&run_updates(&mut Pipeline::new(config).unwrap(), &t, &r));
            prop_assert_eq!(&bits(&run_block(&mut Pipeline::new(config).unwrap(), &t, &r)), &whole);
            let mut cuts: Vec<usize> = cuts.iter().map(|c| c % (t.len() + 1)).collect();
            cuts.sort_unstable();
            let mut p = Pipeline::new(config).unwrap();
            let mut chunked = Vec::new();
            let mut start = 0;
            for end in cuts.into_iter().chain([t.len()]) {
                chunked.extend(run_block(&mut p, &t[start..end], &r[start..end]));
                start = end;
            }
            prop_assert_eq!(bits(&chunked), whole);
        }
    }

    #[test]
    fn reset_equals_fresh_and_clones_continue_identically((t, r) in stream(), at in 0usize..400) {
        for config in configs() {
            let at = at % (t.len() + 1);
            let fresh = Pipeline::new(config).unwrap();
            let mut used = fresh.clone();
            run_updates(&mut used, &t, &r);
            used.reset();
            prop_assert_eq!(&used, &fresh);

            let mut a = Pipeline::new(config).unwrap();
            run_updates(&mut a, &t[..at], &r[..at]);
            let mut b = a.clone();
            prop_assert_eq!(bits(&run_updates(&mut a, &t[at..], &r[at..])), bits(&run_updates(&mut b, &t[at..], &r[at..])));
        }
    }

    #[test]
    fn each_stage_block_equals_update_and_resets((t, r) in stream()) {
        fn check<S: Stage<Output = f64> + Clone + PartialEq + core::fmt::Debug>(fresh: S, t: &[f64], r: &[f64]) {
            let mut a = fresh.clone();
            let updates: Vec<f64> = t.iter().zip(r).map(|(&x, &y)| a.update(x, y)).collect();
            let mut b = fresh.clone();
            let mut block = vec![0.0; t.len()];
            b.process_block(t, r, &mut block).unwrap();
            assert_eq!(updates.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), block.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
            a.reset();
            assert_eq!(a, fresh);
        }
        check(Correction::new(CorrectionConfig { bias: StaticBias::Leading { duration: 2.0 }, ..Default::default() }).unwrap(), &t, &r);
        check(Threshold::new(ThresholdConfig { threshold: 0.05 }).unwrap(), &t, &r);
        check(LowPass::new(LowPassConfig { tau: 0.75 }).unwrap(), &t, &r);
        check(DeLag::new(LowPassConfig { tau: 0.75 }).unwrap(), &t, &r);
        check(Hdr::new(HdrConfig::table_iii()).unwrap(), &t, &r);
        check(Integrator::new(IntegratorConfig::default()).unwrap(), &t, &r);
    }

    #[test]
    fn finite_input_gives_finite_output((t, r) in stream()) {
        for config in configs() {
            for o in run_block(&mut Pipeline::new(config).unwrap(), &t, &r) {
                prop_assert!(o.heading.is_finite() && o.rate.is_finite() && o.drift.is_finite());
            }
        }
    }

    #[test]
    fn a_known_constant_bias_is_removed_exactly((t, _r) in stream(), bias in -0.5f64..0.5) {
        for preset in Preset::ALL {
            let mut config = preset.config();
            config.correction.bias = StaticBias::Fixed(bias);
            let out = run_block(&mut Pipeline::new(config).unwrap(), &t, &vec![bias; t.len()]);
            if preset == Preset::Raw {
                continue;
            }
            prop_assert!(out.iter().all(|o| o.heading == 0.0 && o.drift == 0.0), "{:?}", preset);
        }
    }
}

#[cfg(feature = "serde")]
proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn serde_snapshot_mid_stream_continues_bit_identically((t, r) in stream(), at in 0usize..400) {
        for config in configs() {
            let at = at % (t.len() + 1);
            let mut a = Pipeline::new(config).unwrap();
            run_updates(&mut a, &t[..at], &r[..at]);
            let mut b: Pipeline = serde_json::from_str(&serde_json::to_string(&a).unwrap()).unwrap();
            prop_assert_eq!(&b, &a);
            prop_assert_eq!(bits(&run_updates(&mut a, &t[at..], &r[at..])), bits(&run_updates(&mut b, &t[at..], &r[at..])));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Blocks are checked while they are processed (one pass): a block with one bad sample
    /// anywhere, as the first block or after a good one, gets the error `check_block` names and
    /// leaves the pipeline exactly as it was.
    #[test]
    fn a_bad_sample_anywhere_rejects_the_block_and_changes_nothing(
        (t, r) in stream(), at in 0usize..400, fault in 0usize..6, prefix in 0usize..3,
    ) {
        let at = at % t.len();
        let (mut t, mut r) = (t, r);
        match fault {
            0 => t[at] = f64::NAN,
            1 => t[at] = f64::INFINITY,
            2 => t[at] = if at > 0 { t[at - 1] } else { f64::NEG_INFINITY },
            3 => t[at] = if at > 0 { t[at - 1] - 0.5 } else { f64::NAN },
            4 => r[at] = f64::NAN,
            _ => r[at] = f64::NEG_INFINITY,
        }
        let split = (prefix * t.len() / 4).min(at);
        for config in configs() {
            let mut p = Pipeline::new(config).unwrap();
            run_block(&mut p, &t[..split], &r[..split]);
            let before = p.clone();
            let (t, r) = (&t[split..], &r[split..]);
            // a stream names a step back as a clock's jump (the way on: restart_clock)
            let expected = match check_block(t, r, None, p.last_time(), true).unwrap_err() {
                Error::NotIncreasing { index, previous, value } if value < previous => {
                    Error::ClockStepsBack { index, previous, value }
                }
                e => e,
            };
            let error = common::try_block(&mut p, t, r).unwrap_err();
            // Compared as text: a NaN in the error's `value` is not equal to itself.
            prop_assert_eq!(format!("{error:?}"), format!("{expected:?}"));
            prop_assert_eq!(&p, &before);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Non-finite readings the policy holds or skips, and gaps bridged or reset, anywhere in a
    /// block: the block still equals repeated `update`, in any chunking, and reports the same.
    #[test]
    fn held_skipped_and_gapped_samples_give_what_update_gives(
        (t, r) in stream(),
        bad in proptest::collection::vec((0usize..400, 0usize..3), 0..8),
        gaps in proptest::collection::vec(0usize..400, 0..4),
        cut in 0usize..400,
    ) {
        let (mut t, mut r) = (t, r);
        let n = t.len();
        for (at, kind) in bad {
            r[at % n] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY][kind];
        }
        for at in gaps {
            // Longer than the 2 s default gap limit (the stream's intervals are below 0.31 s).
            for x in &mut t[at % n..] {
                *x += 3.0;
            }
        }
        let cut = cut % (n + 1);
        for base in configs() {
            for non_finite in [NonFinite::Hold, NonFinite::Skip] {
                for gap_action in [GapAction::Bridge, GapAction::Reset] {
                    let mut config = base;
                    config.input.non_finite = non_finite;
                    config.input.gap_action = gap_action;
                    let mut a = Pipeline::new(config).unwrap();
                    let whole = bits(&run_updates(&mut a, &t, &r));
                    let mut b = Pipeline::new(config).unwrap();
                    let mut chunked = run_block(&mut b, &t[..cut], &r[..cut]);
                    chunked.extend(run_block(&mut b, &t[cut..], &r[cut..]));
                    prop_assert_eq!(bits(&chunked), whole);
                    prop_assert_eq!(b.report(), a.report());
                    prop_assert_eq!(&b, &a);
                }
            }
        }
    }
}

#[test]
fn zero_rate_keeps_the_heading_constant() {
    for preset in Preset::ALL {
        let mut config = preset.config();
        config.integrator.initial_heading = 1.25;
        let t: Vec<f64> = (0..500).map(|i| i as f64 * 0.05).collect();
        let out = run_block(&mut Pipeline::new(config).unwrap(), &t, &vec![0.0; t.len()]);
        assert!(out.iter().all(|o| o.heading == 1.25), "{preset:?}");
    }
}

#[test]
fn a_bad_block_is_rejected_whole_with_the_first_bad_index() {
    let mut p = Pipeline::new(Preset::Hdr.config()).unwrap();
    let before = p.clone();
    let mut out = vec![0.0; 4];
    let (mut o2, mut o3) = (out.clone(), out.clone());
    let mut bad = |t: &[f64], r: &[f64], p: &mut Pipeline| {
        p.process_block(t, r, None, Outputs::all(&mut out, &mut o2, &mut o3))
            .unwrap_err()
    };
    assert_eq!(
        bad(&[0.0, 1.0, 1.0, 2.0], &[0.0; 4], &mut p),
        Error::NotIncreasing {
            index: 2,
            previous: 1.0,
            value: 1.0
        }
    );
    assert!(matches!(
        bad(&[0.0, 1.0, 2.0, 3.0], &[0.0, f64::NAN, 0.0, 0.0], &mut p),
        Error::NonFinite {
            what: "rate",
            index: 1,
            ..
        }
    ));
    assert!(matches!(
        bad(&[0.0, 1.0, f64::INFINITY, 3.0], &[0.0; 4], &mut p),
        Error::NonFinite {
            what: "t",
            index: 2,
            ..
        }
    ));
    assert!(matches!(
        bad(&[0.0, 1.0, 2.0, 3.0], &[0.0; 3], &mut p),
        Error::LengthMismatch { what: "rate", .. }
    ));
    assert_eq!(p, before, "nothing may be processed from a rejected block");
    // Across blocks: the next block must start after the last timestamp.
    let mut q = Pipeline::new(Preset::Hdr.config()).unwrap();
    common::try_block(&mut q, &[0.0, 1.0, 2.0, 3.0], &[0.0; 4]).unwrap();
    let err = common::try_block(&mut q, &[3.0, 4.0, 5.0, 6.0], &[0.0; 4]).unwrap_err();
    assert_eq!(
        err,
        Error::NotIncreasing {
            index: 0,
            previous: 3.0,
            value: 3.0
        }
    );
}

#[test]
fn a_temperature_model_without_temperature_is_an_error() {
    let mut config = Preset::Raw.config();
    config.correction.temperature = Some(TemperatureScale {
        slope: 0.0,
        offset: 0.0,
    });
    let mut p = Pipeline::new(config).unwrap();
    let (mut h, mut r, mut d) = (vec![0.0; 1], vec![0.0; 1], vec![0.0; 1]);
    let err = p
        .process_block(&[0.0], &[0.0], None, Outputs::all(&mut h, &mut r, &mut d))
        .unwrap_err();
    assert_eq!(err, Error::MissingTemperature);
}

#[test]
fn presets_are_valid_and_named() {
    for preset in Preset::ALL {
        Pipeline::new(preset.config()).unwrap();
        assert_eq!(Preset::from_name(preset.name()), Some(preset));
    }
    assert_eq!(Preset::from_name("recommended"), Some(Preset::RECOMMENDED));
    assert_eq!(Preset::from_name("nope"), None);
    let hdr = Preset::Hdr.config().hdr.unwrap();
    assert!((hdr.increment.to_degrees() - 0.0422).abs() < 1e-12);
    assert!((hdr.turn_threshold.to_degrees() - 0.564).abs() < 1e-12);
}

#[test]
fn hdr_waits_for_the_end_of_the_rest_window() {
    let mut p = Pipeline::new(common::with_window(Preset::Hdr, 0.0, 10.0)).unwrap();
    let t: Vec<f64> = (0..=150).map(|i| i as f64 * 0.1).collect();
    // A drifting reading during the rest: HDR must not act on it while the bias is measured.
    let rate: Vec<f64> = t.iter().map(|&x| 0.001 * x).collect();
    let out = run_updates(&mut p, &t, &rate);
    assert!(out[..=100].iter().all(|o| o.drift == 0.0));
    assert!(
        out[112..].iter().any(|o| o.drift != 0.0),
        "HDR acts after the window"
    );
}
