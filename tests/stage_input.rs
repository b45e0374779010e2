//! The stand-alone stages (`Streaming<K>`, `Correction`, `Downsample`) given input they cannot
//! use, sample by sample and in blocks, and read back through serde.

mod common;
use common::run;
use gyrocore::*;

/// A stand-alone stage skips a reading it cannot use, as the pipeline's `update` does: a NaN,
/// an infinity or a rate beyond `MAX_READING` taken into the state made every later heading
/// NaN (or, for HDR, its low-passed step mean NaN forever). The run equals one without it.
#[test]
fn a_stage_skips_an_unusable_reading_and_its_block_is_refused_by_index() {
    fn check<S: Stage<Output = f64> + Clone + PartialEq + core::fmt::Debug>(fresh: S) {
        let t: Vec<f64> = (0..40).map(|i| i as f64 * 0.1).collect();
        let rate: Vec<f64> = (0..40).map(|i| 0.01 * (i % 7) as f64).collect();
        let mut stage = fresh.clone();
        let outputs = run(&mut stage, &t[..20], &rate[..20]);
        for bad in [f64::NAN, f64::INFINITY, -MAX_READING, 1e300] {
            let before = stage.clone();
            let last = stage.update(t[20] - 0.05, bad);
            assert_eq!((last.to_bits(), &stage), (outputs[19].to_bits(), &before));
        }
        let clean = run(&mut fresh.clone(), &t, &rate);
        let mut dirty_t = t.clone();
        dirty_t.insert(25, t[24] + 0.05);
        let mut dirty_rate = rate.clone();
        dirty_rate.insert(25, f64::NAN);
        let mut dirty = run(&mut fresh.clone(), &dirty_t, &dirty_rate);
        dirty.remove(25);
        assert_eq!(clean, dirty);
        // a block: refused by the first bad sample's index, nothing processed
        let mut stage = fresh.clone();
        let mut out = vec![0.0; t.len()];
        let e = stage.process_block(&dirty_t[..30], &dirty_rate[..30], &mut out[..30]);
        assert!(
            matches!(
                e,
                Err(Error::NonFinite {
                    what: "rate",
                    index: 25,
                    ..
                })
            ),
            "{e:?}"
        );
        assert_eq!(stage, fresh);
        stage
            .process_block(&t[..10], &rate[..10], &mut out[..10])
            .unwrap();
        let before = stage.clone();
        let e = stage.process_block(&t[5..15], &rate[5..15], &mut out[..10]);
        assert!(
            matches!(e, Err(Error::NotIncreasing { index: 0, .. })),
            "{e:?}"
        );
        assert_eq!(stage, before);
    }
    check(Integrator::new(IntegratorConfig::default()).unwrap());
    check(Threshold::new(ThresholdConfig { threshold: 0.02 }).unwrap());
    check(LowPass::new(LowPassConfig { tau: 0.75 }).unwrap());
    check(DeLag::new(LowPassConfig { tau: 0.75 }).unwrap());
    check(Hdr::new(HdrConfig::table_iii()).unwrap());
}

/// Down-sampling leaves out a reading it cannot use (a NaN made its block's mean NaN), refuses
/// a bad block by index, and an interval beyond 2^40 s or below the smallest normal number.
#[test]
fn downsample_leaves_out_an_unusable_reading_and_refuses_a_bad_block() {
    let config = DownsampleConfig { interval: 1.0 };
    let mut d = Downsample::new(config).unwrap();
    let t = [0.0, 0.5, 0.75, 1.0, 2.0];
    let (mut ot, mut or) = ([0.0; 5], [0.0; 5]);
    let e = d.process_block(&t, &[1.0, f64::NAN, 1.0, 1.0, 1.0], &mut ot, &mut or);
    assert!(matches!(e, Err(Error::NonFinite { index: 1, .. })), "{e:?}");
    assert_eq!(d, Downsample::new(config).unwrap());
    let means = |d: &mut Downsample, t: &[f64], rate: &[f64]| -> Vec<_> {
        t.iter()
            .zip(rate)
            .filter_map(|(&t, &r)| d.update(t, r))
            .collect()
    };
    let rate = [1.0, f64::NAN, 2.0, 3.0, 4.0];
    let clean = means(
        &mut Downsample::new(config).unwrap(),
        &[0.0, 0.75, 1.0, 2.0],
        &[1.0, 2.0, 3.0, 4.0],
    );
    assert_eq!(means(&mut d, &t, &rate), clean);
    let e = d.process_block(&[1.5], &[1.0], &mut ot[..1], &mut or[..1]);
    assert!(
        matches!(e, Err(Error::NotIncreasing { index: 0, .. })),
        "{e:?}"
    );
    for interval in [1e300, 1e-320, f64::NAN] {
        assert!(
            Downsample::new(DownsampleConfig { interval }).is_err(),
            "{interval}"
        );
    }
}

