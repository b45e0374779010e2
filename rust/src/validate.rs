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
    // Fast path first (one branch-free pass); search for the first fault only when it fails.
    if times_ok(t, previous_t) {
        return Ok(());
    }
    check_bounded("t", t, MAX_TIME)?;
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

/// [`check_block`] of a block of readings that must be finite, with no block before it, as long
/// as `go_on()`, asked every 2^16 samples: `Ok(false)` once stopped. Its one-pass checks go piece
/// by piece (a second for 10^8 samples); once a piece fails them the whole block is checked, so
/// that the error is the one [`check_block`] names.
pub(crate) fn check_block_while(
    t: &[f64],
    rate: &[f64],
    go_on: impl Fn() -> bool,
) -> Result<bool, Error> {
    const PIECE: usize = 1 << 16;
    let pieces_fine = rate.len() == t.len()
        && (0..t.len()).step_by(PIECE).all(|start| {
            let piece = start..t.len().min(start + PIECE);
            let previous = start.checked_sub(1).map(|i| t[i]);
            !go_on()
                || all_below(&rate[piece.clone()], MAX_READING) && times_ok(&t[piece], previous)
        });
    if !go_on() {
        return Ok(false);
    }
    if pieces_fine {
        return Ok(true);
    }
    check_block(t, rate, None, None, true).map(|()| true)
}

/// True if every value is finite and below `limit` in magnitude. Branch-free integer
/// arithmetic, so it vectorises.
#[inline]
pub(crate) fn all_below(values: &[f64], limit: f64) -> bool {
    let worst = values.iter().fold(0u64, |m, &v| m.max(magnitude_key(v)));
    worst < magnitude_key(limit)
}

/// A value's bits shifted left past the sign: an integer that orders magnitudes, since the bits
/// of a magnitude grow with it, and puts NaN and the infinities (all exponent bits set) above
/// every finite value. `magnitude_key(v) < magnitude_key(limit)` exactly when `|v| < limit`.
#[inline(always)]
fn magnitude_key(v: f64) -> u64 {
    v.to_bits() << 1
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
/// sample and no early exit, instead of a separate pass over the block (which would wait for the
/// memory the loop's work hides). Integer operations that SSE2 has no instruction for (a
/// maximum, a rotation), so that they stay in the integer registers and leave the vector
/// registers to the chain's state (`docs/performance_lab.md`).
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Checks {
    /// The largest [`interval_key`] seen.
    worst_interval: u64,
    /// The rates' bits rotated left by one (the sign to the lowest bit), OR-ed: at least the
    /// largest [`magnitude_key`] (see [`Checks::passed`]).
    readings: u64,
    /// The largest [`magnitude_key`] of a temperature seen: exact, since temperatures straddle
    /// powers of two (2, 4, ... 32 degC) where an OR would fail on valid ones.
    worst_temperature: u64,
    /// The largest [`magnitude_key`] of a timestamp checked.
    worst_time: u64,
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
        self.readings |= rate.to_bits().rotate_left(1);
        if let Some(celsius) = temperature {
            self.worst_temperature = self.worst_temperature.max(magnitude_key(celsius));
        }
    }

    /// A timestamp finite and within [`MAX_TIME`] (the loop checks the first and the last of
    /// its samples: between them, time increases).
    #[inline(always)]
    pub(crate) fn time(&mut self, t: f64) {
        self.worst_time = self.worst_time.max(magnitude_key(t));
    }

    /// The longest interval seen [s], if every one was valid (finite and >= [`MIN_INTERVAL`]);
    /// [`MIN_INTERVAL`] if none was seen.
    pub(crate) fn longest_interval(&self) -> Option<f64> {
        (self.worst_interval <= interval_key(f64::MAX))
            .then(|| f64::from_bits(self.worst_interval.wrapping_add(MIN_INTERVAL.to_bits())))
    }

    /// True if every value and interval seen was certainly valid. The rates' check is
    /// conservative: an OR is never below the largest of its operands, so an invalid rate always
    /// fails it, but so may valid rates of 2 or more in magnitude (their exponent bits OR-ed with
    /// others' can reach the limit's); the caller then checks the block exactly.
    pub(crate) fn passed(&self) -> bool {
        self.longest_interval().is_some()
            && self.readings.max(self.worst_temperature) < magnitude_key(MAX_READING)
            && self.worst_time < magnitude_key(MAX_TIME)
    }
}

