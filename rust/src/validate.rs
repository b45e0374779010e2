//! Checks of a block of samples before any stage sees it.

use crate::stage::check_len;
use crate::Error;

/// Checks one block: `rate` (and `temperature`, when given) as long as `t`, `t` finite and
/// strictly increasing, also across the previous block whose last timestamp was `previous_t`, and,
/// when `readings_must_be_finite`, every reading finite.
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
        check_finite_all("rate", rate)?;
        if let Some(temp) = temperature {
            check_finite_all("temperature", temp)?;
        }
    }
    check_finite_all("t", t)?;
    // Fast path first (branch-free, vectorisable); search for the index only when it fails.
    let continues = previous_t
        .zip(t.first())
        .is_none_or(|(p, &first)| first > p);
    if continues && increasing(t) {
        return Ok(());
    }
    let mut previous = previous_t;
    for (index, &value) in t.iter().enumerate() {
        if let Some(p) = previous {
            if value <= p {
                return Err(Error::NotIncreasing {
                    index,
                    previous: p,
                    value,
                });
            }
        }
        previous = Some(value);
    }
    Ok(())
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
    values.iter().fold(0u64, |acc, &v| acc | exponent_carry(v)) & CARRY == 0
}

/// The bit that [`exponent_carry`] sets for a non-finite value.
const CARRY: u64 = 1 << 63;

/// A double is NaN or infinite exactly when its 11 exponent bits are all set, and adding one to
/// the exponent field then carries into the top bit ([`CARRY`]); OR-ed over many values, the
/// carry survives.
#[inline(always)]
fn exponent_carry(v: f64) -> u64 {
    const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
    const EXPONENT_ONE: u64 = 0x0010_0000_0000_0000;
    (v.to_bits() & EXPONENT) + EXPONENT_ONE
}

/// A reading the pipeline takes as it is: a finite rate and, if there is one, a finite
/// temperature (any other the input policy holds or skips).
#[inline(always)]
pub(crate) fn finite_reading(rate: f64, temperature: Option<f64>) -> bool {
    rate.is_finite() && temperature.is_none_or(f64::is_finite)
}

/// An interval as an integer that orders the valid ones: for a finite `limit` > 0,
/// `interval_key(dt) <= interval_key(limit)` exactly when `0 < dt <= limit`. The bits of a
/// positive float grow with its value; 0 wraps around to the largest key, and a negative
/// interval (sign bit set) or NaN lands above every finite one. One comparison thus checks that
/// time moves forward, by a finite step and without a gap.
#[inline(always)]
pub(crate) fn interval_key(dt: f64) -> u64 {
    dt.to_bits().wrapping_sub(1)
}

/// Validity of a block's samples, accumulated branch-free while the block is processed (see
/// [`Pipeline::process_block`](crate::Pipeline::process_block)): a few operations per sample
/// and no early exit, instead of a separate pass over the block (which would wait for the
/// memory the loop's work hides).
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Checks {
    /// The largest [`interval_key`] seen.
    worst_interval: u64,
    /// The largest bits of a reading seen, shifted left past the sign: the bits of a
    /// magnitude grow with it, and a NaN's or an infinity's (all exponent bits set) are above
    /// every finite one's. An integer maximum, so the readings' check needs no floating-point
    /// register, which the chain needs for its state (`docs/performance.md`).
    worst_reading: u64,
}

impl Checks {
    /// A finite and positive interval (so, after a finite timestamp, a finite one).
    #[inline(always)]
    pub(crate) fn interval(&mut self, dt: f64) {
        self.worst_interval = self.worst_interval.max(interval_key(dt));
    }

    /// A finite rate and, when there is one, a finite temperature.
    #[inline(always)]
    pub(crate) fn reading(&mut self, rate: f64, temperature: Option<f64>) {
        self.worst_reading = self.worst_reading.max(rate.to_bits() << 1);
        if let Some(celsius) = temperature {
            self.worst_reading = self.worst_reading.max(celsius.to_bits() << 1);
        }
    }

    /// The longest interval seen [s], if every one was valid (finite and > 0); the smallest
    /// positive float if none was seen.
    pub(crate) fn longest_interval(&self) -> Option<f64> {
        (self.worst_interval <= interval_key(f64::MAX))
            .then(|| f64::from_bits(self.worst_interval + 1))
    }

    /// True if every value and interval seen was valid.
    pub(crate) fn passed(&self) -> bool {
        self.longest_interval().is_some() && self.worst_reading < f64::INFINITY.to_bits() << 1
    }
}

/// True if every value is larger than the one before (branch-free, so it vectorises).
#[inline]
fn increasing(values: &[f64]) -> bool {
    let pairs = values.iter().zip(values.iter().skip(1));
    pairs.fold(0u32, |bad, (a, b)| bad | u32::from(b <= a)) == 0
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
    use crate::{Outputs, Pipeline, Preset};

    /// The loop's check of the readings: the largest finite ones pass, and a NaN or an
    /// infinity of either sign anywhere is refused by its index.
    #[test]
    fn the_largest_finite_readings_are_taken_and_a_non_finite_one_is_named() {
        let t: [f64; 8] = core::array::from_fn(|i| i as f64);
        let mut rate = [f64::MAX; 8];
        let mut heading = [0.0; 8];
        let mut checks = Checks::default();
        for r in [f64::MAX, -f64::MAX, 0.0, -0.0, f64::MIN_POSITIVE] {
            checks.reading(r, Some(-r));
        }
        assert!(checks.passed());
        for bad in [f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let (mut rate_check, mut temperature_check) = (checks, checks);
            rate_check.reading(bad, None);
            temperature_check.reading(0.0, Some(bad));
            assert!(!rate_check.passed() && !temperature_check.passed(), "{bad}");
        }
        let mut p = Pipeline::new(Preset::Raw.config()).unwrap();
        p.process_block(&t, &rate, None, Outputs::heading(&mut heading))
            .unwrap();
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            rate[5] = bad;
            let mut p = Pipeline::new(Preset::Combined.config()).unwrap();
            let e = p
                .process_block(&t, &rate, None, Outputs::heading(&mut heading))
                .unwrap_err();
            assert_eq!(e.index(), Some(5), "{e}");
        }
    }

    /// `interval_key(dt) <= interval_key(longest)` exactly when `0 < dt <= longest`.
    #[test]
    fn interval_key_orders_the_valid_intervals() {
        let above = |x: f64| f64::from_bits(x.to_bits() + 1);
        let intervals = [
            0.0,
            -0.0,
            f64::from_bits(1),
            1e-300,
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
        for longest in [f64::from_bits(1), 0.01, 2.0, f64::MAX] {
            for dt in intervals {
                let by_key = interval_key(dt) <= interval_key(longest);
                let valid = dt > 0.0 && dt <= longest;
                assert_eq!(by_key, valid, "dt {dt:e}, longest {longest:e}");
            }
        }
    }
}
