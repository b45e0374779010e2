//! The Rauch-Tung-Striebel smoother of the [`Fusion`](crate::fixes::Fusion) filter, for whole
//! logs: the forward pass stores one [`Step`] per gyro sample and per fix
//! ([`Fusion::process_block_recording`](crate::fixes::Fusion::process_block_recording)), the
//! backward pass ([`smooth`]) corrects each step with everything after it, so that an outage
//! bracketed by fixes gets the fixes after it too.
//!
//! Backward recursion (Rauch, Tung and Striebel 1965), for steps k = n-2 down to 0:
//! `C = P_k F_{k+1}^T (P^-_{k+1})^-1`, `x^s_k = x_k + C (x^s_{k+1} - x^-_{k+1})`,
//! `P^s_k = P_k + C (P^s_{k+1} - P^-_{k+1}) C^T`.

use crate::fixes::Estimate;

/// A symmetric 3x3 matrix, row-major.
pub type Mat3 = [[f64; 3]; 3];

/// What the smoother needs of one filter step: the transition into it, the predicted state and
/// covariance, and the filtered ones (replaced by the smoothed ones by [`smooth`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// `F[0][1]` of the transition into this step (interval times mean rate).
    a: f64,
    /// `F[0][2]` of the transition (the interval).
    c: f64,
    x_pred: [f64; 3],
    p_pred: Mat3,
    x: [f64; 3],
    p: Mat3,
    /// A gyro sample (not a fix).
    pub sample: bool,
}

impl Step {
    /// A step with transition `[[1, a, c], [0, 1, 0], [0, 0, 1]]` predicting `(x, p)`, before any
    /// update (filtered = predicted).
    pub(crate) fn new(a: f64, c: f64, x: &[f64; 3], p: &Mat3) -> Self {
        Step {
            a,
            c,
            x_pred: *x,
            p_pred: *p,
            x: *x,
            p: *p,
            sample: false,
        }
    }

    /// The step marked as a gyro sample.
    pub(crate) fn at_sample(mut self) -> Self {
        self.sample = true;
        self
    }

    /// Sets the filtered state after a fix's update.
    pub(crate) fn set_filtered(&mut self, x: &[f64; 3], p: &Mat3) {
        (self.x, self.p) = (*x, *p);
    }

    /// The estimate of this step (filtered, or smoothed after [`smooth`]).
    pub fn estimate(&self) -> Estimate {
        Estimate::of(&self.x, &self.p)
    }
}

/// The inverse of a symmetric positive-definite 3x3 matrix by cofactors, or None if it is
/// singular or not finite.
fn inverse(m: &Mat3) -> Option<Mat3> {
    let c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    let c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    let c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    let det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
    if !(det.is_finite() && det > 0.0) {
        return None;
    }
    let c11 = m[0][0] * m[2][2] - m[0][2] * m[2][0];
    let c12 = m[0][2] * m[1][0] - m[0][0] * m[1][2];
    let c22 = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let inv = [
        [c00 / det, c01 / det, c02 / det],
        [c01 / det, c11 / det, c12 / det],
        [c02 / det, c12 / det, c22 / det],
    ];
    Some(inv)
}

fn mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut out = [[0.0; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    out
}

/// The Rauch-Tung-Striebel backward pass over the steps of one forward run, in place: each
/// step's estimate becomes the smoothed one. Returns the number of steps it had to leave
/// filtered because a predicted covariance was singular (0 for any valid configuration).
pub fn smooth(steps: &mut [Step]) -> usize {
    let mut left = 0;
    for k in (0..steps.len().saturating_sub(1)).rev() {
        let next = steps[k + 1];
        let Some(inv) = inverse(&next.p_pred) else {
            left += 1;
            continue;
        };
        let step = &mut steps[k];
        // P_k F^T: only F's first row differs from the identity, so only column 0 changes.
        let mut pft = step.p;
        for row in pft.iter_mut() {
            row[0] += next.a * row[1] + next.c * row[2];
        }
        let gain = mul(&pft, &inv);
        let dx: [f64; 3] = core::array::from_fn(|i| next.x[i] - next.x_pred[i]);
        let dp: Mat3 =
            core::array::from_fn(|i| core::array::from_fn(|j| next.p[i][j] - next.p_pred[i][j]));
        for (i, xi) in step.x.iter_mut().enumerate() {
            *xi += (0..3).map(|j| gain[i][j] * dx[j]).sum::<f64>();
        }
        let gdp = mul(&gain, &dp);
        for (row, g) in step.p.iter_mut().zip(&gdp) {
            for (pij, gain_j) in row.iter_mut().zip(&gain) {
                *pij += (0..3).map(|l| g[l] * gain_j[l]).sum::<f64>();
            }
        }
    }
    left
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_of_a_spd_matrix_is_its_inverse() {
        let m = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]];
        let inv = inverse(&m).unwrap();
        let id = mul(&m, &inv);
        for (i, row) in id.iter().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((v - expected).abs() < 1e-14, "{i},{j}: {v}");
            }
        }
        assert!(inverse(&[[0.0; 3]; 3]).is_none());
    }
}
