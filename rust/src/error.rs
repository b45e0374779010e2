//! The one error type of the core crate.

use core::fmt;

use crate::MIN_INTERVAL;

mod checks;
pub(crate) use checks::*;

/// Everything that can go wrong in the core: invalid configuration, and invalid sample blocks
/// handed to the block-processing functions (per-sample `update` never fails).
#[non_exhaustive]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Error {
    /// A configuration parameter is outside its valid range.
    InvalidParameter {
        /// Parameter name as it appears in the config struct.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// The valid range, in words.
        valid: &'static str,
    },
    /// Input slices of one block have different lengths.
    LengthMismatch {
        /// Which slice differs (`"rate"`, `"temperature"`, an output name).
        what: &'static str,
        /// Its length.
        len: usize,
        /// The length it must have: the timestamps' (the message names what else, where it is
        /// another slice: `x` of a projection, the Allan factors).
        expected: usize,
    },
    /// A sample is NaN or infinite.
    NonFinite {
        /// `"t"`, `"rate"` or `"temperature"`.
        what: &'static str,
        /// Index of the first bad sample within the block.
        index: usize,
        /// The value found.
        value: f64,
    },
    /// A sample lies at or beyond its limit in magnitude
    /// ([`MAX_TIME`](crate::MAX_TIME) for `t`, [`MAX_READING`](crate::MAX_READING)
    /// for a reading).
    OutOfRange {
        /// `"t"`, `"rate"`, `"temperature"` or `"phase"` (see [`crate::allan::MAX_PHASE`]).
        what: &'static str,
        /// Index of the first bad sample within the block.
        index: usize,
        /// The value found.
        value: f64,
        /// The limit of its magnitude.
        limit: f64,
    },
    /// A timestamp follows the one before by less than
    /// [`MIN_INTERVAL`](crate::MIN_INTERVAL).
    TooClose {
        /// Index within the block of the offending timestamp.
        index: usize,
        /// The timestamp before it (from this block or the previous one).
        previous: f64,
        /// The offending timestamp.
        value: f64,
    },
    /// Timestamps do not strictly increase at `index` (a duplicate or a step back).
    NotIncreasing {
        /// Index within the block of the first offending timestamp.
        index: usize,
        /// The timestamp before it (from this block or the previous one).
        previous: f64,
        /// The offending timestamp.
        value: f64,
    },
    /// A stream's timestamp steps back at `index` (before the last one taken): a clock that
    /// jumped back (a time sync, a sensor's counter restarted, two logs run together) or samples
    /// out of order. Streams ([`Pipeline`](crate::Pipeline),
    /// [`FusedPipeline`](crate::FusedPipeline), [`Fusion`](crate::Fusion)) go on after a jump
    /// with `restart_clock()`; a duplicate is [`Error::NotIncreasing`].
    ClockStepsBack {
        /// Index within the block of the first offending timestamp.
        index: usize,
        /// The timestamp before it (from this block or the previous one).
        previous: f64,
        /// The offending timestamp.
        value: f64,
    },
    /// `restart_clock()` while the rest window is measured: the window lies on the clock that
    /// jumped, and its bias would mix two clocks.
    ClockRestartInWindow {
        /// Window start \[s\].
        start: f64,
        /// Window end \[s\].
        end: f64,
    },
    /// The configuration asks for a temperature signal and none was given.
    MissingTemperature,
    /// No sample lies in the rest window, so there is no static bias to measure.
    EmptyRestWindow {
        /// Window start \[s\].
        start: f64,
        /// Window end \[s\].
        end: f64,
        /// The first timestamp seen \[s\].
        first: f64,
        /// The last timestamp seen \[s\]: for a stream's block, the first one past the window; from
        /// [`Pipeline::rest_window_missed`](crate::Pipeline::rest_window_missed), the last one taken.
        last: f64,
    },
    /// A statistic needs a longer record than it was given (an averaging time too long for it).
    TooShort {
        /// Samples needed.
        needed: usize,
        /// Samples given.
        len: usize,
    },
    /// A pipeline read back (`serde` feature) whose stages are not the ones its configuration
    /// builds: a state edited by hand, damaged, or saved by another version.
    StagesMismatch,
}

impl Error {
    /// The index of the offending sample, for errors about one sample.
    pub fn index(&self) -> Option<usize> {
        match *self {
            Error::NonFinite { index, .. }
            | Error::OutOfRange { index, .. }
            | Error::TooClose { index, .. }
            | Error::NotIncreasing { index, .. }
            | Error::ClockStepsBack { index, .. } => Some(index),
            _ => None,
        }
    }

    /// The same error with its sample index counted from `offset` (a chunked reader passes the
    /// index of the chunk's first sample in the whole log, so messages name the log's sample).
    /// The sum saturates at `usize::MAX`: an offset near it (on a 32-bit target, the count of a
    /// 50-day log at 1 kHz) overflowed, a panic in a debug build.
    pub fn with_index_offset(mut self, offset: usize) -> Self {
        match &mut self {
            Error::NonFinite { index, .. }
            | Error::OutOfRange { index, .. }
            | Error::TooClose { index, .. }
            | Error::NotIncreasing { index, .. }
            | Error::ClockStepsBack { index, .. } => *index = index.saturating_add(offset),
            _ => {}
        }
        self
    }

