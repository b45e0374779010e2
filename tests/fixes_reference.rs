//! The heading-fix filter (rust/src/fixes.rs, its closed form between fixes in
//! fixes_segment.rs) against a textbook Kalman filter written here with matrix products: a
//! prediction `F P F^T + Q` per interval and the update at each fix.

use gyrocore::fixes::wrap_angle;
use gyrocore::{Fix, Fusion, FusionConfig, FusionOutputs};

type Mat = [[f64; 3]; 3];

fn mul(a: &Mat, b: &Mat) -> Mat {
    core::array::from_fn(|i| core::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

fn transpose(a: &Mat) -> Mat {
    core::array::from_fn(|i| core::array::from_fn(|j| a[j][i]))
}

/// The textbook filter over `x = [psi, s_bar, b_bar]`.
struct Reference {
    config: FusionConfig,
    x: [f64; 3],
    p: Mat,
}

impl Reference {
    fn new(config: FusionConfig) -> Self {
        let mut p = [[0.0; 3]; 3];
        p[0][0] = config.initial_heading_sigma.powi(2);
        p[1][1] = config.initial_scale_sigma.powi(2);
        p[2][2] = config.initial_bias_sigma.powi(2);
        Reference {
            config,
            x: [config.initial_heading, 1.0, -config.initial_bias],
            p,
        }
    }

    /// Hong eq 4 over `dt` with mean rate `m`, and the white noises on psi', s_bar' and b_bar'
    /// integrated over the interval (the rate's integral linear within it).
    fn predict(&mut self, dt: f64, m: f64) {
        let (qa, qs, qb) = (
            self.config.arw.powi(2),
            self.config.scale_walk.powi(2),
            self.config.bias_walk.powi(2),
        );
        let f = [[1.0, dt * m, dt], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let q = [
            [
                qa * dt + (qs * m * m + qb) * dt.powi(3) / 3.0,
                qs * m * dt * dt / 2.0,
                qb * dt * dt / 2.0,
            ],
            [qs * m * dt * dt / 2.0, qs * dt, 0.0],
            [qb * dt * dt / 2.0, 0.0, qb * dt],
        ];
        self.x[0] += dt * (self.x[1] * m + self.x[2]);
        let fpf = mul(&mul(&f, &self.p), &transpose(&f));
        self.p = core::array::from_fn(|i| core::array::from_fn(|j| fpf[i][j] + q[i][j]));
    }

    fn update(&mut self, fix: &Fix) {
        let s = self.p[0][0] + fix.sigma * fix.sigma;
        let nu = wrap_angle(fix.heading - self.x[0]);
        if nu * nu > self.config.gate * s {
            return;
        }
        let k: [f64; 3] = core::array::from_fn(|i| self.p[i][0] / s);
        let row = self.p[0];
        self.x = core::array::from_fn(|i| self.x[i] + k[i] * nu);
        self.p = core::array::from_fn(|i| core::array::from_fn(|j| self.p[i][j] - k[i] * row[j]));
    }
}

/// Irregular samples of a turning gyro, and fixes between them (one half a turn off).
fn case() -> (Vec<f64>, Vec<f64>, Vec<Fix>) {
    let mut t = vec![0.0];
    for k in 1..6000 {
        t.push(t[k - 1] + 0.01 + 0.004 * ((k as f64) * 0.7).sin());
    }
    let rate: Vec<f64> = t
        .iter()
        .map(|&t| 0.02 + 0.6 * (0.11 * t).sin() + 0.3 * (1.3 * t).cos())
        .collect();
    // the gyro's own heading from 0.2 rad, and a wandering error on the fixes
    let mut psi = vec![0.2];
    for k in 1..t.len() {
        psi.push(psi[k - 1] + (t[k] - t[k - 1]) * 0.5 * (rate[k - 1] + rate[k]));
    }
    let mut fixes: Vec<Fix> = (0..t.len())
        .step_by(37)
        .filter(|k| !(2000..=4500).contains(k)) // an outage in the middle
        .map(|k| Fix {
            t: t[k] + 0.0031,
            heading: psi[k] - 0.01 * t[k] + 0.02 * (k as f64).sin(),
            sigma: 0.02,
        })
        .collect();
    fixes[10].heading += std::f64::consts::PI; // the gate rejects it
    (t, rate, fixes)
}

#[test]
fn the_closed_form_equals_the_textbook_filter_step_by_step() {
    let config = FusionConfig {
        // walks large enough that every noise term shows in the heading's sigma
        arw: 2e-3,
        bias_walk: 1e-3,
        scale_walk: 1e-2,
        initial_heading_sigma: 0.3,
        ..FusionConfig::default()
    };
    let (t, rate, fixes) = case();
    let n = t.len();
    let mut cols = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let [heading, sigma, bias, scale] = &mut cols;
    let mut fusion = Fusion::new(config).unwrap();
    let out = FusionOutputs::all(heading, sigma, bias, scale);
    assert_eq!(
        fusion.process_block(&t, &rate, &fixes, out),
        Ok(fixes.len())
    );
    assert_eq!(fusion.counts().rejected, 1);

    let mut reference = Reference::new(config);
    let mut used = 0;
    let (mut worst_heading, mut worst_sigma) = (0.0f64, 0.0f64);
    for k in 0..n {
        if k > 0 {
            let (t0, r0) = (t[k - 1], rate[k - 1]);
            let (mut from, mut r_from) = (t0, r0);
            while used < fixes.len() && fixes[used].t <= t[k] {
                let f = fixes[used];
                let r_fix = r0 + (rate[k] - r0) * (f.t - t0) / (t[k] - t0);
                reference.predict(f.t - from, 0.5 * (r_from + r_fix));
                reference.update(&f);
                (from, r_from) = (f.t, r_fix);
                used += 1;
            }
            reference.predict(t[k] - from, 0.5 * (r_from + rate[k]));
        }
        let x = &reference.x;
        worst_heading = worst_heading.max((cols[0][k] - x[0]).abs());
        let s = reference.p[0][0].sqrt();
        worst_sigma = worst_sigma.max((cols[1][k] - s).abs() / s);
        assert!((cols[2][k] + x[2] / x[1]).abs() < 1e-12, "bias at {k}");
        assert!(
            (cols[3][k] - (1.0 / x[1] - 1.0)).abs() < 1e-12,
            "scale at {k}"
        );
    }
    // rounding alone: the two sum the same terms in another order
    assert!(worst_heading < 1e-11, "heading off by {worst_heading}");
    assert!(worst_sigma < 1e-9, "sigma off by {worst_sigma} (relative)");
    let e = fusion.estimate();
    assert!((e.heading - reference.x[0]).abs() < 1e-11);
    assert!((e.heading_sigma / reference.p[0][0].sqrt() - 1.0).abs() < 1e-9);
}
