//! States stored in a binary serde format (postcard: no `deserialize_any`, what a small target
//! writes to flash) read back whole and carry on bit for bit, infinite settings included.
#![cfg(feature = "serde")]

mod common;

use gyrocore::*;
use serde::{de::DeserializeOwned, Serialize};

/// `value` written with postcard and read back.
fn through_postcard<T: Serialize + DeserializeOwned>(value: &T) -> T {
    let bytes = postcard::to_allocvec(value).unwrap();
    postcard::from_bytes(&bytes).unwrap()
}

/// 20 s at 100 Hz: a rest, then turns of 0.3 rad/s every other second, a rate with a bias.
fn drive() -> (Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = (0..2000).map(|i| i as f64 * 0.01).collect();
    let rate = (0..2000)
        .map(|i| {
            0.002
                + if i > 600 && (i / 100) % 2 == 1 {
                    0.3
                } else {
                    0.0
                }
        })
        .collect();
    (t, rate)
}

/// A tracked pipeline with every switch that serialises as infinity turned off (no gap limit,
/// no change test, no gate), read back from postcard halfway, gives the headings of the one
/// that ran through (postcard refused any state: the infinite-capable fields asked for
/// `deserialize_any`).
#[test]
fn a_pipeline_stored_with_postcard_carries_on_bit_for_bit() {
    let mut config = Preset::Tracked.config();
    config.correction.bias = StaticBias::Leading { duration: 5.0 };
    config.input.gap_limit = f64::INFINITY;
    let tracker = config.rest_tracker.as_mut().unwrap();
    (tracker.change_sigmas, tracker.gate_sigmas) = (f64::INFINITY, f64::INFINITY);
    let (t, rate) = drive();
    let mut whole = Pipeline::new(config).unwrap();
    let mut first = Pipeline::new(config).unwrap();
    for i in 0..1000 {
        whole.update(t[i], rate[i]);
        first.update(t[i], rate[i]);
    }
    let mut read = through_postcard(&first);
    assert_eq!(read, first);
    for i in 1000..2000 {
        assert_eq!(read.update(t[i], rate[i]), whole.update(t[i], rate[i]));
    }
}

/// The same of a fused pipeline between two blocks, and of a stand-alone stage.
#[test]
fn a_fused_pipeline_and_a_stage_stored_with_postcard_carry_on() {
    let (t, rate) = drive();
    let fixes: Vec<Fix> = (1..20)
        .map(|s| Fix {
            t: s as f64,
            heading: 0.1,
            sigma: 0.05,
        })
        .collect();
    let mut config = Preset::Hdr.config();
    config.input.gap_limit = f64::INFINITY;
    let fused = FusedPipeline::new(config, FusionConfig::default()).unwrap();
    let run = |f: &mut FusedPipeline, range: core::ops::Range<usize>, fixes: &[Fix]| {
        let n = range.len();
        let (mut h, mut r) = (vec![0.0; n], vec![0.0; n]);
        let out = common::heading_and_rate(&mut h, &mut r);
        let used = f
            .process_block(Samples::new(&t[range.clone()], &rate[range]), fixes, out)
            .unwrap();
        (h, used)
    };
    let mut a = fused.clone();
    let (_, used) = run(&mut a, 0..1000, &fixes);
    let mut b = through_postcard(&a);
    assert_eq!(b, a);
    assert_eq!(
        run(&mut b, 1000..2000, &fixes[used..]),
        run(&mut a, 1000..2000, &fixes[used..])
    );

    let mut stage = Hdr::new(HdrConfig::table_iii()).unwrap();
    for i in 0..1000 {
        stage.update(t[i], rate[i]);
    }
    let mut read = through_postcard(&stage);
    for i in 1000..2000 {
        assert_eq!(read.update(t[i], rate[i]), stage.update(t[i], rate[i]));
    }
}
