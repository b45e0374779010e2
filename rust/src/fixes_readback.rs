//! The checks of a [`Fusion`] read back (`serde` feature): its configuration as `new` checks it,
//! its state (`Segment::check`, `Anchor::check`), and its times in order.

use super::Fusion;
use crate::fixes_segment::Anchor;
use crate::Error;

impl Fusion {
    /// The checks of a filter read back (`serde` feature): its configuration as `new` checks
    /// it, and its state (`Segment::check`, `Anchor::check`).
    pub(crate) fn check_restored(&self) -> Result<(), Error> {
        self.config.validate()?;
        self.segment.check()?;
        // A restart of the clock waits for a sample after one, and forgets the fixes' times.
        if self.restarted && (self.anchor.is_none() || self.last_fix.is_some()) {
            return Err(Error::InvalidParameter {
                name: "restarted",
                value: 1.0,
                valid: "false before the first sample, and with a last fix's time",
            });
        }
        let interval = "> 0 s (inf: fewer than two fixes processed)";
        let (least, most) = (f64::MIN_POSITIVE, f64::INFINITY);
        crate::error::check_range("fix interval", self.fix_interval, least, most, interval)?;
        self.drift.as_ref().map_or(Ok(()), |d| d.check())?;
        let last_fix = self.last_fix.map(|t| Anchor::of_sample(t, 0.0));
        self.anchor
            .iter()
            .chain(&last_fix)
            .try_for_each(Anchor::check)?;
        // The times in order: the knot, the last fix and the last sample no later than the time
        // the filter stands at (one behind it integrated the time between as rate at once).
        let Some(anchor) = self.anchor else {
            let rejected = self
                .rejected_run
                .map(|(t, _)| ("first rejected fix time", t));
            return match self.last_fix.map(|t| ("last fix time", t)).or(rejected) {
                Some((name, value)) => Err(Error::InvalidParameter {
                    name,
                    value,
                    valid: "none before the first sample (a fix before it is not applied)",
                }),
                None => Ok(()),
            };
        };
        let valid = "at or before the time the filter stands at";
        let now = anchor.t;
        if let Some(t) = self.last_fix {
            crate::error::check_range("last fix time", t, f64::NEG_INFINITY, now, valid)?;
        }
        let name = "filter sample time";
        crate::error::check_range(name, anchor.sample_t, f64::NEG_INFINITY, now, valid)?;
        if let Some((since, n)) = self.rejected_run {
            // The run's first fix is one the filter processed: none after the last fix, none
            // where no fix was, and none before any time (one at -1e300 s had lasted any
            // readmit_after, and the next fix beyond the gate was re-admitted at once).
            let name = "first rejected fix time";
            let last = self.last_fix.ok_or(Error::InvalidParameter {
                name,
                value: since,
                valid: "none where no fix was processed",
            })?;
            let limit = crate::MAX_TIME;
            let within = "within -2^40 s and the last fix's time";
            crate::error::check_range(name, since, -limit, last, within)?;
            let rejected = "at least 1 and at most the fixes rejected";
            let allowed = self.counts.rejected as f64;
            crate::error::check_range("rejected run", n as f64, 1.0, allowed, rejected)?;
            // within the run's span: more had made it last readmit_after at once, or never
            let span = "within 0 and the run's span (its first fix to the last)";
            crate::error::check_range("run outages", self.run_outages, 0.0, last - since, span)?;
        } else {
            let none = "0 without a run of rejections";
            crate::error::check_range("run outages", self.run_outages, 0.0, 0.0, none)?;
        }
        self.segment.check_before(now)
    }
}