/// `Streaming::step`, for a caller with its own clock, leaves the stage as it was for an
/// interval no two valid timestamps have (NaN, 0, negative, below 1 ps, infinite): a NaN or
/// negative one made the low-pass NaN for good, and a NaN one stopped HDR's steps.
#[test]
fn a_stage_stepped_by_a_bad_interval_stays_as_it_was() {
    fn check<K: kernel::Validated + Copy + PartialEq + core::fmt::Debug>(mut stage: Streaming<K>) {
        let first = stage.step(f64::NAN, 0.5);
        let mut last = stage.step(0.1, 0.25);
        for dt in [
            f64::NAN,
            0.0,
            -0.75,
            -1.0,
            1e-13,
            f64::INFINITY,
            3.0 * MAX_TIME,
        ] {
            let before = stage;
            assert_eq!(stage.step(dt, 2.0).to_bits(), last.to_bits(), "{dt}");
            assert_eq!(stage, before, "{dt}");
        }
        assert!(first.is_finite());
        for _ in 0..40 {
            last = stage.step(0.1, 0.001);
        }
        assert!(last.is_finite());
    }
    check(LowPass::new(LowPassConfig { tau: 0.75 }).unwrap());
    check(DeLag::new(LowPassConfig { tau: 0.75 }).unwrap());
    check(Integrator::new(IntegratorConfig::default()).unwrap());
    check(Hdr::new(HdrConfig::table_iii()).unwrap());
    check(Threshold::new(ThresholdConfig { threshold: 0.01 }).unwrap());
}

/// A correction or down-sampling read back is checked as `new` checks it: a scale of 0 or an
/// interval of -1 edited into a stored state ran (every rate 0; a block closed at every sample).
#[cfg(feature = "serde")]
#[test]
fn a_stage_read_back_is_checked_as_new_checks_it() {
    let mut c = Correction::new(CorrectionConfig::default()).unwrap();
    c.update(0.0, 0.1);
    let json = serde_json::to_string(&c).unwrap();
    assert_eq!(serde_json::from_str::<Correction>(&json).unwrap(), c);
    let e = serde_json::from_str::<Correction>(&json.replace("\"scale\":1.0", "\"scale\":0.0"));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("invalid parameter scale = 0"));
    let d = Downsample::new(DownsampleConfig { interval: 1.0 }).unwrap();
    let json = serde_json::to_string(&d).unwrap();
    assert_eq!(serde_json::from_str::<Downsample>(&json).unwrap(), d);
    let e =
        serde_json::from_str::<Downsample>(&json.replace("\"interval\":1.0", "\"interval\":-1.0"));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("invalid parameter interval = -1"));
}

/// A stand-alone stage read back is checked as `new` checks its settings: a low-pass `tau` of
/// -0.75 edited into a stored state gave NaN from its second sample on, and an HDR bound of -1
/// pinned the correction `I` at -1 rad/s.
#[cfg(feature = "serde")]
#[test]
fn a_streaming_stage_read_back_is_checked() {
    let mut l = LowPass::new(LowPassConfig { tau: 0.75 }).unwrap();
    l.update(0.0, 0.1);
    let json = serde_json::to_string(&l).unwrap();
    assert_eq!(serde_json::from_str::<LowPass>(&json).unwrap(), l);
    let e = serde_json::from_str::<LowPass>(&json.replace("\"tau\":0.75", "\"tau\":-0.75"));
    assert!(e.unwrap_err().to_string().contains("lowpass_tau = -0.75"));
    let h = Hdr::new(HdrConfig::table_iii()).unwrap();
    let json = serde_json::to_string(&h).unwrap();
    assert_eq!(serde_json::from_str::<Hdr>(&json).unwrap(), h);
    let e = serde_json::from_str::<Hdr>(&json.replace("\"bound\":\"inf\"", "\"bound\":-1.0"));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("hdr_max_correction = -1"));
    let e = serde_json::from_str::<Hdr>(&json.replace("\"c2\":1.8", "\"c2\":0.0"));
    assert!(e.unwrap_err().to_string().contains("hdr_c2"));
}

/// A stage's block checks its samples on the way (the pipeline's way) and exactly only where the
/// quick check may have failed: rates of 2 rad/s and more (which its bound takes for suspects)
/// and a first time of 2^40 - 1 s (where the first interval rounds to 0) give what `update`
/// gives, sample for sample, and a NaN in the last sample still refuses the block whole.
#[test]
fn a_stage_block_equals_update_where_its_quick_check_is_unsure() {
    let t: Vec<f64> = (0..50).map(|i| MAX_TIME - 1.0 - 50.0 + i as f64).collect();
    let rate: Vec<f64> = (0..50).map(|i| 3.0 * (i % 5) as f64 - 6.0).collect();
    let fresh = Hdr::new(HdrConfig::table_iii()).unwrap();
    let (mut a, mut b) = (fresh, fresh);
    let updates = run(&mut a, &t, &rate);
    let mut out = vec![0.0; t.len()];
    b.process_block(&t, &rate, &mut out).unwrap();
    assert_eq!((out, b), (updates, a));
    let mut bad = rate.clone();
    bad[49] = f64::NAN;
    let mut c = fresh;
    let e = c.process_block(&t, &bad, &mut vec![0.0; t.len()]);
    assert!(
        matches!(e, Err(Error::NonFinite { index: 49, .. })),
        "{e:?}"
    );
    assert_eq!(c, fresh);
}

/// A stage fed by `step` (its caller's clock) and then by `update` or a block takes their first
/// sample as the start of its clock only: its interval was 0 there, and the de-lag's output
/// -inf (a block: -7.5e11).
#[test]
fn a_stage_fed_by_step_then_by_time_starts_its_clock() {
    let stepped = || {
        let mut d = DeLag::new(LowPassConfig { tau: 0.75 }).unwrap();
        d.step(0.1, 1.0);
        let last = d.step(0.1, 2.0);
        (d, last)
    };
    let (mut a, last) = stepped();
    assert_eq!(a.update(5.0, 1.0), last);
    assert!(a.update(5.1, 1.0).is_finite());
    let (mut b, _) = stepped();
    let mut out = [0.0; 2];
    b.process_block(&[5.0, 5.1], &[1.0, 1.0], &mut out).unwrap();
    assert_eq!(out[0], last);
    assert_eq!(b, a);
}
