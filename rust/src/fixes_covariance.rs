//! What the heading-fix filter's covariance may be: symmetric and positive semi-definite.
//!
//! A fix's update `P - r r^T / s` (`r` the covariance's first column, `s` the innovation's
//! variance) subtracts nearly all of `P` where fixes are far tighter than the gyro's noise: the
//! variances left cancel below what float64 resolves, and the update computed `P` with a scale
//! or bias variance below 0 and correlations beyond 1 (a bias variance of -8e-13 beside fixes of
//! 3e-11 rad). A covariance so rounded made later heading variances negative, and a fix whose
//! innovation variance rounded to 0 divided by it. [`semi_definite`] keeps the update's result
//! where its `L D L^T` factors show it positive semi-definite, and otherwise keeps its variances
//! and brings its covariances within them; [`check`] refuses a covariance read back (`serde`
//! feature) that is not one, within rounding. A covariance's bound is the product of the two
//! standard deviations, not the root of the variances' product: variances of 1e-160 and 1e-158
//! (valid initial sigmas) have a product below the smallest normal double.

use crate::fixes_smooth::Mat3;

/// The pivots `d` of the `L D L^T` factors of the symmetric matrix of `p`'s upper triangle (each
/// a variance given the ones before it; a factor below a pivot that is not positive taken as 0),
/// and whether they make `p` positive semi-definite (every pivot >= 0, and a pivot of 0 with no
/// covariance left below it).
fn pivots(p: &Mat3) -> ([f64; 3], bool) {
    let d0 = p[0][0];
    let (mut l10, mut l20) = (p[0][1] / d0, p[0][2] / d0);
    let mut fits = d0 >= 0.0;
    if !(d0 > 0.0 && l10.is_finite() && l20.is_finite()) {
        fits &= p[0][1] == 0.0 && p[0][2] == 0.0;
        (l10, l20) = (0.0, 0.0);
    }
    let d1 = p[1][1] - l10 * p[0][1];
    let c12 = p[1][2] - l20 * p[0][1];
    let mut l21 = c12 / d1;
    fits &= d1 >= 0.0;
    if !(d1 > 0.0 && l21.is_finite()) {
        fits &= c12 == 0.0;
        l21 = 0.0;
    }
    let d2 = p[2][2] - l20 * p[0][2] - l21 * c12;
    fits &= d2 >= 0.0;
    ([d0, d1, d2], fits)
}

/// The largest covariance two variances `a`, `b` >= 0 allow: the product of their roots.
fn most(a: f64, b: f64) -> f64 {
    libm::sqrt(a) * libm::sqrt(b)
}

/// `p` (the covariance a fix's update left) made symmetric from its upper triangle (the update
/// computes the two triangles in other orders, which differ in their last bits) and positive
/// semi-definite: as it is where it already is; else its variances are kept (one below 0 is a
/// rounding of 0: known to the float's resolution of it) and each covariance is brought within
/// what they allow, in the order the factors take them. The variances are what the update
/// resolves; where a heading is known to 1e-12 rad, its covariances are the rounding (raising
/// the pivots to 0 instead would make that rounding a variance: 1e-17 would become 1.6e9).
pub(crate) fn semi_definite(mut p: Mat3) -> Mat3 {
    (p[1][0], p[2][0], p[2][1]) = (p[0][1], p[0][2], p[1][2]);
    if pivots(&p).1 {
        return p;
    }
    let v: [f64; 3] = core::array::from_fn(|i| {
        let v = p[i][i];
        if v >= 0.0 {
            v
        } else {
            f64::EPSILON * -v
        }
    });
    let within = |c: f64, a: f64, b: f64| c.clamp(-most(a, b), most(a, b));
    let (p01, p02) = (within(p[0][1], v[0], v[1]), within(p[0][2], v[0], v[2]));
    // the scale's and the bias's variances and covariance given the heading
    let (l10, l20) = if v[0] > 0.0 {
        (p01 / v[0], p02 / v[0])
    } else {
        (0.0, 0.0)
    };
    let d1 = (v[1] - l10 * p01).max(0.0);
    let d2 = (v[2] - l20 * p02).max(0.0);
    let p12 = within(p[1][2] - l20 * p01, d1, d2) + l20 * p01;
    [[v[0], p01, p02], [p01, v[1], p12], [p02, p12, v[2]]]
}

/// Checks a covariance read back (`serde` feature): symmetric within rounding, no variance
/// below 0 (as [`semi_definite`] leaves them), and positive semi-definite within [`ROUNDING`](crate::error::ROUNDING) (no
/// covariance beyond the product of its two standard deviations): a negative bias variance read
/// back gave NaN or imaginary sigmas.
#[cfg(feature = "serde")]
pub(crate) fn check(p: &Mat3) -> Result<(), crate::Error> {
    use crate::error::check_range;
    check_range("heading variance", p[0][0], 0.0, f64::MAX, ">= 0")?;
    check_range("scale variance", p[1][1], 0.0, f64::MAX, ">= 0")?;
    check_range("bias variance", p[2][2], 0.0, f64::MAX, ">= 0")?;
    let names = [
        ["", "heading-scale covariance", "heading-bias covariance"],
        ["", "", "scale-bias covariance"],
    ];
    let mut inflated = *p;
    for i in 0..3 {
        inflated[i][i] = p[i][i] * (1.0 + crate::error::ROUNDING);
    }
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        let (c, mirror) = (p[i][j], p[j][i]);
        let bound = most(inflated[i][i], inflated[j][j]);
        let valid = "within the root of the product of its two variances, and equal to its \
                     mirror image (a covariance is symmetric and positive semi-definite)";
        let name = names[i][j];
        check_range(name, c, -bound, bound, valid)?;
        check_range(name, mirror, -bound, bound, valid)?;
        let off = libm::fabs(c - mirror);
        if off > crate::error::ROUNDING * bound {
            return Err(crate::Error::InvalidParameter {
                name,
                value: mirror,
                valid,
            });
        }
    }
    let (d, fits) = pivots(&inflated);
    if !fits {
        return Err(crate::Error::InvalidParameter {
            name: "filter covariance",
            value: d[2],
            valid: "positive semi-definite (its covariances together exceed what its variances \
                    allow: the bias variance given the heading and the scale is the value)",
        });
    }
    Ok(())
}