    /// The error as a stream reports it: a timestamp that steps back (not a duplicate) becomes
    /// [`Error::ClockStepsBack`], whose words name the way on after a clock's jump.
    pub(crate) fn of_stream(self) -> Self {
        match self {
            Error::NotIncreasing {
                index,
                previous,
                value,
            } if value < previous => Error::ClockStepsBack {
                index,
                previous,
                value,
            },
            e => e,
        }
    }

    /// The error as a caller that gave a whole series at once reports it (a log, a file: one
    /// series to sort or mend, with no stream to restart): [`Error::ClockStepsBack`] becomes
    /// [`Error::NotIncreasing`], whose words leave out `restart_clock()`; any other is itself.
    /// A stream's error ([`Pipeline`](crate::Pipeline), [`Fusion`](crate::Fusion)) fed the
    /// whole series in one block, or in chunks read from one file, is mapped so.
    pub fn of_series(self) -> Self {
        match self {
            Error::ClockStepsBack {
                index,
                previous,
                value,
            } => Error::NotIncreasing {
                index,
                previous,
                value,
            },
            e => e,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::InvalidParameter { name, value, valid } => {
                let value = Num(value);
                write!(f, "invalid parameter {name} = {value}: must be {valid}")
            }
            Error::LengthMismatch {
                what,
                len,
                expected,
            } => write!(
                f,
                "length mismatch: {what} has {len} samples but {} has {expected}",
                measured_against(what)
            ),
            Error::NonFinite { what, index, value } => write!(
                f,
                "{what}[{index}] is {value}: samples must be finite (drop or fill them first)"
            ),
            Error::OutOfRange {
                what,
                index,
                value,
                limit,
            } => {
                let (unit, hint) = match what {
                    "t" => (
                        "s",
                        "give seconds, e.g. from the first sample or a recent epoch \
                         (nanoseconds read as seconds are this large)",
                    ),
                    "temperature" => ("degC", "give degrees Celsius"),
                    "phase" => (
                        "rad",
                        "its Allan variance overflows; the phase of readings within +-2^20 \
                         rad/s over 2^40 s stays below it: check the unit",
                    ),
                    _ => (
                        "rad/s",
                        "no gyro reads that fast: check the unit and the column",
                    ),
                };
                let value = Num(value);
                write!(
                    f,
                    "{what}[{index}] = {value} {unit} is beyond +-{limit} {unit}: {hint}"
                )
            }
            Error::TooClose {
                index,
                previous,
                value,
            } => write!(
                f,
                "t[{index}] = {} follows {} by {:e} s, under the shortest interval of \
                 {MIN_INTERVAL:e} s: drop duplicate samples, or give the times in seconds",
                Num(value),
                Num(previous),
                value - previous
            ),
            Error::NotIncreasing {
                index,
                previous,
                value,
            } => not_increasing(f, index, previous, value),
            Error::ClockStepsBack {
                index,
                previous,
                value,
            } => {
                // a series' words first, then a stream's way on: one sentence, written once
                not_increasing(f, index, previous, value)?;
                write!(
                    f,
                    "; where the clock jumped back (a time sync, a sensor restarted, two logs \
                     run together), call restart_clock() and give the samples from t[{index}] \
                     on: the heading, bias and estimates are kept, and nothing is integrated \
                     across the jump"
                )
            }
            Error::ClockRestartInWindow { start, end } => write!(
                f,
                "restart_clock() while the rest window [{start}, {end}] s is measured: the \
                 window lies on the clock that jumped back, and its bias would mix two clocks; \
                 restart the clock once the window is over, or reset() the stream"
            ),
            Error::MissingTemperature => write!(
                f,
                "the temperature scale-factor model is configured but no temperature was given"
            ),
            Error::EmptyRestWindow {
                start,
                end,
                first,
                last,
            } => write!(
                f,
                "the bias window [{start}, {end}] s holds no sample of the samples from t = \
                 {first} to {last} s (give the window in the samples' own time base)"
            ),
            Error::TooShort { needed, len } => write!(
                f,
                "the record is too short: {len} samples given, {needed} needed \
                 (choose a shorter averaging time or a longer record)"
            ),
            Error::StagesMismatch => f.write_str(
                "the stored pipeline's stages do not match its stored configuration (a state \
                 edited by hand, damaged, or saved by another version): to change a parameter, \
                 build a new pipeline from the edited configuration",
            ),
        }
    }
}

impl core::error::Error for Error {}

/// The words of [`Error::NotIncreasing`], which [`Error::ClockStepsBack`] begins with.
fn not_increasing(
    f: &mut fmt::Formatter<'_>,
    index: usize,
    previous: f64,
    value: f64,
) -> fmt::Result {
    write!(
        f,
        "timestamps must strictly increase: t[{index}] = {value} follows {previous} \
         (sort the log and drop duplicate timestamps)"
    )
}

/// What a slice named `what` in [`Error::LengthMismatch`] is measured against: the timestamps,
/// but for the slices of a projection (`x`), of the Allan variances (their averaging factors, and
/// the phase one longer than the rate) and an output slice (its input, whichever that is).
fn measured_against(what: &str) -> &'static str {
    match what {
        "y" | "z" => "x",
        "variance" | "terms" => "factors",
        "phase" => "rate + 1",
        "out" => "the input",
        _ => "t",
    }
}

/// A number as a message shows it: in full where that is short (a timestamp keeps its digits),
/// in exponent form where it is extreme (`1e308`, not 309 digits).
pub(crate) struct Num(pub(crate) f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let magnitude = libm::fabs(self.0);
        if magnitude >= 1e15 || (magnitude < 1e-6 && magnitude > 0.0) {
            write!(f, "{:e}", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}
