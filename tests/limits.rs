//! The limits of a valid sample and parameter (`MAX_READING`, `MAX_TIME`, `MIN_INTERVAL`): inside
//! them every output is finite, outside them a block is rejected naming the sample and `update`
//! treats the sample as it treats a non-finite one.

mod common;

use gyrocore::*;

/// A reading just inside the limit.
const TOP: f64 = MAX_READING * (1.0 - f64::EPSILON);

/// Timestamps from just inside `-MAX_TIME` to just inside `MAX_TIME`: runs of the shortest
/// interval between jumps of a quarter of the range.
fn extreme_times() -> Vec<f64> {
    let start = -MAX_TIME * (1.0 - 1e-9);
    let mut t = vec![start];
    for jump in 0..8 {
        let base = start + jump as f64 * MAX_TIME / 4.0;
        // a run of samples one shortest interval apart, as far as the float spacing allows there
        let step = (2.0 * MIN_INTERVAL).max(8.0 * f64::EPSILON * base.abs());
        for k in 0..50 {
            let next = base + k as f64 * step;
            if next > *t.last().unwrap() {
                t.push(next);
            }
        }
    }
    t.push(MAX_TIME * (1.0 - 1e-9));
    t
}

/// Every preset with every parameter at the limit that makes it largest, on readings at the
/// limit that turn back and forth and on the widest timestamps: every output is finite.
#[test]
fn inputs_at_the_limits_give_finite_outputs() {
    let t = extreme_times();
    let r: Vec<f64> = (0..t.len())
        .map(|i| if i % 7 < 4 { TOP } else { -TOP })
        .collect();
    for preset in Preset::ALL {
        for (scale, tau) in [(MAX_READING, MAX_TIME), (MAX_READING, 1e-6)] {
            let mut c = preset.config();
            c.correction.bias = StaticBias::Fixed(-MAX_READING);
            c.correction.offset = MAX_READING;
            c.correction.scale = scale;
            c.correction.c_cw = scale;
            c.correction.c_ccw = scale;
            if c.lowpass.is_some() {
                c.set_lowpass_tau(tau);
            }
            if let Some(h) = &mut c.hdr {
                h.interval = MAX_TIME;
                h.increment = MAX_READING;
            }
            let mut p = Pipeline::new(c).unwrap();
            let out = common::try_block(&mut p, &t, &r).unwrap();
            let bad = out.iter().position(|o| {
                !(o.heading.is_finite() && o.rate.is_finite() && o.drift.is_finite())
            });
            assert_eq!(
                bad,
                None,
                "{preset:?} scale {scale} tau {tau}: {:?}",
                bad.map(|i| out[i])
            );
        }
    }
}

/// HDR at its largest increment, stepping often, with the attenuator's power at 1024 and
/// `c_1 = 0` (R = 1: the formula alone gives 0 * inf once `r^c_2` overflows): finite throughout.
#[test]
fn hdr_at_its_largest_settings_stays_finite() {
    let t = extreme_times();
    let r: Vec<f64> = (0..t.len())
        .map(|i| if i % 3 == 0 { 1e-3 } else { -1e-3 })
        .collect();
    let mut c = Preset::Hdr.config();
    c.correction.bias = StaticBias::Fixed(0.0);
    let h = c.hdr.as_mut().unwrap();
    (h.increment, h.interval, h.c1, h.c2) = (MAX_READING, 1e-6, 0.0, 1024.0);
    assert_eq!(h.attenuation(1 << 20), 1.0);
    let out = common::try_block(&mut Pipeline::new(c).unwrap(), &t, &r).unwrap();
    assert!(out
        .iter()
        .all(|o| o.heading.is_finite() && o.drift.is_finite()));
}

/// FOG eq 6's factor where the model's turn error reaches -100 %: bounded, not infinite.
#[test]
fn the_temperature_factor_stays_finite_where_its_denominator_vanishes() {
    let m = TemperatureScale {
        slope: -0.5,
        offset: 0.0,
    };
    assert_eq!(m.factor(2.0), MAX_READING);
    assert_eq!(m.factor(1.0), 2.0);
    // No temperature measured: NaN, not the bound (2^20 times the reading).
    assert!(m.factor(f64::NAN).is_nan());
}

