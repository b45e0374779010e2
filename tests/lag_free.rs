//! The pipeline's chains compute the low-pass (HDR eq 7), HDR and the de-lag (eq 13) in closed
//! form (`rust/src/lag_free.rs`). Here every chain that holds them is checked against the three
//! run as printed, stage after stage through the stand-alone stages: the two forms differ by
//! rounding alone.

use gyrocore::*;

/// A 10-minute drive at about 100 Hz with irregular timestamps: turns, curves below HDR's turn
/// switch, and a bias HDR has to chase.
fn drive() -> (Vec<f64>, Vec<f64>) {
    let n = 60_000;
    let t: Vec<f64> = (0..n)
        .map(|i| i as f64 * 0.01 + 0.004 * ((i * 7919 % 1000) as f64 / 1000.0))
        .collect();
    let rate = t
        .iter()
        .map(|&s| 0.002 + 0.3 * (s / 40.0).sin().powi(9) + 0.004 * (s / 7.0).sin())
        .collect();
    (t, rate)
}

/// `config`'s outputs (heading, rate, drift) computed stage after stage: correction, dead band,
/// then the low-pass, HDR's correction added (eq 12) and the de-lag, each as printed.
fn stage_after_stage(config: &PipelineConfig, t: &[f64], rate: &[f64]) -> [Vec<f64>; 3] {
    let mut correction = Correction::new(config.correction).unwrap();
    let dead_band = config
        .threshold
        .unwrap_or(ThresholdConfig { threshold: 0.0 });
    let mut threshold = Threshold::new(dead_band).unwrap();
    let mut lowpass = config.lowpass.map(|c| LowPass::new(c).unwrap());
    let mut hdr = config.hdr.map(|c| Hdr::new(c).unwrap());
    let mut delag = config
        .lowpass
        .filter(|_| config.delag)
        .map(|c| DeLag::new(c).unwrap());
    let mut integrator = Integrator::new(config.integrator).unwrap();
    let mut out: [Vec<f64>; 3] = Default::default();
    for (&ti, &ri) in t.iter().zip(rate) {
        let corrected = threshold.update(ti, correction.update(ti, ri));
        let mut w = lowpass
            .as_mut()
            .map_or(corrected, |l| l.update(ti, corrected));
        let applied = hdr.as_mut().map_or(0.0, |h| {
            let applied = -h.drift();
            h.update(ti, corrected); // decides on the corrected rate's step means
            applied
        });
        w += applied;
        let y = delag.as_mut().map_or(w, |d| d.update(ti, w));
        out[0].push(integrator.update(ti, y));
        out[1].push(y);
        out[2].push(-applied);
    }
    out
}

fn check(name: &str, config: PipelineConfig) {
    let (t, rate) = drive();
    let n = t.len();
    let (mut heading, mut r, mut drift) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut p = Pipeline::new(config).unwrap();
    p.process_block(
        &t,
        &rate,
        None,
        Outputs::all(&mut heading, &mut r, &mut drift),
    )
    .unwrap();
    let [h_ref, r_ref, d_ref] = stage_after_stage(&config, &t, &rate);
    assert_eq!(drift, d_ref, "{name}: HDR's corrections");
    if config.hdr.is_some() {
        assert!(drift.iter().any(|&d| d != 0.0), "{name}: HDR must act");
    }
    let worst = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs() / (1.0 + y.abs()))
            .fold(0.0, f64::max)
    };
    let (dh, dr) = (worst(&heading, &h_ref), worst(&r, &r_ref));
    assert!(dh < 1e-11, "{name}: heading differs by {dh:e} rad");
    assert!(dr < 1e-12, "{name}: rate differs by {dr:e} rad/s");
}

fn combined() -> PipelineConfig {
    let mut c = Preset::Combined.config();
    c.correction.bias = StaticBias::Fixed(0.001);
    c
}

#[test]
fn the_hdr_chain_equals_the_stages_run_as_printed() {
    check("combined", combined());
    let mut tuned = Preset::Tuned.config();
    tuned.correction.bias = StaticBias::Fixed(0.001);
    check("tuned", tuned);
}

#[test]
fn the_general_chain_equals_the_stages_run_as_printed() {
    // A factor per turn direction takes the general chain with all three stages.
    let mut split = combined();
    split.correction.c_cw = 1.01;
    check("combined, factor per direction", split);
    // The low-pass without the de-lag: its lag stays, HDR added after it.
    check(
        "low-pass, HDR, no de-lag",
        PipelineConfig {
            delag: false,
            ..combined()
        },
    );
    // The low-pass and the de-lag without HDR: the corrected rate itself.
    check(
        "low-pass and de-lag, no HDR",
        PipelineConfig {
            hdr: None,
            ..combined()
        },
    );
}

#[test]
fn the_low_pass_and_de_lag_without_hdr_give_the_corrected_rate_exactly() {
    let config = PipelineConfig {
        hdr: None,
        ..combined()
    };
    let (t, rate) = drive();
    let n = t.len();
    let (mut h, mut r, mut d) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    Pipeline::new(config)
        .unwrap()
        .process_block(&t, &rate, None, Outputs::all(&mut h, &mut r, &mut d))
        .unwrap();
    // the same without the low-pass and the de-lag (and, like `config`, without HDR)
    let plain = PipelineConfig {
        lowpass: None,
        delag: false,
        ..config
    };
    let (mut h_plain, mut r_plain, mut d_plain) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    Pipeline::new(plain)
        .unwrap()
        .process_block(
            &t,
            &rate,
            None,
            Outputs::all(&mut h_plain, &mut r_plain, &mut d_plain),
        )
        .unwrap();
    assert_eq!(r, r_plain);
    assert_eq!(h, h_plain);
}