/// True if every timestamp lies within [`MAX_TIME`] (so is finite) and comes at least
/// [`MIN_INTERVAL`] after the one before, the first after `previous_t`: one branch-free pass
/// over the timestamps, so it vectorises.
#[inline]
fn times_ok(t: &[f64], previous_t: Option<f64>) -> bool {
    let continues = previous_t
        .zip(t.first())
        .is_none_or(|(p, &first)| spaced(p, first));
    let first = t.first().map_or(0, |&v| magnitude_key(v));
    let pairs = t.iter().zip(t.iter().skip(1));
    let (worst, bad) = pairs.fold((first, 0u32), |(worst, bad), (&a, &b)| {
        (worst.max(magnitude_key(b)), bad | u32::from(!spaced(a, b)))
    });
    continues && worst < magnitude_key(MAX_TIME) && bad == 0
}

/// Fails with [`Error::NonFinite`] naming the first NaN or infinite value, or with
/// [`Error::OutOfRange`] naming the first value at or beyond `limit` in magnitude.
pub(crate) fn check_bounded(what: &'static str, values: &[f64], limit: f64) -> Result<(), Error> {
    // One pass for the common case: below the limit means finite too.
    if all_below(values, limit) {
        return Ok(());
    }
    check_finite_all(what, values)?;
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
    use crate::{Outputs, Pipeline, Preset};

    /// The loop's check of the readings: a NaN, an infinity or a reading at the limit, of
    /// either sign, fails it whatever valid readings come with it; the usual readings (rates
    /// below 2 rad/s, any temperature from -40 to 85 degC) pass it, so that no exact check
    /// follows; and the pipeline takes the largest usable
    /// readings (just inside [`MAX_READING`], mixed with others, where the loop's bound fails and
    /// the exact check decides) and refuses any other by its index.
    #[test]
    fn the_largest_usable_readings_are_taken_and_any_other_is_named() {
        let top = f64::from_bits(MAX_READING.to_bits() - 1);
        let usual = [1.999, -1.999, 0.0, -0.0, f64::MIN_POSITIVE, 0.3];
        let celsius = [25.0, -5.0, 0.5, 85.0, -40.0, 1.0];
        let mut checks = Checks::default();
        for (r, c) in usual.into_iter().zip(celsius) {
            checks.reading(r, Some(c));
        }
        assert!(checks.passed());
        let mut all = checks;
        for r in [top, -top] {
            all.reading(r, Some(r));
        }
        let bad = [
            f64::NAN,
            -f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            MAX_READING,
            -MAX_READING,
            f64::MAX,
        ];
        for bad in bad {
            for with in [Checks::default(), checks, all] {
                let (mut rate_check, mut temperature_check) = (with, with);
                rate_check.reading(bad, None);
                temperature_check.reading(0.0, Some(bad));
                assert!(!rate_check.passed() && !temperature_check.passed(), "{bad}");
            }
        }
        let t: [f64; 8] = core::array::from_fn(|i| i as f64);
        let mut rate = [top, -top, 0.0, -0.0, f64::MIN_POSITIVE, top, 0.3, -top];
        let mut heading = [0.0; 8];
        let mut p = Pipeline::new(Preset::Raw.config()).unwrap();
        p.process_block(&t, &rate, None, Outputs::heading(&mut heading))
            .unwrap();
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -MAX_READING] {
            rate[5] = bad;
            let mut p = Pipeline::new(Preset::Combined.config()).unwrap();
            let e = p
                .process_block(&t, &rate, None, Outputs::heading(&mut heading))
                .unwrap_err();
            assert_eq!(e.index(), Some(5), "{e}");
        }
    }

    /// Intervals on both sides of a power of two (0.75 s and 1.5 s, under a gap limit of 2 s)
    /// count no gap, and a gap among them is reported at its own length.
    #[test]
    fn gaps_are_counted_at_their_length() {
        let mut t = [0.0; 9];
        for i in 1..t.len() {
            t[i] = t[i - 1] + if i % 2 == 0 { 0.75 } else { 1.5 };
        }
        let rate = [0.01; 9];
        let mut heading = [0.0; 9];
        let mut p = Pipeline::new(Preset::Raw.config()).unwrap();
        p.process_block(&t, &rate, None, Outputs::heading(&mut heading))
            .unwrap();
        assert_eq!(p.report().gaps, 0);
        let later = t.map(|x| x + t[8] + 2.5);
        p.process_block(&later, &rate, None, Outputs::heading(&mut heading))
            .unwrap();
        assert_eq!((p.report().gaps, p.report().longest_gap), (1, 2.5));
    }

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
