//! The rules between parameters live in `PipelineConfig::validate`, a block may ask for only
//! some outputs, a rest window must hold a sample, and the static bias test is the pipeline's.

mod common;
use gyrocore::*;

fn stream(n: usize) -> (Vec<f64>, Vec<f64>) {
    let t = (0..n).map(|i| 50.0 + i as f64 * 0.02).collect();
    let r = (0..n)
        .map(|i| {
            0.01 + 0.4 * ((i as f64) * 0.013).sin().powi(5) + 0.002 * ((i * 7919 % 13) as f64 - 6.0)
        })
        .collect();
    (t, r)
}

fn invalid_name(config: PipelineConfig) -> &'static str {
    match Pipeline::new(config) {
        Err(Error::InvalidParameter { name, .. }) => name,
        other => panic!("expected an invalid parameter, got {other:?}"),
    }
}

#[test]
fn an_initial_heading_beyond_2_pow_20_rad_is_refused() {
    // at 1e300 rad every sample's increment was lost: the heading never moved
    for bad in [1e300, -1e300, MAX_READING * 2.0] {
        let mut c = Preset::Raw.config();
        c.integrator.initial_heading = bad;
        assert_eq!(invalid_name(c), "initial_heading");
    }
    let mut c = Preset::Raw.config();
    c.integrator.initial_heading = -MAX_READING;
    assert!(Pipeline::new(c).is_ok());
}

#[test]
fn delag_needs_a_lowpass() {
    let mut c = Preset::Hdr.config();
    c.lowpass = None;
    c.hdr = Some(HdrConfig {
        tau: 0.0,
        ..HdrConfig::table_iii()
    });
    assert_eq!(invalid_name(c), "delag");
    c.delag = false;
    assert!(Pipeline::new(c).is_ok());
}

#[test]
fn hdr_smooths_its_steps_with_the_lowpass_tau() {
    let mut c = Preset::Hdr.config();
    c.lowpass = Some(LowPassConfig { tau: 0.5 });
    assert_eq!(invalid_name(c), "hdr.tau");
    c.set_lowpass_tau(0.5);
    assert_eq!(c.hdr.unwrap().tau, 0.5);
    assert!(Pipeline::new(c).is_ok());
    // Removing the low-pass leaves de-lag with nothing to invert: an error, not a silent change.
    c.set_lowpass_tau(0.0);
    assert_eq!(c.lowpass, None);
    assert_eq!(invalid_name(c), "delag");
}

#[test]
fn switching_hdr_on_takes_table_iii_with_the_lowpass_tau() {
    let mut c = Preset::StaticBias.config();
    c.set_hdr(true);
    assert_eq!(
        c.hdr,
        Some(HdrConfig {
            tau: 0.0,
            ..HdrConfig::table_iii()
        })
    );
    assert!(Pipeline::new(c).is_ok());
    c.set_hdr(false);
    assert_eq!(c.hdr, None);
}

#[test]
fn the_heading_alone_is_the_heading_of_all_outputs() {
    let (t, r) = stream(5000);
    for preset in Preset::ALL {
        let mut c = preset.config();
        c.correction.bias = StaticBias::Leading { duration: 10.0 };
        let all = common::try_block(&mut Pipeline::new(c).unwrap(), &t, &r).unwrap();
        let mut heading = vec![0.0; t.len()];
        let mut p = Pipeline::new(c).unwrap();
        p.process_block(&t, &r, None, Outputs::heading(&mut heading))
            .unwrap();
        let expected: Vec<u64> = all.iter().map(|o| o.heading.to_bits()).collect();
        let got: Vec<u64> = heading.iter().map(|h| h.to_bits()).collect();
        assert!(expected == got, "{preset:?}");
    }
}

#[test]
fn an_output_of_the_wrong_length_is_an_error() {
    let (t, r) = stream(10);
    let mut short = vec![0.0; 9];
    let mut p = Pipeline::new(Preset::Raw.config()).unwrap();
    let e = p
        .process_block(&t, &r, None, Outputs::heading(&mut short))
        .unwrap_err();
    assert!(matches!(
        e,
        Error::LengthMismatch {
            what: "heading",
            len: 9,
            expected: 10
        }
    ));
}

/// A stream with a gap over its rest window, [75, 80] s: no sample between 70 and 90 s (20 s to
/// 40 s after the start), so none inside the window.
fn stream_past_an_empty_window() -> (Vec<f64>, Vec<f64>, PipelineConfig) {
    let (t, r) = stream(3000);
    let c = common::with_window(Preset::Tuned, 75.0, 80.0);
    let t = t
        .iter()
        .map(|&x| if x > 70.0 { x + 20.0 } else { x })
        .collect();
    (t, r, c)
}