fn stream(n: usize) -> (Vec<f64>, Vec<f64>) {
    let t = (0..n).map(|i| 10.0 + i as f64 * 0.01).collect();
    let r = (0..n).map(|i| 0.1 * (i as f64 * 0.01).sin()).collect();
    (t, r)
}

fn combined() -> PipelineConfig {
    let mut c = Preset::Combined.config();
    c.correction.bias = StaticBias::Fixed(0.001);
    c
}

/// A block with a sample beyond a limit is rejected naming it, and leaves the pipeline as it was;
/// `update` skips the sample as it skips a non-finite one.
#[test]
fn a_sample_beyond_a_limit_is_rejected_naming_it() {
    type Expected = fn(&Error) -> bool;
    let cases: [(&str, usize, f64, Expected); 5] = [
        ("rate", 250, MAX_READING, |e| {
            matches!(
                e,
                Error::OutOfRange {
                    what: "rate",
                    index: 250,
                    ..
                }
            )
        }),
        ("rate", 3, -1e308, |e| {
            matches!(
                e,
                Error::OutOfRange {
                    what: "rate",
                    index: 3,
                    ..
                }
            )
        }),
        ("t", 0, -MAX_TIME, |e| {
            matches!(
                e,
                Error::OutOfRange {
                    what: "t",
                    index: 0,
                    ..
                }
            )
        }),
        ("t", 399, 1.5e308, |e| {
            matches!(
                e,
                Error::OutOfRange {
                    what: "t",
                    index: 399,
                    ..
                }
            )
        }),
        // a timestamp half the shortest interval after the one before
        ("close", 120, MIN_INTERVAL / 2.0, |e| {
            matches!(e, Error::TooClose { index: 120, .. })
        }),
    ];
    for (what, index, value, expected) in cases {
        let (mut t, mut r) = stream(400);
        match what {
            "rate" => r[index] = value,
            "close" => t[index] = t[index - 1] + value,
            _ => t[index] = value,
        }
        // the bad sample in a later block of a stream, or in the first
        let split = if index >= 100 { 100 } else { 0 };
        let mut p = Pipeline::new(combined()).unwrap();
        common::try_block(&mut p, &t[..split], &r[..split]).unwrap();
        let before = p.clone();
        let err = common::try_block(&mut p, &t[split..], &r[split..])
            .unwrap_err()
            .with_index_offset(split);
        assert!(expected(&err), "{what}[{index}] = {value}: {err:?}");
        let named = format!("{}[{index}]", if what == "rate" { "rate" } else { "t" });
        assert!(err.to_string().contains(&named), "{err}");
        assert_eq!(
            p, before,
            "{what}[{index}]: a rejected block changes nothing"
        );

        // update: the sample is skipped (the heading stays, the rate is NaN)
        let mut u = Pipeline::new(combined()).unwrap();
        let outs: Vec<Output> = t.iter().zip(&r).map(|(&x, &y)| u.update(x, y)).collect();
        assert!(
            outs[index].rate.is_nan(),
            "{what}[{index}]: {:?}",
            outs[index]
        );
        assert!(
            outs.iter().all(|o| o.heading.is_finite()),
            "{what}[{index}]"
        );
    }
}

