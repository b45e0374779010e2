//! Vertical projection of a three-axis gyro: the yaw rate is the angular velocity's component
//! along the unit vector that points up in the sensor frame, `yaw rate = gyro . up`.
//!
//! `up` is what an accelerometer reads at rest (the specific force opposes gravity), or a known
//! mounting. The projection is exact while the sensor keeps that attitude; a body that tilts
//! strongly as it moves needs a full attitude filter instead.

use crate::Error;

/// The unit vector that points up, in the sensor frame (a validated, normalised `Copy` value).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Up {
    unit: [f64; 3],
}

impl Up {
    /// `direction` normalised to unit length.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] (`up`) when a component is not finite or the vector has no
    /// length to normalise (its norm is zero, or so small that it underflows).
    pub fn new(direction: [f64; 3]) -> Result<Self, Error> {
        // hypot: no overflow or underflow of the squares for very long or short vectors
        let norm_of = |[x, y, z]: [f64; 3]| libm::hypot(libm::hypot(x, y), z);
        // A norm beyond the largest float is that of the vector halved (exactly, at that size),
        // which points the same way: finite components of 1.5e308 were refused as not finite.
        let [x, y, z] = if norm_of(direction).is_infinite() {
            direction.map(|c| 0.5 * c)
        } else {
            direction
        };
        let norm = norm_of([x, y, z]);
        if !(norm.is_finite() && norm >= f64::MIN_POSITIVE) {
            let value = if norm.is_finite() { norm } else { f64::NAN };
            return Err(Error::InvalidParameter {
                name: "up",
                value,
                valid: "three finite components, not all zero (its length is shown)",
            });
        }
        Ok(Up {
            unit: [x / norm, y / norm, z / norm],
        })
    }

    /// The unit vector.
    pub fn unit(&self) -> [f64; 3] {
        self.unit
    }

    /// The rate about `up` \[rad/s\] of one three-axis reading (NaN if a component is NaN).
    #[inline]
    pub fn project(&self, gyro: [f64; 3]) -> f64 {
        let [ux, uy, uz] = self.unit;
        gyro[0] * ux + gyro[1] * uy + gyro[2] * uz
    }

    /// [`Up::project`] over a block: `out[i] = (x[i], y[i], z[i]) . up`.
    ///
    /// # Errors
    /// [`Error::LengthMismatch`] when `y`, `z` or `out` is not as long as `x` (nothing written).
    pub fn project_block(
        &self,
        x: &[f64],
        y: &[f64],
        z: &[f64],
        out: &mut [f64],
    ) -> Result<(), Error> {
        for (what, len) in [("y", y.len()), ("z", z.len()), ("out", out.len())] {
            if len != x.len() {
                return Err(Error::LengthMismatch {
                    what,
                    len,
                    expected: x.len(),
                });
            }
        }
        for (((o, &gx), &gy), &gz) in out.iter_mut().zip(x).zip(y).zip(z) {
            *o = self.project([gx, gy, gz]);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalises_and_projects() {
        let up = Up::new([0.0, 0.0, -2.0]).unwrap();
        assert_eq!(up.unit(), [0.0, 0.0, -1.0]);
        assert_eq!(up.project([1.0, 2.0, 3.0]), -3.0);
        let tilted = Up::new([3.0, 0.0, 4.0]).unwrap();
        assert_eq!(tilted.unit(), [0.6, 0.0, 0.8]);
        assert_eq!(
            Up::new([3e300, 0.0, 4e300]).unwrap().unit(),
            [0.6, 0.0, 0.8]
        );
        let mut out = [0.0; 2];
        tilted
            .project_block(&[1.0, 0.0], &[5.0, 5.0], &[0.0, 1.0], &mut out)
            .unwrap();
        assert_eq!(out, [0.6, 0.8]);
    }

    #[test]
    fn refuses_no_direction_and_mismatched_blocks() {
        for bad in [[0.0; 3], [f64::NAN, 0.0, 1.0], [f64::INFINITY, 0.0, 0.0]] {
            assert!(matches!(
                Up::new(bad),
                Err(Error::InvalidParameter { name: "up", .. })
            ));
        }
        let up = Up::new([1.0, 0.0, 0.0]).unwrap();
        let mut out = [0.0; 2];
        let e = up.project_block(&[1.0, 2.0], &[1.0], &[1.0, 2.0], &mut out);
        assert!(matches!(
            e,
            Err(Error::LengthMismatch {
                what: "y",
                len: 1,
                expected: 2
            })
        ));
        assert!(up.project([f64::NAN, 0.0, 0.0]).is_nan());
    }
}
