//! A fix far surer than the filter (an unknown heading, sigma up to 2^20 rad, fixed to a
//! milliradian): the update's covariance keeps the fix's sigma instead of rounding it away.

use gyrocore::{Fix, Fusion, FusionConfig, FusionOutputs};

/// The heading sigma right after one fix of `fix_sigma` at the first sample, from a prior of
/// `prior` \[rad\].
fn sigma_after_one_fix(prior: f64, fix_sigma: f64) -> f64 {
    let config = FusionConfig {
        initial_heading_sigma: prior,
        ..FusionConfig::default()
    };
    let mut f = Fusion::new(config).unwrap();
    let (t, rate) = ([0.0, 0.01], [0.0, 0.0]);
    let mut cols = [[0.0; 2]; 4];
    let [h, s, b, c] = &mut cols;
    let fix = Fix {
        t: 0.0,
        heading: 1.0,
        sigma: fix_sigma,
    };
    f.process_block(&t, &rate, &[fix], FusionOutputs::all(h, s, b, c))
        .unwrap();
    s[0]
}

#[test]
fn a_sure_fix_on_an_unknown_heading_keeps_its_sigma() {
    for prior in [1.0f64, 1e3, 1e5, 1_048_576.0] {
        for fix in [1e-12f64, 1e-6, 1e-3, 0.0175, 0.5] {
            // sigma^2 = P r / (P + r), exactly what two independent estimates combine to
            let want = (prior * prior * fix * fix / (prior * prior + fix * fix)).sqrt();
            let got = sigma_after_one_fix(prior, fix);
            assert!(
                ((got - want) / want).abs() < 1e-12,
                "prior {prior}, fix {fix}: sigma {got}, want {want}"
            );
        }
    }
}