/// Parameters just beyond their limits are refused, naming the parameter.
#[test]
fn parameters_beyond_their_limits_are_refused() {
    let above = |x: f64| f64::from_bits(x.to_bits() + 1);
    type Set = fn(&mut PipelineConfig, f64);
    let set: [(&str, Set, f64); 13] = [
        (
            "bias",
            |c, v| c.correction.bias = StaticBias::Fixed(-v),
            above(MAX_READING),
        ),
        ("offset", |c, v| c.correction.offset = v, above(MAX_READING)),
        ("scale", |c, v| c.correction.scale = v, above(MAX_READING)),
        ("c_ccw", |c, v| c.correction.c_ccw = v, above(MAX_READING)),
        (
            "bias_duration",
            |c, v| c.correction.bias = StaticBias::Leading { duration: v },
            above(MAX_TIME),
        ),
        (
            "bias_window.end",
            |c, v| c.correction.bias = StaticBias::Window { start: 0.0, end: v },
            above(MAX_TIME),
        ),
        (
            "bias_window.start",
            |c, v| {
                c.correction.bias = StaticBias::Window {
                    start: -v,
                    end: 0.0,
                }
            },
            above(MAX_TIME),
        ),
        ("lowpass_tau", |c, v| c.set_lowpass_tau(v), above(MAX_TIME)),
        (
            "hdr_interval",
            |c, v| c.hdr.as_mut().unwrap().interval = v,
            above(MAX_TIME),
        ),
        (
            "gap_limit",
            |c, v| c.input.gap_limit = v,
            MIN_INTERVAL / 2.0,
        ),
        (
            "hdr_increment",
            |c, v| c.hdr.as_mut().unwrap().increment = v,
            above(MAX_READING),
        ),
        (
            "rest_bias_walk",
            |c, v| {
                c.rest_tracker = Some(RestTrackerConfig {
                    bias_walk: v,
                    ..Default::default()
                })
            },
            above(MAX_READING),
        ),
        (
            "rest_block",
            |c, v| {
                c.rest_tracker = Some(RestTrackerConfig {
                    block: v,
                    ..Default::default()
                })
            },
            above(MAX_TIME),
        ),
    ];
    for (name, apply, value) in set {
        let mut c = combined();
        apply(&mut c, value);
        match Pipeline::new(c) {
            Err(Error::InvalidParameter { name: got, .. }) => assert_eq!(got, name),
            other => panic!("{name} = {value}: {other:?}"),
        }
    }
}

/// An extreme value reads short in a message; a timestamp keeps its digits.
#[test]
fn extreme_values_read_short_in_messages() {
    let mut c = combined();
    c.correction.scale = 1e308;
    let e = Pipeline::new(c).unwrap_err().to_string();
    assert!(e.contains("scale = 1e308: must be > 0"), "{e}");
    let e = check_block(
        &[1_700_000_000.25, 1_700_000_000.0],
        &[0.0; 2],
        None,
        None,
        true,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("t[1] = 1700000000 follows 1700000000.25"), "{e}");
}

/// An error's index moved by an offset near `usize::MAX` saturates (it overflowed: a panic in a
/// debug build); errors of no sample keep no index.
#[test]
fn an_index_offset_near_the_largest_saturates() {
    let e = Error::NotIncreasing {
        index: 7,
        previous: 1.0,
        value: 0.5,
    };
    assert_eq!(
        e.with_index_offset(usize::MAX - 3).index(),
        Some(usize::MAX)
    );
    assert_eq!(e.with_index_offset(10).index(), Some(17));
    assert_eq!(
        Error::MissingTemperature
            .with_index_offset(usize::MAX)
            .index(),
        None
    );
}

/// A length mismatch names the slice it is measured against: the message said `but t has` of
/// slices that have no `t` (a projection's `y` against `x`, the Allan outputs against the
/// factors, the phase against the rate).
#[test]
fn a_length_mismatch_names_what_it_is_measured_against() {
    let mut out = [0.0; 2];
    let up = Up::new([0.0, 0.0, 1.0]).unwrap();
    let e = up.project_block(&[1.0, 2.0], &[1.0], &[1.0, 2.0], &mut out);
    assert_eq!(
        e.unwrap_err().to_string(),
        "length mismatch: y has 1 samples but x has 2"
    );
    let (mut v, mut n) = ([0.0; 1], [0u64; 2]);
    let e = allan::variances(&[0.0; 8], 1.0, &[1], Variance::Allan, &mut v, &mut n);
    assert!(e
        .unwrap_err()
        .to_string()
        .ends_with("terms has 2 samples but factors has 1"));
    let e = allan::phase_from_rate(&[0.0; 4], 1.0, &mut [0.0; 4]);
    assert!(e.unwrap_err().to_string().ends_with("but rate + 1 has 5"));
    let mut i = Integrator::new(IntegratorConfig::default()).unwrap();
    let e = i.process_block(&[0.0, 1.0], &[0.0, 0.0], &mut out[..1]);
    assert!(e
        .unwrap_err()
        .to_string()
        .ends_with("out has 1 samples but the input has 2"));
    let e = Pipeline::new(Preset::Raw.config()).unwrap().process_block(
        &[0.0, 1.0],
        &[0.0],
        None,
        Outputs::default(),
    );
    assert!(e
        .unwrap_err()
        .to_string()
        .ends_with("rate has 1 samples but t has 2"));
}