#[test]
fn a_block_that_passes_an_empty_rest_window_changes_nothing() {
    let (t, r, c) = stream_past_an_empty_window();
    let mut p = Pipeline::new(c).unwrap();
    let head = 500;
    common::try_block(&mut p, &t[..head], &r[..head]).unwrap();
    let before = p.clone();
    let e = common::try_block(&mut p, &t[head..], &r[head..]).unwrap_err();
    assert!(
        matches!(
            e,
            Error::EmptyRestWindow {
                start: 75.0,
                end: 80.0,
                first: 50.0,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("holds no sample"), "{e}");
    assert_eq!(p, before);
    // Sent again, the same error: the pipeline did not move on.
    assert_eq!(
        common::try_block(&mut p, &t[head..], &r[head..]).unwrap_err(),
        e
    );
}

#[test]
fn a_sample_stream_tells_when_it_passed_an_empty_rest_window() {
    let (t, r, mut c) = stream_past_an_empty_window();
    let mut p = Pipeline::new(c).unwrap();
    let mut missed = Vec::new();
    for (&ti, &ri) in t.iter().zip(&r) {
        p.update(ti, ri);
        missed.push(p.rest_window_missed());
    }
    // Silent until the first sample past the window's end, then the block path's own error.
    let first_past = t.iter().position(|&x| x > 80.0).unwrap();
    assert!(missed[..first_past].iter().all(Option::is_none));
    let e = missed[first_past].unwrap();
    assert!(
        matches!(e, Error::EmptyRestWindow { start: 75.0, end: 80.0, first: 50.0, last }
            if last == t[first_past]),
        "{e:?}"
    );
    assert!(missed[first_past..].iter().all(Option::is_some));
    let mut whole = Pipeline::new(c).unwrap();
    assert_eq!(common::try_block(&mut whole, &t, &r).unwrap_err(), e);
    // A window that holds readings is never reported.
    c.correction.bias = StaticBias::Window {
        start: 60.0,
        end: 65.0,
    };
    let mut held = Pipeline::new(c).unwrap();
    for (&ti, &ri) in t.iter().zip(&r) {
        held.update(ti, ri);
        assert_eq!(held.rest_window_missed(), None);
    }
}

#[test]
fn the_static_bias_test_is_the_pipelines_rest_window() {
    let (t, r) = stream(4000);
    let (start, end) = (60.0, 90.0);
    let mut p = Pipeline::new(common::with_window(Preset::Tuned, start, end)).unwrap();
    common::try_block(&mut p, &t, &r).unwrap();
    let test = static_bias_test(&t, &r, start, end).unwrap();
    assert_eq!((test.bias, test.count), p.bias());
    assert_eq!(test.statistics, p.rest_statistics());
    assert!(matches!(
        static_bias_test(&t, &r, 10.0, 20.0),
        Err(Error::EmptyRestWindow { .. })
    ));
}

/// A pipeline read back is checked as `Pipeline::new` checks a configuration, and its stages
/// against the ones its configuration builds: a negative `tau` or a gap limit of -1 edited into a
/// stored state ran (`tau` in the stored stages gave NaN headings), and a parameter edited in the
/// configuration alone was kept as stored without a word. A setting whose float reads back a
/// digit apart in both places (`serde_json` without `float_roundtrip`) is taken: HDR's eq 10
/// table is rebuilt from it, not compared with the one written.
#[cfg(feature = "serde")]
#[test]
fn a_pipeline_read_back_is_checked_against_its_configuration() {
    let mut config = Preset::Tracked.config();
    config.correction.bias = StaticBias::Leading { duration: 2.0 };
    let mut p = Pipeline::new(config).unwrap();
    let (t, r) = stream(500);
    let mut h = vec![0.0; t.len()];
    p.process_block(&t, &r, None, Outputs::heading(&mut h))
        .unwrap();
    let json = serde_json::to_string(&p).unwrap();
    assert_eq!(serde_json::from_str::<Pipeline>(&json).unwrap(), p);
    let read =
        |edited: String| serde_json::from_str::<Pipeline>(&edited).map_err(|e| e.to_string());
    // in the configuration (the first of each) and in the stages (the second)
    for (from, to, named) in [
        ("\"tau\":0.75", "\"tau\":-0.75", "lowpass_tau"),
        ("\"gap_limit\":2.0", "\"gap_limit\":-1.0", "gap_limit"),
        ("\"c2\":1.8", "\"c2\":-1.0", "hdr_c2"),
        ("\"c2\":1.8", "\"c2\":2.0", "stages do not match"),
    ] {
        let e = read(json.replacen(from, to, 1)).unwrap_err();
        assert!(e.contains(named), "{from}: {e}");
        if json.matches(from).count() > 1 {
            let second = json.rfind(from).unwrap();
            let edited = format!("{}{to}{}", &json[..second], &json[second + from.len()..]);
            assert!(
                read(edited).unwrap_err().contains("stages do not match"),
                "{from}"
            );
        }
    }
    let last = format!("\"last\":{}", p.last_time().unwrap());
    let e = read(json.replace(&last, "\"last\":1e300")).unwrap_err();
    assert!(e.contains("last_time"), "{e}");
    let nudged = json.replace("\"c1\":0.16", "\"c1\":0.16000000000000003");
    let restored = read(nudged).unwrap();
    assert_eq!(restored.config().hdr.unwrap().c1, 0.16000000000000003);
    // a state written with the table (before it was rebuilt) reads back as it was
    let with_table = json.replace("\"bound\":", "\"attenuation\":[1.0,0.5],\"bound\":");
    assert_eq!(read(with_table).unwrap(), p);
}

#[test]
fn an_invalid_hdr_tau_is_named_as_hdr_tau() {
    // It was named `lowpass_tau`, which held a valid 0.75 s (or was not configured at all).
    for bad in [-1.0, 1e300, f64::NAN] {
        let mut c = Preset::Hdr.config();
        c.hdr.as_mut().unwrap().tau = bad;
        assert_eq!(invalid_name(c), "hdr.tau");
        let alone = HdrConfig {
            tau: bad,
            ..HdrConfig::table_iii()
        };
        match Hdr::new(alone) {
            Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, "hdr.tau"),
            other => panic!("expected an invalid parameter, got {other:?}"),
        }
    }
}
