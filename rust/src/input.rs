//! What the pipeline does with input that is not a clean, regular stream: non-finite readings and
//! gaps. Non-increasing or non-finite timestamps are never guessed at: block processing rejects
//! them, and the per-sample `update` (which cannot fail) skips such a sample untouched.

use crate::error::check_range;
use crate::{Error, MIN_INTERVAL};

/// What to do with a rate (or temperature) reading that is NaN, infinite or beyond
/// [`MAX_READING`](crate::MAX_READING) in magnitude, or a temperature missing where the
/// temperature model needs one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum NonFinite {
    /// Reject the block, naming the first bad index. (`update`, which cannot fail, skips the sample.)
    #[default]
    Error,
    /// Use the last finite reading in its place (skip it if there is none yet).
    Hold,
    /// Leave the sample out: the filters never see it; its output row repeats the heading and drift
    /// so far, with a NaN rate; the next sample's interval spans the hole.
    Skip,
}

/// What to do when the interval between two samples exceeds [`InputPolicy::gap_limit`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum GapAction {
    /// Integrate across the gap as across any interval (and count it).
    #[default]
    Bridge,
    /// Also restart HDR, the low-pass and the de-lag: their memory predates the gap. The heading and
    /// the static bias carry on.
    Reset,
}

/// The input policy of a [`crate::Pipeline`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct InputPolicy {
    /// Non-finite readings.
    pub non_finite: NonFinite,
    /// Longest interval that is not a gap \[s\], > 0 (infinity: never a gap).
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_float"))]
    pub gap_limit: f64,
    /// What a gap does.
    pub gap_action: GapAction,
}

impl Default for InputPolicy {
    fn default() -> Self {
        InputPolicy {
            non_finite: NonFinite::Error,
            gap_limit: 2.0,
            gap_action: GapAction::Bridge,
        }
    }
}

impl InputPolicy {
    /// Checks `gap_limit`.
    pub fn validate(&self) -> Result<(), Error> {
        check_range(
            "gap_limit",
            self.gap_limit,
            MIN_INTERVAL,
            f64::INFINITY,
            ">= 1e-12 s, the shortest interval (infinity: no gap detection)",
        )
    }
}

/// Counts of what the input policy did, since the pipeline was created or reset. Each count
/// saturates at `u64::MAX`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct InputReport {
    /// Readings [`NonFinite::Hold`] replaced by the last usable one.
    pub held: u64,
    /// Samples left out: readings not finite or beyond [`MAX_READING`](crate::MAX_READING) (or
    /// a missing temperature the model needs) that the policy does not hold, and, in `update`,
    /// timestamps that are not finite, lie beyond [`MAX_TIME`](crate::MAX_TIME) or do not move
    /// forward by [`MIN_INTERVAL`].
    pub skipped: u64,
    /// Intervals longer than the gap limit.
    pub gaps: u64,
    /// The longest such interval \[s\] (0 without gaps).
    pub longest_gap: f64,
}

impl InputReport {
    /// Counts an interval `dt` [s] longer than the gap limit.
    #[inline(always)]
    pub(crate) fn gap(&mut self, dt: f64) {
        self.gaps_up_to(1, dt);
    }

    /// Counts `count` intervals longer than the gap limit, none longer than `longest` [s].
    #[inline(always)]
    pub(crate) fn gaps_up_to(&mut self, count: u64, longest: f64) {
        if count > 0 {
            self.gaps = self.gaps.saturating_add(count);
            self.longest_gap = self.longest_gap.max(longest);
        }
    }

    /// Checks a report read back (`serde` feature): the longest gap an interval, within 0 and
    /// 2^41 s, and 0 without gaps.
    #[cfg(feature = "serde")]
    pub(crate) fn check_restored(&self) -> Result<(), crate::Error> {
        let most = if self.gaps == 0 {
            0.0
        } else {
            2.0 * crate::MAX_TIME
        };
        let valid = "within 0 and 2^41 s (an interval), and 0 without gaps";
        crate::error::check_range("longest_gap", self.longest_gap, 0.0, most, valid)
    }
}
