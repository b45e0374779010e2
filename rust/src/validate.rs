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
    check_len("rate", rate.len(), t.len())?;
    if let Some(temp) = temperature {
        check_len("temperature", temp.len(), t.len())?;
    }
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

/// True if every value is finite. Branch-free integer arithmetic, so it vectorises: a double is
/// NaN or infinite exactly when its 11 exponent bits are all set, and adding one to the exponent
/// field then carries into the top bit.
#[inline]
pub(crate) fn all_finite(values: &[f64]) -> bool {
    const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
    const ONE: u64 = 0x0010_0000_0000_0000;
    let carry = values
        .iter()
        .fold(0u64, |acc, v| acc | ((v.to_bits() & EXPONENT) + ONE));
    carry & (1 << 63) == 0
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
