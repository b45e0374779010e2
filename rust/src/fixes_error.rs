//! The errors of the heading-fix filter ([`Fusion`](crate::Fusion)): a bad gyro block or
//! configuration (the core's [`Error`]), or a bad fix named by its index, field and value.

use core::fmt;

use crate::error::Num;
use crate::Error;

/// What was wrong with a fix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FixProblem {
    /// NaN or infinite.
    NonFinite,
    /// A sigma that is not > 0.
    NotPositive,
    /// A time beyond +-2^40 s, a heading beyond +-2^20 rad, or a sigma outside
    /// [[`MIN_FIX_SIGMA`](crate::fixes::MIN_FIX_SIGMA), 2^20] rad.
    OutOfRange,
    /// Earlier than the fix before it (at `previous`).
    OutOfOrder {
        /// The time of the fix before \[s\].
        previous: f64,
    },
    /// Earlier than a gyro sample already processed (at `processed`).
    Late {
        /// The last time processed \[s\].
        processed: f64,
    },
}

/// An error of [`Fusion`](crate::Fusion): a bad gyro block or configuration, or a bad fix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FusionError {
    /// The gyro samples or the configuration (the core's error).
    Gyro(Error),
    /// A fix that cannot be used.
    Fix {
        /// Index of the fix within the fixes given.
        index: usize,
        /// `"t"`, `"heading"` or `"sigma"`.
        what: &'static str,
        /// The value found.
        value: f64,
        /// What is wrong with it.
        problem: FixProblem,
    },
}

impl FusionError {
    /// The error as a caller that gave a whole series at once reports it
    /// ([`Error::of_series`]): a step back of the gyro's clock is a series' to sort or mend, with
    /// no stream to restart.
    pub fn of_series(self) -> Self {
        match self {
            FusionError::Gyro(e) => FusionError::Gyro(e.of_series()),
            e => e,
        }
    }
}

impl From<Error> for FusionError {
    fn from(e: Error) -> Self {
        FusionError::Gyro(e)
    }
}

impl fmt::Display for FusionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (index, what, value, problem) = match *self {
            FusionError::Gyro(e) => return e.fmt(f),
            FusionError::Fix {
                index,
                what,
                value,
                problem,
            } => (index, what, value, problem),
        };
        write!(f, "fix {index}: {what} = {} ", Num(value))?;
        match problem {
            FixProblem::NonFinite => f.write_str("is not finite; drop or repair the fix"),
            FixProblem::NotPositive => f.write_str("must be > 0 (a standard deviation in rad)"),
            FixProblem::OutOfRange => f.write_str(match what {
                "t" => "is beyond +-2^40 s; check the time unit",
                "heading" => "is beyond +-2^20 rad; check the unit (radians)",
                _ => "is outside [1e-12, 2^20] rad; check the unit (radians)",
            }),
            FixProblem::OutOfOrder { previous } => write!(
                f,
                "comes before the fix before it (t = {previous}); sort the fixes by time"
            ),
            FixProblem::Late { processed } => write!(
                f,
                "comes before the last gyro sample processed (t = {processed}); pass each fix \
                 with the block of samples that reaches its time"
            ),
        }
    }
}

// `core::error::Error`, as the core's `Error`: a `no_std` embedder's `?` into its own error type
// (or `Box<dyn Error>`) takes both. No `source`: the message of `Gyro` is the core error's own.
impl core::error::Error for FusionError {}
