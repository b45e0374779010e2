//! The checks of a [`RestTracker`] read back (`serde` feature): its bias, variance and noise, its
//! times in order, and the sums of its block, run and pending block as readings leave them.

use super::{Filling, RestTracker, Sums};

impl RestTracker {
    /// Checks a tracker read back (`serde` feature), naming the field: the filtered bias a mean
    /// of readings (a stored 1e308 gave infinite headings); its variance and the noise finite
    /// and >= 0 (a negative variance gave a NaN standard error, a NaN bound on HDR, and a state
    /// that no longer read back); the times >= 0 and in order (the last update and every sum's
    /// span no later than now); and the sums of the block, the run and the block before it as
    /// readings within 2^20 leave them.
    pub(super) fn check(&self) -> Result<(), crate::Error> {
        use crate::error::{check_range, check_reading};
        use crate::{MAX_READING, MAX_TIME};
        check_reading("rest tracker bias", self.bias)?;
        let times = "within 0 and 2^42 s (the time since the first sample)";
        check_range("rest tracker now", self.now, 0.0, 4.0 * MAX_TIME, times)?;
        let valid = "within 0 and the tracker's now (the time of the last update)";
        check_range("rest tracker updated", self.updated, 0.0, self.now, valid)?;
        if let Some(variance) = self.variance {
            let valid = "finite and >= 0";
            check_range("rest tracker variance", variance, 0.0, f64::MAX, valid)?;
        }
        if let Some(noise) = self.noise {
            // successive differences of two readings are within 2^21
            let valid = "finite, >= 0 and at most 2^21 rad/s (what two readings' difference gives)";
            check_range("rest tracker noise", noise, 0.0, 2.0 * MAX_READING, valid)?;
        }
        if let Some((mean, _)) = self.previous {
            let valid = "within +-2^21 rad/s (a mean of readings, with room for rounding)";
            let most = 2.0 * MAX_READING;
            check_range("rest tracker previous block mean", mean, -most, most, valid)?;
        }
        self.block.check(self.now)?;
        if let Some((sums, pending)) = &self.run {
            sums.check(self.now)?;
            if let Some(p) = pending {
                p.check(self.now)?;
            }
        }
        Ok(())
    }
}

impl Filling {
    /// See [`Sums::check`]; the last rate a reading.
    fn check(&self, now: f64) -> Result<(), crate::Error> {
        if let Some(rate) = self.previous_rate {
            crate::error::check_usable("rest tracker block last rate", rate)?;
        }
        self.sums.check(now)
    }
}

impl Sums {
    /// Checks sums read back: `0 <= start <= end <= now`, the time covered within 0 and 2^42 s
    /// and the integral's mean a reading (a rest's mean becomes the filtered bias), the squared
    /// differences within what the largest readings give, and the block means' sums within what
    /// `blocks` means of readings give.
    fn check(&self, now: f64) -> Result<(), crate::Error> {
        use crate::error::{check_mean, check_range};
        use crate::{MAX_READING, MAX_TIME};
        let valid = "within 0 and the tracker's now, start before end";
        check_range("rest tracker sums start", self.start, 0.0, now, valid)?;
        check_range("rest tracker sums end", self.end, self.start, now, valid)?;
        let valid = "within 0 and 2^42 s";
        check_range(
            "rest tracker sums duration",
            self.duration,
            0.0,
            4.0 * MAX_TIME,
            valid,
        )?;
        check_mean("rest tracker sums integral", self.integral, self.duration)?;
        let difference = 2.0 * (2.0 * MAX_READING) * (2.0 * MAX_READING);
        let most = difference * self.differences as f64;
        let valid = ">= 0 and at most (2^21)^2 per difference, the largest two readings make";
        check_range(
            "rest tracker sums squared differences",
            self.squared_differences,
            0.0,
            most,
            valid,
        )?;
        let blocks = self.blocks as f64;
        let valid = "within +-2^21 rad/s per block (block means of readings)";
        let most = 2.0 * MAX_READING * blocks;
        check_range("rest tracker sums means", self.means, -most, most, valid)?;
        let valid = ">= 0 and within (2^21)^2 per block (squares of block means)";
        let most = 4.0 * MAX_READING * MAX_READING * blocks;
        check_range(
            "rest tracker sums squared means",
            self.squared_means,
            0.0,
            most,
            valid,
        )
    }
}
