//! The Rauch-Tung-Striebel smoother of the [`Fusion`](crate::fixes::Fusion) filter, for whole
//! logs: an outage bracketed by fixes gets the fixes after it too.
//!
//! Between two fixes the filter has no measurement, so the smoother needs its state only where
//! one was applied: the forward pass ([`Fusion::process_block_recording`]) stores one [`Knot`]
//! per fix applied (and one at the first sample), the backward pass ([`smooth`]) runs over the
//! knots, and a second forward pass ([`Fusion::process_block_smoothed`]) writes every sample's
//! smoothed estimate from its filtered one and the next knot's correction.
//!
//! Backward recursion over the knots (Rauch, Tung and Striebel 1965), for j = n-2 down to 0, with
//! `F` the transition from knot j to knot j+1 and `P^-` the prediction at j+1:
//! `G = P_j F^T (P^-_{j+1})^-1`, `x^s_j = x_j + G (x^s_{j+1} - x^-_{j+1})`,
//! `P^s_j = P_j + G (P^s_{j+1} - P^-_{j+1}) G^T`. A sample k between knots j and j+1 takes the
//! same form with its own filtered `x_k`, `P_k` and the transition `F_k` from it to knot j+1
//! (no measurement lies between, and the noise after k is independent of `x_k`): with
//! `w = (P^-_{j+1})^-1 (x^s_{j+1} - x^-_{j+1})` and `E = (P^-_{j+1})^-1 (P^s_{j+1} - P^-_{j+1})
//! (P^-_{j+1})^-1`, both kept at knot j+1, `x^s_k = x_k + P_k F_k^T w` and
//! `P^s_k = P_k + P_k F_k^T E F_k P_k`. Samples after the last knot keep their filtered estimate.
//!
//! [`Fusion::process_block_recording`]: crate::fixes::Fusion::process_block_recording
//! [`Fusion::process_block_smoothed`]: crate::fixes::Fusion::process_block_smoothed

/// A symmetric 3x3 matrix, row-major.
pub type Mat3 = [[f64; 3]; 3];

/// The filter where a fix was applied (or at the first sample): what the smoother needs of it.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Knot {
    /// Its time \[s\]: where the segment after it starts.
    pub(crate) t: f64,
    /// At a restart of the clock, the time on the old clock where the segment before it ends
    /// (its transition's `C` runs to there, `t` being on the new clock); None elsewhere.
    #[cfg_attr(feature = "serde", serde(default))]
    jumped_from: Option<f64>,
    /// `F[0][1]` of the transition from the knot before (the rate's integral over the interval).
    pub(crate) a: f64,
    x_pred: [f64; 3],
    p_pred: Mat3,
    /// Filtered, then smoothed by [`smooth`].
    x: [f64; 3],
    p: Mat3,
    /// After [`smooth`]: `w` and `E` of the module's text, for the samples before this knot.
    pub(crate) w: [f64; 3],
    pub(crate) e: Mat3,
}

impl Knot {
    /// A knot at `t`, `a` after the one before, predicting `(x_pred, p_pred)` and updated to
    /// `(x, p)`.
    pub(crate) fn new(t: f64, a: f64, predicted: ([f64; 3], Mat3), x: [f64; 3], p: Mat3) -> Self {
        Knot {
            t,
            jumped_from: None,
            a,
            x_pred: predicted.0,
            p_pred: predicted.1,
            x,
            p,
            w: [0.0; 3],
            e: [[0.0; 3]; 3],
        }
    }

    /// The knot of a restart of the clock: its transition from the knot before ends at `now`,
    /// the last time on the old clock (no time passes across the jump).
    pub(crate) fn jumped_from(self, now: f64) -> Self {
        Knot {
            jumped_from: Some(now),
            ..self
        }
    }

    /// The time where the transition from the knot before ends, on that knot's clock: `C` of
    /// the transition is this less that knot's time, a sample's this less its own.
    #[inline(always)]
    pub(crate) fn reached_at(&self) -> f64 {
        self.jumped_from.unwrap_or(self.t)
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
    core::array::from_fn(|i| core::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

fn mul_vec(a: &Mat3, v: &[f64; 3]) -> [f64; 3] {
    core::array::from_fn(|i| (0..3).map(|k| a[i][k] * v[k]).sum())
}

/// `P F^T` for `F = [[1, a, c], [0, 1, 0], [0, 0, 1]]`: only column 0 differs from `P`.
pub(crate) fn times_f_transposed(p: &Mat3, a: f64, c: f64) -> Mat3 {
    let mut pft = *p;
    for row in pft.iter_mut() {
        row[0] += a * row[1] + c * row[2];
    }
    pft
}

/// The smoothed state and covariance of a point with filtered `(x, p)` whose transition to the
/// next knot is `F = [[1, a, c], ...]`, given that knot's `w` and `E` (see the module's text).
#[inline(always)]
pub(crate) fn smoothed(
    x: &[f64; 3],
    p: &Mat3,
    a: f64,
    c: f64,
    w: &[f64; 3],
    e: &Mat3,
) -> ([f64; 3], Mat3) {
    let pft = times_f_transposed(p, a, c);
    let dx = mul_vec(&pft, w);
    let pe = mul(&pft, e);
    let xs = core::array::from_fn(|i| x[i] + dx[i]);
    let ps = core::array::from_fn(|i| {
        core::array::from_fn(|j| p[i][j] + (0..3).map(|l| pe[i][l] * pft[j][l]).sum::<f64>())
    });
    (xs, ps)
}

/// The Rauch-Tung-Striebel backward pass over the knots of one forward run, in place: each
/// knot's estimate becomes the smoothed one, and each keeps the correction of the samples before
/// it. Returns the number of knots it had to leave filtered because a predicted covariance was
/// singular (0 for any valid configuration).
pub fn smooth(knots: &mut [Knot]) -> usize {
    let mut left = 0;
    for j in (0..knots.len().saturating_sub(1)).rev() {
        let next = &mut knots[j + 1];
        let Some(inv) = inverse(&next.p_pred) else {
            left += 1;
            continue;
        };
        let dx: [f64; 3] = core::array::from_fn(|i| next.x[i] - next.x_pred[i]);
        let dp: Mat3 =
            core::array::from_fn(|i| core::array::from_fn(|k| next.p[i][k] - next.p_pred[i][k]));
        next.w = mul_vec(&inv, &dx);
        next.e = mul(&mul(&inv, &dp), &inv);
        let (w, e, a, c) = (next.w, next.e, next.a, next.reached_at() - knots[j].t);
        let knot = &mut knots[j];
        (knot.x, knot.p) = smoothed(&knot.x, &knot.p, a, c, &w, &e);
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
