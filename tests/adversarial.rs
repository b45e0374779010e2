//! Adversarial inputs through the public API: arbitrary floats (subnormals, +-0, +-1e308, values
//! at the documented limits), arbitrary configurations and arbitrary block splits. Every call
//! returns `Ok` with finite outputs or an `Err`, never a panic; where it is `Ok`, a chunked run
//! equals one call.

mod common;

use common::bits;
use gyrocore::*;
use proptest::prelude::*;

/// A float an embedder might give: ordinary values, the special ones, and values at the limits.
fn float() -> impl Strategy<Value = f64> {
    let above = |x: f64| f64::from_bits(x.to_bits() + 1);
    let below = |x: f64| f64::from_bits(x.to_bits() - 1);
    let special = [
        0.0,
        -0.0,
        f64::from_bits(1),
        f64::MIN_POSITIVE,
        1e-300,
        MIN_INTERVAL,
        below(MIN_INTERVAL),
        1.0,
        -1.0,
        MAX_READING,
        below(MAX_READING),
        -below(MAX_READING),
        above(MAX_READING),
        MAX_TIME,
        below(MAX_TIME),
        -below(MAX_TIME),
        1e308,
        -1e308,
        f64::MAX,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ];
    prop_oneof![
        3 => -2.0..2.0f64,
        2 => proptest::sample::select(special.to_vec()),
        1 => any::<f64>(),
    ]
}

/// Mostly a value of `range`, sometimes any [`float`].
fn mostly(range: core::ops::Range<f64>) -> impl Strategy<Value = f64> {
    prop_oneof![9 => range, 1 => float()]
}

/// Samples: times from arbitrary steps (mostly forward, some not), arbitrary readings; half of
/// the streams with only ordinary steps and readings near the limits.
fn samples(max: usize) -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
    let dirty = (prop_oneof![6 => 1e-3..0.5f64, 1 => float()], float());
    let limit = f64::from_bits(MAX_READING.to_bits() - 1);
    let clean = (
        1e-3..0.5f64,
        prop_oneof![6 => -2.0..2.0f64, 1 => -limit..limit],
    );
    prop_oneof![
        proptest::collection::vec(dirty, 0..max),
        proptest::collection::vec(clean, 0..max),
    ]
    .prop_map(|v| {
        let mut now = 0.0;
        v.into_iter()
            .map(|(dt, r)| {
                now = if dt.is_finite() && (now + dt).is_finite() {
                    now + dt
                } else {
                    dt
                };
                (now, r)
            })
            .unzip()
    })
}

/// A configuration from a preset with some of its parameters replaced by arbitrary floats.
fn config() -> impl Strategy<Value = PipelineConfig> {
    (
        proptest::sample::select(Preset::ALL.to_vec()),
        proptest::collection::vec((0usize..16, float()), 0..4),
        0usize..3,
        0usize..4,
    )
        .prop_map(|(preset, edits, bias, policy)| {
            let mut c = preset.config();
            c.correction.bias = match bias {
                0 => StaticBias::Fixed(0.001),
                1 => StaticBias::Leading { duration: 0.3 },
                _ => StaticBias::Window {
                    start: 0.1,
                    end: 0.6,
                },
            };
            c.input.non_finite = [NonFinite::Error, NonFinite::Hold, NonFinite::Skip][policy % 3];
            c.input.gap_action = [GapAction::Bridge, GapAction::Reset][policy / 2];
            for (field, v) in edits {
                match field {
                    0 => c.correction.scale = v,
                    1 => c.correction.offset = v,
                    2 => c.correction.c_cw = v,
                    3 => c.correction.bias = StaticBias::Fixed(v),
                    4 => c.correction.bias = StaticBias::Leading { duration: v },
                    5 => c.threshold = Some(ThresholdConfig { threshold: v }),
                    6 => c.set_lowpass_tau(v),
                    7 => c.hdr.iter_mut().for_each(|h| h.increment = v),
                    8 => c.hdr.iter_mut().for_each(|h| h.interval = v),
                    9 => c.hdr.iter_mut().for_each(|h| h.turn_threshold = v),
                    10 => c.hdr.iter_mut().for_each(|h| h.max_correction = v),
                    11 => c.hdr.iter_mut().for_each(|h| (h.c1, h.c2) = (v, v)),
                    12 => c.integrator.initial_heading = v,
                    13 => c.input.gap_limit = v,
                    14 => c.noise_scaled.hdr_bound_sigmas = Some(v),
                    _ => {
                        c.rest_tracker = Some(RestTrackerConfig {
                            block: v.abs().min(1e6),
                            min_duration: 2.0 * v.abs().min(1e6),
                            ..Default::default()
                        })
                    }
                }
            }
            c
        })
}

