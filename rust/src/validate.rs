//! Checks of a block of samples before any stage sees it, and the limits of a valid sample.
//!
//! The limits keep every output finite for every input the checks accept: with readings below
//! [`MAX_READING`], factors and biases below it too (each stage's `validate`), timestamps below
//! [`MAX_TIME`] and intervals of at least [`MIN_INTERVAL`], no sum or quotient in the pipeline
//! can reach the largest float.

use crate::stage::check_len;
use crate::Error;

/// The largest magnitude of a reading: a rate \[rad/s\] (and a temperature \[degC\]) must lie
/// strictly within +-2^20 (1,048,576), far beyond any gyro; a rate there is a wrong unit or a
/// corrupt sample. Biases, offsets and scale factors are bounded by it too.
pub const MAX_READING: f64 = 1_048_576.0;

/// The largest magnitude of a timestamp \[s\]: +-2^40 s (about 35,000 years), so that any
/// interval and any heading stays finite. Epoch seconds fit; nanoseconds read as seconds do not.
pub const MAX_TIME: f64 = 1_099_511_627_776.0;

/// The shortest interval between two samples \[s\] (1 ps): closer timestamps are duplicates or
/// times in a wrong unit, and dividing by such an interval would overflow.
pub const MIN_INTERVAL: f64 = 1e-12;

/// Checks one block: `rate` (and `temperature`, when given) as long as `t`; `t` finite, within
/// [`MAX_TIME`] and increasing by at least [`MIN_INTERVAL`], also after the previous block whose
/// last timestamp was `previous_t`; and, when `readings_must_be_finite`, every reading finite
/// and within [`MAX_READING`] (otherwise the input policy holds or skips the ones that are not).
///
/// The error names the first offending index, so nothing is processed from a bad block.
pub fn check_block(
    t: &[f64],
    rate: &[f64],
    temperature: Option<&[f64]>,
    previous_t: Option<f64>,
    readings_must_be_finite: bool,
) -> Result<(), Error> {
    check_lengths(t, rate, temperature)?;
    if readings_must_be_finite {
        check_bounded("rate", rate, MAX_READING)?;
        if let Some(temp) = temperature {
            check_bounded("temperature", temp, MAX_READING)?;
        }
    }
    check_bounded("t", t, MAX_TIME)?;
    // Fast path first (branch-free, vectorisable); search for the index only when it fails.
    let continues = previous_t
        .zip(t.first())
        .is_none_or(|(p, &first)| spaced(p, first));
    if continues && increasing(t) {
        return Ok(());
    }
    let mut previous = previous_t;
    for (index, &value) in t.iter().enumerate() {
        match previous {
            Some(p) if value <= p => {
                return Err(Error::NotIncreasing {
                    index,
                    previous: p,
                    value,
                })
            }
            Some(p) if !spaced(p, value) => {
                return Err(Error::TooClose {
                    index,
                    previous: p,
                    value,
                })
            }
            _ => previous = Some(value),
        }
    }
    Ok(())
}

/// True if `value` comes at least [`MIN_INTERVAL`] after `previous`.
#[inline(always)]
fn spaced(previous: f64, value: f64) -> bool {
    value - previous >= MIN_INTERVAL
}

/// Fails with [`Error::LengthMismatch`] unless `rate` (and `temperature`, when given) is as long
/// as `t`.
pub(crate) fn check_lengths(
    t: &[f64],
    rate: &[f64],
    temperature: Option<&[f64]>,
) -> Result<(), Error> {
    check_len("rate", rate.len(), t.len())?;
    if let Some(temp) = temperature {
        check_len("temperature", temp.len(), t.len())?;
    }
    Ok(())
}

/// True if every value is finite. Branch-free integer arithmetic, so it vectorises.
#[inline]
pub(crate) fn all_finite(values: &[f64]) -> bool {
    all_below(values, f64::INFINITY)
}

/// True if every value is finite and below `limit` in magnitude (`limit` a power of two, or
/// infinity). Branch-free integer arithmetic, so it vectorises.
#[inline]
fn all_below(values: &[f64], limit: f64) -> bool {
    values
        .iter()
        .fold(0u64, |acc, &v| acc | exponent_carry(v, limit))
        & CARRY
        == 0
}

/// The bit that [`exponent_carry`] sets for a value at or beyond its limit.
const CARRY: u64 = 1 << 63;

/// For `limit` = 2^k (or infinity, for finiteness): a double's magnitude reaches 2^k exactly when
/// its 11-bit exponent field reaches that of 2^k, and adding what takes that field to 2^11 then
/// carries into the top bit ([`CARRY`]); NaN and infinity have the largest field. OR-ed over
/// many values, the carry survives.
#[inline(always)]
fn exponent_carry(v: f64, limit: f64) -> u64 {
    const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
    (v.to_bits() & EXPONENT) + (CARRY - (limit.to_bits() & EXPONENT))
}

/// A reading the pipeline takes as it is: a rate and, if there is one, a temperature, finite and
/// within [`MAX_READING`] (any other the input policy holds or skips).
#[inline(always)]
pub(crate) fn usable_reading(rate: f64, temperature: Option<f64>) -> bool {
    let usable = |v: f64| libm::fabs(v) < MAX_READING;
    usable(rate) && temperature.is_none_or(usable)
}

