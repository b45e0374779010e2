//! The checks every stage's settings and read-back state go through: each fails with the
//! [`Error`] that names the value and what it must be.

use super::Error;
use crate::{MAX_READING, MAX_TIME};

/// Checks that `value` lies in `[lo, hi]` (both finite or infinite bounds allowed, NaN rejected).
pub(crate) fn check_range(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    valid: &'static str,
) -> Result<(), Error> {
    if value >= lo && value <= hi {
        Ok(())
    } else {
        Err(Error::InvalidParameter { name, value, valid })
    }
}

/// Checks that `value` is finite and strictly positive.
pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<(), Error> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            valid: "finite and > 0",
        })
    }
}

/// Checks a reading read back that the input policy took (a state's last reading, which it
/// holds over a NaN): finite and below [`MAX_READING`] in magnitude, as
/// [`usable_reading`](crate::validate::usable_reading) takes one.
#[cfg(feature = "serde")]
pub(crate) fn check_usable(name: &'static str, value: f64) -> Result<(), Error> {
    if crate::validate::usable_reading(value, None) {
        Ok(())
    } else {
        let valid = "within +-2^20, exclusive (a usable reading: one the input policy takes)";
        Err(Error::InvalidParameter { name, value, valid })
    }
}

/// The relative difference a value read back may have from the one the rest of its state gives
/// (a bias from its window's sums, a covariance's variances against their rebuilt bound): a state
/// written without exact floats (`serde_json` without `float_roundtrip`) stays far within it.
#[cfg(feature = "serde")]
pub(crate) const ROUNDING: f64 = 1.0 / (1u64 << 36) as f64;

/// Checks an integral of readings over `duration` \[s\] read back (a block's, a rest window's):
/// its mean within +-2^21 rad/s, a reading's limit with room for rounding. One of 1e308 over a
/// duration of 1e-300 gave an infinite mean.
#[cfg(feature = "serde")]
pub(crate) fn check_integral(
    name: &'static str,
    integral: f64,
    duration: f64,
) -> Result<(), Error> {
    let valid = "its mean over its duration within +-2^21 rad/s (a reading's limit, and room \
                 for rounding)";
    check_mean_within(name, integral, duration, 2.0 * MAX_READING, valid)
}

/// Checks an integral of readings over `duration` \[s\] read back whose mean becomes a bias (the
/// static bias test's, a rest's): that mean a reading, within +-2^20 rad/s with no room, as the
/// bias it gives must be on the next read-back. One of 2^20 rad over 0.79 s was accepted, its
/// bias of 1.3e6 rad/s ran, and the state it left no longer read back.
#[cfg(feature = "serde")]
pub(crate) fn check_mean(name: &'static str, integral: f64, duration: f64) -> Result<(), Error> {
    let valid = "its mean over its duration a reading: within +-2^20 rad/s (0 over no time)";
    check_mean_within(name, integral, duration, MAX_READING, valid)
}

/// `integral / duration` within `limit` in magnitude (the mean itself, as it is used), and an
/// integral of 0 over no time.
#[cfg(feature = "serde")]
fn check_mean_within(
    name: &'static str,
    integral: f64,
    duration: f64,
    limit: f64,
    valid: &'static str,
) -> Result<(), Error> {
    let within = if duration > 0.0 {
        libm::fabs(integral / duration) <= limit
    } else {
        integral == 0.0
    };
    if within {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name,
            value: integral,
            valid,
        })
    }
}

/// Checks a bias, offset or other value in the units of a reading: at most
/// [`MAX_READING`] in magnitude.
pub(crate) fn check_reading(name: &'static str, value: f64) -> Result<(), Error> {
    check_range(
        name,
        value,
        -MAX_READING,
        MAX_READING,
        "finite and at most 2^20 = 1048576 in magnitude (the limit of a reading)",
    )
}

/// Checks a size (a noise density, a random walk, an increment): >= 0 and at most
/// [`MAX_READING`], as a reading, so that its square summed over any time span stays finite.
pub(crate) fn check_magnitude(name: &'static str, value: f64) -> Result<(), Error> {
    let valid = "finite, >= 0 and at most 2^20 = 1048576 (the limit of a reading)";
    check_range(name, value, 0.0, MAX_READING, valid)
}

/// Checks a scale factor: > 0 and at most [`MAX_READING`].
pub(crate) fn check_factor(name: &'static str, value: f64) -> Result<(), Error> {
    let valid = "> 0 and at most 2^20 = 1048576";
    check_range(name, value, f64::MIN_POSITIVE, MAX_READING, valid)
}

/// Checks a duration \[s\]: > 0 and at most [`MAX_TIME`].
pub(crate) fn check_duration(name: &'static str, value: f64) -> Result<(), Error> {
    let valid = "> 0 and at most 2^40 s (about 35,000 years)";
    check_range(name, value, f64::MIN_POSITIVE, MAX_TIME, valid)
}

/// Checks that `value` is finite.
pub(crate) fn check_finite(name: &'static str, value: f64) -> Result<(), Error> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            valid: "finite",
        })
    }
}

/// The largest magnitude of a heading \[rad\], rate \[rad/s\] or other value a state read back
/// (`serde` feature) may hold where no tighter bound applies: 2^256, far beyond what valid input
/// reaches (a rate of about 2^183, where the de-lag of HDR's largest step of about 2^101 meets the
/// shortest interval, over at most 2^41 s) and far below where the next sample's sums overflow.
#[cfg(feature = "serde")]
pub(crate) const MAX_STORED: f64 = 1.157_920_892_373_162e77;

/// The largest magnitude of a heading \[rad\] a state read back may hold (a pipeline's, an
/// integrator's, the heading-fix filter's): 2^225. A heading is its initial value (within 2^20
/// rad) and the integral of the rate its integrator is fed, which valid input keeps below 2^183
/// rad/s (see [`MAX_STORED`]: the de-lag of HDR's largest step at the shortest interval; a
/// stand-alone integrator and the filter's own blocks take readings within 2^20), over
/// timestamps at most 2^41 s apart: below 2^20 + 2^224. A heading beyond it is a state edited or
/// damaged, on which no increment counts any more (at 2^256 rad, the float's spacing is 2^204).
/// A stand-alone integrator fed by `step`, which keeps no clock, would need 2^164 calls of the
/// longest interval at the largest reading to pass it.
#[cfg(feature = "serde")]
pub(crate) const MAX_HEADING: f64 = MAX_STORED / 2_147_483_648.0;

/// Fails unless a heading read back lies within +-[`MAX_HEADING`] (so is finite).
#[cfg(feature = "serde")]
pub(crate) fn check_heading(name: &'static str, value: f64) -> Result<(), Error> {
    let valid = "within +-2^225 rad (5.4e67), beyond the headings valid input reaches: its \
                 initial heading within 2^20 rad, and a rate below 2^183 rad/s over 2^41 s";
    check_range(name, value, -MAX_HEADING, MAX_HEADING, valid)
}

/// Fails unless a value read back lies within +-[`MAX_STORED`] (so is finite).
#[cfg(feature = "serde")]
pub(crate) fn check_stored(name: &'static str, value: f64) -> Result<(), Error> {
    let valid = "within +-2^256, beyond what valid input reaches";
    check_range(name, value, -MAX_STORED, MAX_STORED, valid)
}