fn all_finite(out: &[Output]) -> bool {
    out.iter()
        .all(|o| o.heading.is_finite() && o.drift.is_finite())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// A pipeline of any configuration `new` takes, on any samples: one call and any split give
    /// the same result; an accepted block gives finite headings, and so does every `update`.
    #[test]
    fn any_pipeline_on_any_samples((t, r) in samples(120), config in config(), cut in 0usize..120) {
        let Ok(fresh) = Pipeline::new(config) else { return Ok(()) };
        let mut whole = fresh.clone();
        let one = common::try_block(&mut whole, &t, &r);
        let cut = cut.min(t.len());
        let mut chunked = fresh.clone();
        let first = common::try_block(&mut chunked, &t[..cut], &r[..cut]);
        match (&one, first) {
            (Ok(one), Ok(mut a)) => {
                let b = common::try_block(&mut chunked, &t[cut..], &r[cut..]);
                prop_assert!(b.is_ok(), "{:?}", b);
                a.extend(b.unwrap());
                prop_assert!(all_finite(one), "{:?}", one);
                prop_assert_eq!(bits(one), bits(&a));
            }
            (Ok(_), Err(e)) => prop_assert!(false, "one call took the samples, a part did not: {e}"),
            _ => {}
        }
        let mut u = fresh;
        for (&x, &y) in t.iter().zip(&r) {
            let o = u.update(x, y);
            prop_assert!(o.heading.is_finite() && o.drift.is_finite(), "{:?} at t = {}", o, x);
        }
    }

    /// Every stand-alone stage, sample by sample and by block, on any samples.
    #[test]
    fn any_stage_on_any_samples((t, r) in samples(80), v in float(), dt in float()) {
        // `Correction` corrects any reading it is given (a NaN one gives NaN): only those within
        // the limits must come out finite.
        fn check<S: Stage<Output = f64> + Clone>(stage: Result<S, Error>, t: &[f64], r: &[f64]) {
            let Ok(fresh) = stage else { return };
            let mut a = fresh.clone();
            let updates = common::run(&mut a, t, r);
            let passes_readings = core::any::type_name::<S>().ends_with("Correction");
            let excused = |v: f64| passes_readings && (v.is_nan() || v.abs() >= MAX_READING);
            let bad = updates
                .iter()
                .zip(r)
                .position(|(x, &v)| !x.is_finite() && !excused(v));
            assert!(bad.is_none(), "{}: sample {bad:?} of t = {t:?}, rate = {r:?}: {:?}", core::any::type_name::<S>(), bad.map(|i| updates[i]));
            let mut b = fresh;
            let mut out = vec![0.0; t.len()];
            if b.process_block(t, r, &mut out).is_ok() {
                assert_eq!(out, updates);
            }
        }
        check(Correction::new(CorrectionConfig { scale: v, ..Default::default() }), &t, &r);
        check(Correction::new(CorrectionConfig { bias: StaticBias::Leading { duration: v }, ..Default::default() }), &t, &r);
        check(Threshold::new(ThresholdConfig { threshold: v }), &t, &r);
        check(LowPass::new(LowPassConfig { tau: v }), &t, &r);
        check(DeLag::new(LowPassConfig { tau: v }), &t, &r);
        check(Hdr::new(HdrConfig { interval: v, ..HdrConfig::table_iii() }), &t, &r);
        check(Hdr::new(HdrConfig { increment: v, tau: 0.0, ..HdrConfig::table_iii() }), &t, &r);
        check(Integrator::new(IntegratorConfig { initial_heading: v, ..Default::default() }), &t, &r);
        if let Ok(mut h) = Hdr::new(HdrConfig::table_iii()) {
            h.bound_correction(v);
            for (&x, &y) in t.iter().zip(&r) {
                prop_assert!(h.update(x, y).is_finite());
                prop_assert!(h.step(dt, y).is_finite());
            }
        }
        if let Ok(mut d) = Downsample::new(DownsampleConfig { interval: v }) {
            let n = t.len();
            let (mut ot, mut or) = (vec![0.0; n], vec![0.0; n]);
            if let Ok(k) = d.process_block(&t, &r, &mut ot, &mut or) {
                prop_assert!(or[..k].iter().all(|x| x.is_finite()));
            }
        }
    }

    /// The heading-fix filter: any configuration, samples and fixes; one call and a split agree,
    /// and every estimate of an accepted block is finite.
    #[test]
    fn any_fusion_on_any_samples(
        (t, r) in samples(100),
        fixes in proptest::collection::vec((float(), float(), float()), 0..8),
        edits in proptest::collection::vec((0usize..9, float()), 0..3),
        cut in 0usize..100,
    ) {
        let mut config = FusionConfig::default();
        for (field, v) in edits {
            match field {
                0 => config.arw = v,
                1 => config.bias_walk = v,
                2 => config.scale_walk = v,
                3 => config.initial_heading = v,
                4 => config.initial_heading_sigma = v,
                5 => config.initial_bias = v,
                6 => config.initial_bias_sigma = v,
                7 => config.initial_scale_sigma = v,
                _ => config.gate = v,
            }
        }
        let Ok(fresh) = Fusion::new(config) else { return Ok(()) };
        let span = t.last().copied().unwrap_or(1.0);
        let mut fixes: Vec<Fix> = fixes
            .into_iter()
            .map(|(at, heading, sigma)| Fix { t: if at.is_finite() { at.rem_euclid(span.abs().max(1.0)) } else { at }, heading, sigma })
            .collect();
        fixes.sort_by(|a, b| a.t.total_cmp(&b.t));
        let n = t.len();
        let mut cols = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        let [h, s, b, k] = &mut cols;
        let mut knots = Vec::new();
        let mut one = fresh;
        let used = one.process_block_recording(&t, &r, &fixes, FusionOutputs::all(h, s, b, k), |x| knots.push(x));
        let Ok(used) = used else { return Ok(()) };
        for col in &cols {
            prop_assert!(col.iter().all(|x| x.is_finite()), "{:?}", cols);
        }
        let cut = cut.min(n);
        let mut parts = fresh;
        let mut heading = vec![0.0; n];
        let first = parts.process_block(&t[..cut], &r[..cut], &fixes, FusionOutputs::heading(&mut heading[..cut]));
        prop_assert!(first.is_ok(), "{:?}", first);
        let first = first.unwrap();
        let second = parts.process_block(&t[cut..], &r[cut..], &fixes[first..], FusionOutputs::heading(&mut heading[cut..]));
        prop_assert_eq!(second.map(|u| u + first).ok(), Some(used));
        prop_assert_eq!(bits_of(&heading), bits_of(&cols[0]));
        smooth(&mut knots);
        let mut again = fresh;
        let [h, s, b, k] = &mut cols;
        again.process_block_smoothed(&t, &r, &fixes, &knots, FusionOutputs::all(h, s, b, k)).unwrap();
        // The smoothed sigma between knots is a difference of nearly equal terms that grow with
        // the square of the rate's integral: with rates near the limit (1e6 rad/s) it loses its
        // digits (a variance of -0.43, NaN). It is checked on ordinary rates only.
        let ordinary = r.iter().all(|x| x.abs() < 1e3);
        for (j, col) in cols.iter().enumerate() {
            let checked = j != 1 || ordinary;
            prop_assert!(!checked || col.iter().all(|x| x.is_finite()), "smoothed {:?}", cols);
        }
    }

    /// The Allan helpers on any rate, interval and factors.
    #[test]
    fn any_allan_input(rate in proptest::collection::vec(float(), 0..60), dt in float(), factors in proptest::collection::vec(0usize..40, 0..4)) {
        let mut x = vec![0.0; rate.len() + 1];
        if allan::phase_from_rate(&rate, dt, &mut x).is_ok() {
            prop_assert!(x.iter().all(|v| v.is_finite()), "{:?}", x);
            for kind in Variance::ALL {
                let (mut v, mut n) = (vec![0.0; factors.len()], vec![0u64; factors.len()]);
                if allan::variances(&x, dt, &factors, kind, &mut v, &mut n).is_ok() {
                    prop_assert!(v.iter().all(|v| v.is_finite() && *v >= 0.0), "{:?} {:?}", kind, v);
                    #[cfg(feature = "std")]
                    {
                        let (mut w, mut m) = (vec![0.0; factors.len()], vec![0u64; factors.len()]);
                        allan::variances_parallel(&x, dt, &factors, kind, 3, &mut w, &mut m).unwrap();
                        prop_assert_eq!(bits_of(&v), bits_of(&w));
                    }
                }
            }
        }
    }

    /// The Allan variances of a phase the caller gives.
    #[test]
    fn any_allan_phase(x in proptest::collection::vec(float(), 0..40), tau0 in float(), m in 0usize..12) {
        for kind in [Variance::Allan, Variance::ModifiedAllan, Variance::OverlappingHadamard] {
            if let Ok((v, _)) = allan::variance(&x, tau0, m, kind) {
                prop_assert!(v.is_finite() && v >= 0.0, "{:?}: {}", kind, v);
            }
        }
    }

    /// The static bias test, the axis projection and the rest statistics.
    #[test]
    fn any_rest_and_axis_input((t, r) in samples(60), start in float(), end in float(), up in (float(), float(), float())) {
        if let Ok(test) = static_bias_test(&t, &r, start, end) {
            prop_assert!(test.bias.is_finite());
            if let Some(s) = test.statistics {
                prop_assert!(s.noise.is_finite() && s.bias_std_error.is_finite(), "{:?}", s);
            }
        }
        if let Ok(axis) = Up::new([up.0, up.1, up.2]) {
            prop_assert!(axis.unit().iter().all(|u| u.is_finite()));
            for &v in &r {
                let p = axis.project([v, v, v]);
                prop_assert!(p.is_finite() || !v.is_finite() || v.abs() > 1e300, "{}", p);
            }
        }
    }

    /// The simulated gyro and its sampler: any configuration `validate` takes gives instants and
    /// readings without a panic or a hang.
    #[test]
    fn any_simulated_gyro(edits in proptest::collection::vec((0usize..10, float()), 0..4), seed in any::<u64>(), t in proptest::collection::vec(float(), 0..30)) {
        let mut c = GyroModelConfig::ideal(100.0);
        for (field, v) in edits {
            match field {
                0 => c.rate_hz = v,
                1 => c.jitter = v,
                2 => c.drop_probability = v,
                3 => c.arw = v,
                4 => c.bias_instability = v,
                5 => c.rrw = v,
                6 => c.drift_step = v,
                7 => c.resolution = v,
                8 => c.bandwidth = v,
                _ => c.flicker_min = v,
            }
        }
        let Ok(mut model) = GyroModel::new(c, seed) else { return Ok(()) };
        let instants: Vec<f64> = model.sampler(0.0).take(20).collect();
        prop_assert!(instants.windows(2).all(|w| w[0] < w[1]), "{:?}", instants);
        for x in t.into_iter().filter(|x| x.is_finite()) {
            let s = model.measure(x, 0.1);
            prop_assert!(s.rate.is_finite(), "{:?} at {}", s, x);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// A pipeline with a temperature model and a speed, and the fused pipeline with fixes, on
    /// any samples: one call and a split agree, and an accepted block's outputs are finite.
    #[test]
    fn any_fused_pipeline_with_temperature_and_speed(
        (t, r) in samples(100),
        extra in proptest::collection::vec((mostly(-40.0..85.0), mostly(0.0..0.2)), 100),
        fixes in proptest::collection::vec((0.0..30.0f64, mostly(-4.0..4.0), mostly(1e-3..0.5)), 0..6),
        model in (mostly(-0.5..0.5), mostly(-20.0..20.0), mostly(0.9..1.1), mostly(0.9..1.1)),
        config in config(),
        cut in 0usize..100,
    ) {
        let n = t.len();
        let temperature: Vec<f64> = extra[..n].iter().map(|e| e.0).collect();
        let speed: Vec<f64> = extra[..n].iter().map(|e| e.1).collect();
        let mut c = config;
        c.correction.temperature = Some(TemperatureScale { slope: model.0, offset: model.1 });
        (c.correction.c_cw, c.correction.c_ccw) = (model.2, model.3);
        if let Ok(fresh) = Pipeline::new(c) {
            let run = |p: &mut Pipeline, range: core::ops::Range<usize>| {
                let k = range.len();
                let (mut h, mut d) = (vec![0.0; k], vec![0.0; k]);
                let out = Outputs { heading: Some(&mut h), rate: None, drift: Some(&mut d) };
                let (t, r) = (&t[range.clone()], &r[range.clone()]);
                let (temp, speed) = (&temperature[range.clone()], &speed[range]);
                p.process_block_with_speed(t, r, Some(temp), Some(speed), out).map(|()| (h, d))
            };
            let cut = cut.min(n);
            let (mut one, mut parts) = (fresh.clone(), fresh);
            if let Ok((h, d)) = run(&mut one, 0..n) {
                prop_assert!(h.iter().chain(&d).all(|x| x.is_finite()), "{:?}", h);
                let (mut h2, mut d2) = run(&mut parts, 0..cut).unwrap();
                let (h3, d3) = run(&mut parts, cut..n).unwrap();
                h2.extend(h3);
                d2.extend(d3);
                prop_assert_eq!(bits_of(&h), bits_of(&h2));
                prop_assert_eq!(bits_of(&d), bits_of(&d2));
            }
        }
        let Ok(fresh) = FusedPipeline::new(config, FusionConfig::default()) else { return Ok(()) };
        let mut fixes: Vec<Fix> = fixes.into_iter().map(|(t, heading, sigma)| Fix { t, heading, sigma }).collect();
        fixes.sort_by(|a, b| a.t.total_cmp(&b.t));
        let run = |p: &mut FusedPipeline, range: core::ops::Range<usize>, fixes: &[Fix]| {
            let k = range.len();
            let (mut h, mut s, mut rate) = (vec![0.0; k], vec![0.0; k], vec![0.0; k]);
            let samples = Samples { speed: Some(&speed[range.clone()]), ..Samples::new(&t[range.clone()], &r[range]) };
            let out = FusedOutputs { heading: &mut h, heading_sigma: Some(&mut s), bias: None, scale: None, rate: &mut rate, drift: None };
            p.process_block(samples, fixes, out).map(|used| (used, h, s))
        };
        let mut one = fresh.clone();
        if let Ok((used, h, s)) = run(&mut one, 0..n, &fixes) {
            prop_assert!(h.iter().chain(&s).all(|x| x.is_finite()), "{:?} {:?}", h, s);
            let cut = cut.min(n);
            let mut parts = fresh;
            let (first, mut h2, _) = run(&mut parts, 0..cut, &fixes).unwrap();
            let (second, h3, _) = run(&mut parts, cut..n, &fixes[first..]).unwrap();
            h2.extend(h3);
            prop_assert_eq!(first + second, used);
            prop_assert_eq!(bits_of(&h), bits_of(&h2));
        }
    }
}

fn bits_of(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// A phase the caller gives whose variance overflows (1e308: the square of its difference is
/// infinite) is an error naming the sample beyond `allan::MAX_PHASE`; it was `Ok(inf)`. At the
/// limit, over the shortest `tau0`, every kind stays finite.
#[test]
fn a_phase_whose_variance_overflows_is_named() {
    let mut x = [0.0; 9];
    x[8] = 1e308;
    for kind in [Variance::Allan, Variance::ModifiedAllan, Variance::Hadamard] {
        let e = allan::variance(&x, 1.0, 1, kind).unwrap_err();
        assert!(
            matches!(
                e,
                Error::OutOfRange {
                    what: "phase",
                    index: 8,
                    ..
                }
            ),
            "{kind:?}: {e}"
        );
    }
    let e = allan::variance(&x, 1.0, 1, Variance::Allan).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("phase[8] = 1e308 rad is beyond +-1152921504606847000 rad"),
        "{e}"
    );
    let top = f64::from_bits(allan::MAX_PHASE.to_bits() - 1);
    let x: Vec<f64> = (0..64)
        .map(|i| if i % 2 == 0 { top } else { -top })
        .collect();
    for kind in Variance::ALL {
        let (v, _) = allan::variance(&x, MIN_INTERVAL, 1, kind).unwrap();
        assert!(v.is_finite() && v > 0.0, "{kind:?}: {v}");
    }
}

/// A simulated gyro's resolution finer than the float spacing of its readings (a subnormal one)
/// quantises nothing; `reading / resolution` overflowed, and every reading was infinite.
#[test]
fn a_subnormal_resolution_leaves_the_reading() {
    let mut c = GyroModelConfig::ideal(100.0);
    c.resolution = f64::from_bits(1);
    let mut model = GyroModel::new(c, 0).unwrap();
    assert_eq!(model.measure(0.0, 0.1).rate, 0.1);
    c.resolution = 0.25;
    let mut model = GyroModel::new(c, 0).unwrap();
    assert_eq!(model.measure(0.0, 0.2).rate, 0.25);
}