/// An interval as an integer that orders the valid ones: for a finite `limit` >= [`MIN_INTERVAL`],
/// `interval_key(dt) <= interval_key(limit)` exactly when `MIN_INTERVAL <= dt <= limit`. The bits
/// of a positive float grow with its value; an interval below [`MIN_INTERVAL`] wraps around to
/// the largest keys, and a negative interval (sign bit set) or NaN lands above every finite one.
/// One comparison thus checks that time moves forward, by a valid step and without a gap.
#[inline(always)]
pub(crate) fn interval_key(dt: f64) -> u64 {
    dt.to_bits().wrapping_sub(MIN_INTERVAL.to_bits())
}

/// Validity of a block's samples, accumulated branch-free while the block is processed (see
/// [`Pipeline::process_block`](crate::Pipeline::process_block)): a few integer operations per
/// sample and no early exit, instead of a separate pass over the block.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Checks {
    /// The largest [`interval_key`] seen.
    worst_interval: u64,
    /// [`exponent_carry`] of every value seen, OR-ed.
    carry: u64,
}

impl Checks {
    /// A finite and positive interval (so, after a finite timestamp, a finite one).
    #[inline(always)]
    pub(crate) fn interval(&mut self, dt: f64) {
        self.worst_interval = self.worst_interval.max(interval_key(dt));
    }

    /// A usable reading: a rate and, when there is one, a temperature, finite and within
    /// [`MAX_READING`].
    #[inline(always)]
    pub(crate) fn reading(&mut self, rate: f64, temperature: Option<f64>) {
        self.carry |= exponent_carry(rate, MAX_READING);
        if let Some(celsius) = temperature {
            self.carry |= exponent_carry(celsius, MAX_READING);
        }
    }

    /// A timestamp finite and within [`MAX_TIME`] (the loop checks the first and the last of
    /// its samples: between them, time increases).
    #[inline(always)]
    pub(crate) fn time(&mut self, t: f64) {
        self.carry |= exponent_carry(t, MAX_TIME);
    }

    /// The longest interval seen [s], if every one was valid (finite and >= [`MIN_INTERVAL`]);
    /// [`MIN_INTERVAL`] if none was seen.
    pub(crate) fn longest_interval(&self) -> Option<f64> {
        (self.worst_interval <= interval_key(f64::MAX))
            .then(|| f64::from_bits(self.worst_interval.wrapping_add(MIN_INTERVAL.to_bits())))
    }

    /// True if every value and interval seen was valid.
    pub(crate) fn passed(&self) -> bool {
        self.longest_interval().is_some() && self.carry & CARRY == 0
    }
}

/// True if every value comes at least [`MIN_INTERVAL`] after the one before (branch-free, so it
/// vectorises).
#[inline]
fn increasing(values: &[f64]) -> bool {
    let pairs = values.iter().zip(values.iter().skip(1));
    pairs.fold(0u32, |bad, (&a, &b)| bad | u32::from(!spaced(a, b))) == 0
}

/// Fails with [`Error::NonFinite`] naming the first NaN or infinite value, or with
/// [`Error::OutOfRange`] naming the first value at or beyond `limit` in magnitude.
fn check_bounded(what: &'static str, values: &[f64], limit: f64) -> Result<(), Error> {
    check_finite_all(what, values)?;
    if all_below(values, limit) {
        return Ok(());
    }
    match values.iter().position(|v| libm::fabs(*v) >= limit) {
        Some(index) => Err(Error::OutOfRange {
            what,
            index,
            value: values[index],
            limit,
        }),
        None => Ok(()),
    }
}

/// Fails with [`Error::NonFinite`] naming the first NaN or infinite value.
pub(crate) fn check_finite_all(what: &'static str, values: &[f64]) -> Result<(), Error> {
    if all_finite(values) {
        return Ok(());
    }
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(Error::NonFinite {
            what,
            index,
            value: values[index],
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `interval_key(dt) <= interval_key(longest)` exactly when `MIN_INTERVAL <= dt <= longest`.
    #[test]
    fn interval_key_orders_the_valid_intervals() {
        let above = |x: f64| f64::from_bits(x.to_bits() + 1);
        let below = |x: f64| f64::from_bits(x.to_bits() - 1);
        let intervals = [
            0.0,
            -0.0,
            f64::from_bits(1),
            1e-300,
            below(MIN_INTERVAL),
            MIN_INTERVAL,
            0.005,
            0.01,
            above(0.01),
            2.0,
            above(2.0),
            f64::MAX,
            f64::INFINITY,
            -1.0,
            f64::NEG_INFINITY,
            f64::NAN,
            -f64::NAN,
        ];
        for longest in [MIN_INTERVAL, 0.01, 2.0, f64::MAX] {
            for dt in intervals {
                let by_key = interval_key(dt) <= interval_key(longest);
                let valid = dt >= MIN_INTERVAL && dt <= longest;
                assert_eq!(by_key, valid, "dt {dt:e}, longest {longest:e}");
            }
        }
    }
}
