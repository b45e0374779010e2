//! The heading-fix filter (rust/src/fixes.rs, its closed form between fixes in
//! fixes_segment.rs) against a textbook Kalman filter written here with matrix products: a
//! prediction `F P F^T + Q` per interval and the update at each fix; and its smoother (knots at
//! the fixes, fixes_smooth.rs) against the textbook Rauch-Tung-Striebel pass over every step.

use gyrocore::fixes::wrap_angle;
use gyrocore::fixes_smooth::Knot;
use gyrocore::{smooth, Fix, Fusion, FusionConfig, FusionOutputs};

type Mat = [[f64; 3]; 3];

fn mul(a: &Mat, b: &Mat) -> Mat {
    core::array::from_fn(|i| core::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

fn transpose(a: &Mat) -> Mat {
    core::array::from_fn(|i| core::array::from_fn(|j| a[j][i]))
}

/// One step of the textbook filter for its smoother: the transition into it, the prediction
/// and the filtered estimate, and whether it is a gyro sample (else a fix).
#[derive(Clone, Copy)]
struct Step {
    f: Mat,
    x_pred: [f64; 3],
    p_pred: Mat,
    x: [f64; 3],
    p: Mat,
    sample: bool,
}

/// The textbook filter over `x = [psi, s_bar, b_bar]`, keeping every step.
struct Reference {
    config: FusionConfig,
    x: [f64; 3],
    p: Mat,
    steps: Vec<Step>,
}

impl Reference {
    fn new(config: FusionConfig) -> Self {
        let mut p = [[0.0; 3]; 3];
        p[0][0] = config.initial_heading_sigma.powi(2);
        p[1][1] = config.initial_scale_sigma.powi(2);
        p[2][2] = config.initial_bias_sigma.powi(2);
        let x = [config.initial_heading, 1.0, -config.initial_bias];
        let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let first = Step {
            f: identity,
            x_pred: x,
            p_pred: p,
            x,
            p,
            sample: true,
        };
        Reference {
            config,
            x,
            p,
            steps: vec![first],
        }
    }

    /// Hong eq 4 over `dt` with mean rate `m`, and the white noises on psi', s_bar' and b_bar'
    /// integrated over the interval (the rate's integral linear within it).
    fn predict(&mut self, dt: f64, m: f64, sample: bool) {
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
        self.steps.push(Step {
            f,
            x_pred: self.x,
            p_pred: self.p,
            x: self.x,
            p: self.p,
            sample,
        });
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
        let step = self.steps.last_mut().unwrap();
        (step.x, step.p) = (self.x, self.p);
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

/// Noise settings large enough that every term shows in the heading's sigma.
fn config() -> FusionConfig {
    FusionConfig {
        arw: 2e-3,
        bias_walk: 1e-3,
        scale_walk: 1e-2,
        initial_heading_sigma: 0.3,
        ..FusionConfig::default()
    }
}

/// The textbook filter over the samples with the fixes between them, as the filter takes them:
/// the rate linear between samples, each fix at its own time. Returns its steps.
fn textbook(config: FusionConfig, t: &[f64], rate: &[f64], fixes: &[Fix]) -> Vec<Step> {
    let mut reference = Reference::new(config);
    let mut used = 0;
    for k in 1..t.len() {
        let (t0, r0) = (t[k - 1], rate[k - 1]);
        let (mut from, mut r_from) = (t0, r0);
        while used < fixes.len() && fixes[used].t <= t[k] {
            let f = fixes[used];
            let r_fix = r0 + (rate[k] - r0) * (f.t - t0) / (t[k] - t0);
            reference.predict(f.t - from, 0.5 * (r_from + r_fix), false);
            reference.update(&f);
            (from, r_from) = (f.t, r_fix);
            used += 1;
        }
        reference.predict(t[k] - from, 0.5 * (r_from + rate[k]), true);
    }
    reference.steps
}

/// The inverse of a 3x3 matrix by Gauss-Jordan elimination with partial pivoting.
fn invert(m: &Mat) -> Mat {
    let mut a: [[f64; 6]; 3] = core::array::from_fn(|i| {
        core::array::from_fn(|j| {
            if j < 3 {
                m[i][j]
            } else {
                f64::from(j - 3 == i)
            }
        })
    });
    for col in 0..3 {
        let pivot = (col..3)
            .max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))
            .unwrap();
        a.swap(col, pivot);
        let d = a[col][col];
        a[col].iter_mut().for_each(|v| *v /= d);
        for row in 0..3 {
            if row != col {
                let factor = a[row][col];
                let pivot_row = a[col];
                for (v, p) in a[row].iter_mut().zip(pivot_row) {
                    *v -= factor * p;
                }
            }
        }
    }
    core::array::from_fn(|i| core::array::from_fn(|j| a[i][j + 3]))
}

/// The Rauch-Tung-Striebel backward pass over every step, in place.
fn textbook_smoother(steps: &mut [Step]) {
    for k in (0..steps.len() - 1).rev() {
        let next = steps[k + 1];
        let gain = mul(
            &mul(&steps[k].p, &transpose(&next.f)),
            &invert(&next.p_pred),
        );
        let dp: Mat =
            core::array::from_fn(|i| core::array::from_fn(|j| next.p[i][j] - next.p_pred[i][j]));
        let dx: [f64; 3] = core::array::from_fn(|j| next.x[j] - next.x_pred[j]);
        let step = &mut steps[k];
        step.x =
            core::array::from_fn(|i| step.x[i] + (0..3).map(|j| gain[i][j] * dx[j]).sum::<f64>());
        let correction = mul(&mul(&gain, &dp), &transpose(&gain));
        step.p =
            core::array::from_fn(|i| core::array::from_fn(|j| step.p[i][j] + correction[i][j]));
    }
}

/// The worst differences of the four columns from the sample steps' estimates: heading
/// \[rad\], sigma (relative), bias \[rad/s\] and scale.
fn worst(cols: &[Vec<f64>; 4], steps: &[Step]) -> [f64; 4] {
    let samples = steps.iter().filter(|s| s.sample);
    let mut worst = [0.0f64; 4];
    for (k, s) in samples.enumerate() {
        let sigma = s.p[0][0].sqrt();
        let expected = [s.x[0], sigma, -s.x[2] / s.x[1], 1.0 / s.x[1] - 1.0];
        for (c, ((w, col), e)) in worst.iter_mut().zip(cols).zip(expected).enumerate() {
            let scale = if c == 1 { sigma } else { 1.0 };
            *w = w.max((col[k] - e).abs() / scale);
        }
    }
    worst
}

#[test]
fn the_closed_form_equals_the_textbook_filter_step_by_step() {
    let (t, rate, fixes) = case();
    let n = t.len();
    let mut cols = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let [heading, sigma, bias, scale] = &mut cols;
    let mut fusion = Fusion::new(config()).unwrap();
    let out = FusionOutputs::all(heading, sigma, bias, scale);
    assert_eq!(
        fusion.process_block(&t, &rate, &fixes, out),
        Ok(fixes.len())
    );
    assert_eq!(fusion.counts().rejected, 1);
    let steps = textbook(config(), &t, &rate, &fixes);
    assert_eq!(steps.iter().filter(|s| s.sample).count(), n);
    // rounding alone: the two sum the same terms in another order
    let [heading, sigma, bias, scale] = worst(&cols, &steps);
    assert!(heading < 1e-11, "heading off by {heading}");
    assert!(sigma < 1e-9, "sigma off by {sigma} (relative)");
    assert!(bias < 1e-12 && scale < 1e-12, "bias {bias}, scale {scale}");
    let e = fusion.estimate();
    let last = steps.last().unwrap();
    assert!((e.heading - last.x[0]).abs() < 1e-11);
    assert!((e.heading_sigma / last.p[0][0].sqrt() - 1.0).abs() < 1e-9);
}

#[test]
fn the_smoother_over_the_knots_equals_the_textbook_smoother_over_every_step() {
    let (t, rate, fixes) = case();
    let n = t.len();
    let mut knots: Vec<Knot> = Vec::new();
    let mut forward = Fusion::new(config()).unwrap();
    let mut heading = vec![0.0; n];
    let out = FusionOutputs::heading(&mut heading);
    forward
        .process_block_recording(&t, &rate, &fixes, out, |k| knots.push(k))
        .unwrap();
    assert_eq!(knots.len() as u64, 1 + forward.counts().applied);
    assert_eq!(smooth(&mut knots), 0);
    let mut cols = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let [heading, sigma, bias, scale] = &mut cols;
    let out = FusionOutputs::all(heading, sigma, bias, scale);
    let mut again = Fusion::new(config()).unwrap();
    assert_eq!(
        again.process_block_smoothed(&t, &rate, &fixes, &knots, out),
        Ok(fixes.len())
    );
    let mut steps = textbook(config(), &t, &rate, &fixes);
    textbook_smoother(&mut steps);
    let [heading, sigma, bias, scale] = worst(&cols, &steps);
    assert!(heading < 1e-9, "heading off by {heading}");
    assert!(sigma < 1e-7, "sigma off by {sigma} (relative)");
    assert!(bias < 1e-9 && scale < 1e-9, "bias {bias}, scale {scale}");
}
