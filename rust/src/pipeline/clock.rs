//! A restart of the clock: the way on after a clock that jumped back, which keeps every
//! estimate (see [`Pipeline::restart_clock`]).

use super::Pipeline;
use crate::Error;

impl Pipeline {
    /// Takes the next sample on a new time base, whatever its time: for a clock that jumped back
    /// (a time sync, a sensor's counter restarted, a log stitched from two sessions), which a
    /// stream otherwise refuses ([`Error::ClockStepsBack`]) or skips
    /// ([`Pipeline::update`]) until it passes the last time taken. The heading, the bias, the
    /// rest tracker's filtered bias and every stage's estimate are kept; the next sample is taken
    /// as the sample after a gap is under the input policy's
    /// [`gap_action`](crate::InputPolicy::gap_action) (`Reset` restarts HDR, the low-pass and
    /// the de-lag; `Bridge` keeps them), but with no interval: nothing is integrated across the
    /// jump, however long it lasted. The samples after it must increase again. Before the first
    /// sample it does nothing.
    ///
    /// The rest tracker holds no clock (it sums the intervals taken), so the times of the rests
    /// it finds after the jump count on from those before it, the jump adding nothing.
    ///
    /// Refused while the rest window is measured ([`Error::ClockRestartInWindow`]; the window
    /// lies on the old clock), the pipeline unchanged. No allocation; the sample's per-sample
    /// path is the one a gap takes.
    pub fn restart_clock(&mut self) -> Result<(), Error> {
        if self.clock.last().is_none() {
            return Ok(());
        }
        if self.bias.learning() {
            let (start, end) = self.bias.window().unwrap_or((f64::NAN, f64::NAN));
            return Err(Error::ClockRestartInWindow { start, end });
        }
        self.clock_restarted = true;
        self.clock_restarts = self.clock_restarts.saturating_add(1);
        Ok(())
    }

    /// How many times [`Pipeline::restart_clock`] restarted the clock.
    pub fn clock_restarts(&self) -> u64 {
        self.clock_restarts
    }

    /// True from [`Pipeline::restart_clock`] to the next sample taken.
    #[cfg(feature = "serde")] // read by a read-back state's check alone
    pub(crate) fn clock_restart_pending(&self) -> bool {
        self.clock_restarted
    }

    /// The last time taken, unless [`Pipeline::restart_clock`] has cut the next sample loose of
    /// it: the time the next one must follow.
    pub(super) fn previous_time(&self) -> Option<f64> {
        self.clock.last().filter(|_| !self.clock_restarted)
    }
}
