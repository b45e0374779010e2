//! A fix's Kalman update, its gate, the re-admission that ends the gate's lock-out
//! ([`FusionConfig::readmit_after`](crate::FusionConfig::readmit_after)), and a restart of the
//! clock, which forgets the fixes' times.

use super::{wrap_angle, Fix, Fusion, READMIT_GAP, READMIT_MIN_REJECTED, READMIT_REACH};
use crate::fixes_drift::Drift;
use crate::fixes_smooth::Mat3;

impl Fusion {
    /// The Kalman update of state `x` with covariance `p` by a fix (H = [1, 0, 0]): the updated
    /// pair, or None if the gate rejects the fix. Where the fix is re-admitted (the module's
    /// text), `p` is left raised as the update used it.
    #[inline(always)]
    pub(super) fn correct(
        &mut self,
        fix: &Fix,
        mut x: [f64; 3],
        p: &mut Mat3,
    ) -> Option<([f64; 3], Mat3)> {
        // A heading variance rounded below 0 made `s` <= 0 (no gate refused the fix; 0 divided)
        if p[0][0] < 0.0 {
            *p = crate::fixes_covariance::semi_definite(*p);
        }
        let r = fix.sigma * fix.sigma;
        let nu = wrap_angle(fix.heading - x[0]);
        let bound = self.config.gate * (p[0][0] + r);
        if nu * nu > bound {
            let run = self.rejected_run;
            let outages = self.run_outages + self.outage_before(fix.t);
            let drift = match (run, self.drift) {
                (None, _) => Some(Drift::first(nu)),
                (Some((since, _)), Some(d)) => Some(d.with(fix.t - since, nu)),
                (Some(_), None) => None,
            };
            // Beyond reach, a run whose innovations drift: its slope's square, the bias's error
            let drifting = if nu * nu <= READMIT_REACH * READMIT_REACH * bound {
                Some(0.0)
            } else {
                self.drifting(run, drift, (fix.t, r), (p[0][0], bound))
            };
            if !self.readmits(run, fix.t - outages, drifting.is_some()) {
                self.counts.rejected = self.counts.rejected.saturating_add(1);
                let (since, n) = run.unwrap_or((fix.t, 0));
                self.rejected_run = Some((since, n.saturating_add(1)));
                // a run's first fix follows no outage of its own
                self.run_outages = if run.is_some() { outages } else { 0.0 };
                self.drift = drift;
                return None;
            }
            self.reopen(p, nu, drifting.unwrap_or(0.0));
            self.counts.readmitted = self.counts.readmitted.saturating_add(1);
        }
        self.rejected_run = None;
        self.run_outages = 0.0;
        self.drift = None;
        self.counts.applied = self.counts.applied.saturating_add(1);
        let s = p[0][0] + r;
        let k = [p[0][0] / s, p[1][0] / s, p[2][0] / s];
        let row = p[0];
        let mut p = *p;
        for ((x, p_i), k) in x.iter_mut().zip(p.iter_mut()).zip(k) {
            *x += k * nu;
            for (pij, p0j) in p_i.iter_mut().zip(row) {
                *pij -= k * p0j;
            }
        }
        // The heading's variance of eq 6's `P - K H P` as `P_00 r / s`: the same value without
        // the cancellation of `P_00 - P_00^2 / s` where the fix is far surer than the filter (a
        // heading of sigma 2^20 rad fixed to 1e-3 rad read back a sigma of 0, and of 1e5 rad one
        // of 1.38e-3). Its covariances stay as they were: the smoother's gains need them to
        // match the scale's and bias's block, computed the same way.
        p[0][0] = row[0] * (r / s);
        Some((x, crate::fixes_covariance::semi_definite(p)))
    }

    /// The time of an outage before a fix at `t` left out of a run of rejections' length: what
    /// the gap since the last fix lasted beyond [`READMIT_GAP`] times the fixes' shortest
    /// interval and half of `readmit_after` (the longest gap a run counts whole; 0 within it). An
    /// outage holds no rejection: counted whole, two stray fixes before a tunnel and one after it
    /// re-admitted the third and reset the heading to it. Counted up to that longest gap, rather
    /// than ending the run, so that fixes in bursts (10 Hz for 3 s in every 10) or at a pace that
    /// falls (10 Hz, then 0.1 Hz) still end a lock-out: ended at each gap, such a run never
    /// lasted `readmit_after`. (A pace that follows the last intervals instead, grown by one
    /// outage, let a second one soon after count whole: stray fixes between two tunnels.)
    #[inline(always)]
    fn outage_before(&self, t: f64) -> f64 {
        let c = &self.config;
        let span = (READMIT_MIN_REJECTED - 1) as f64;
        let longest = (READMIT_GAP * self.fix_interval).max(c.readmit_after / span);
        let gap = self.last_fix.map_or(0.0, |last| t - last);
        (gap - longest).max(0.0)
    }

    /// Whether a fix at `t` (less the run's outages) that fails the gate, continuing the
    /// rejections `run`, ends the gate's lock-out: the fixes have failed it for `readmit_after`
    /// seconds, at least [`READMIT_MIN_REJECTED`] in a row with this one, and this one is
    /// `admissible` (within [`READMIT_REACH`], or beyond it at the end of a run that drifts).
    #[inline(always)]
    fn readmits(&self, run: Option<(f64, u64)>, t: f64, admissible: bool) -> bool {
        admissible
            && run.is_some_and(|(since, n)| {
                n.saturating_add(1) >= READMIT_MIN_REJECTED
                    && t - since >= self.config.readmit_after
            })
    }

    /// The slope's square \[(rad/s)^2\] of the innovations of the rejections `run` with this fix
    /// at `t` (`drift`; a fix's variance `r`) where the heading has run away from the fixes over
    /// the run by more than the gate allows the filter's heading variance `p_heading`, the line
    /// through them starting within [`READMIT_REACH`] radii of this fix's gate (`bound`): the
    /// fixes agree with each other and with the gyro's turns, the filter does not, and it is
    /// surer than that. None for a run of a steady offset (a lasting wrong course: the filter's
    /// heading follows the gyro as the fixes do) or of scattered fixes.
    fn drifting(
        &self,
        run: Option<(f64, u64)>,
        drift: Option<Drift>,
        (t, r): (f64, f64),
        (p_heading, bound): (f64, f64),
    ) -> Option<f64> {
        let (since, n) = run?;
        let (start, slope, residual, spread) = drift?.line(n.saturating_add(1))?;
        // The line starts within reach: the fixes left the filter's heading by drifting away
        // from it, not at a step (a lasting wrong course beyond reach is off from its first fix
        // on, and a filter too sure of itself, on the KITTI drives' rate, drifts a few degrees
        // from it too).
        // (false for a NaN line: no drift)
        let starts_within = start * start <= READMIT_REACH * READMIT_REACH * bound;
        if !starts_within {
            return None;
        }
        // three points leave one degree of freedom, which may fit by chance: at least `r`
        let variance = residual.max(r) / spread;
        // Within the range of `initial_bias_sigma`: fixes nanoseconds apart gave slopes whose
        // square, as the bias's variance, was infinite and the covariance NaN.
        let most = crate::fixes_config::MAX_INITIAL_BIAS;
        let squared = (slope * slope).min(most * most);
        let span = t - since;
        (squared * span * span > self.config.gate * (variance * span * span + p_heading))
            .then_some(squared)
    }

    /// The covariance of a filter the fixes have shown to be too sure of itself, before the fix
    /// that re-admits them: the heading's variance raised by the innovation's square over the
    /// gate (the fix then passes it, and the heading takes at least c/(1+c) of the innovation
    /// where its square is c times the gate's bound: over half, 16/17 at [`READMIT_REACH`]), the
    /// scale's and bias's raised back to their initial ones (their error is what turned the
    /// heading away). A diagonal added: the covariance stays one, and the smoother sees it as
    /// noise entering at the fix. Where the run's innovations drifted (`drift_squared`, the
    /// square of their slope), the bias's variance is raised to that at least: an initial one
    /// far below the gyro's error would lock the filter out again.
    #[cold]
    fn reopen(&self, p: &mut Mat3, nu: f64, drift_squared: f64) {
        let c = &self.config;
        // At most the variance of an unknown heading (sigma 2^20 rad, `initial_heading_sigma`'s
        // limit): a drifting run beyond reach with a gate near 0 raised it to infinity.
        p[0][0] += (nu * nu / c.gate).min(crate::MAX_READING * crate::MAX_READING);
        let scale = c.initial_scale_sigma * c.initial_scale_sigma;
        let bias = c.initial_bias_sigma * c.initial_bias_sigma;
        p[1][1] = p[1][1].max(scale);
        p[2][2] = p[2][2].max(bias).max(drift_squared);
    }

    /// Takes the next sample on a new time base, whatever its time (a clock that jumped back; see
    /// [`Pipeline::restart_clock`](crate::Pipeline::restart_clock)). The estimate (heading,
    /// bias, scale) and its covariance are kept and move nothing across the jump: no time passes
    /// there for the filter. Fixes belong to the clock they were stamped on: the filter forgets
    /// the last fix's time and any run of rejections (the gate's lock-out starts afresh), so the
    /// next fixes are on the new clock; those still to be given on the old one must be dropped
    /// (they would be applied at the wrong time). Fixes before the next sample are counted as
    /// [`FixCounts::before_start`](crate::FixCounts::before_start). Before the first sample it
    /// does nothing.
    pub fn restart_clock(&mut self) {
        if self.anchor.is_none() {
            return;
        }
        self.restarted = true;
        (self.last_fix, self.rejected_run, self.drift) = (None, None, None);
        self.run_outages = 0.0;
    }

    /// True from [`Fusion::restart_clock`] to the next sample taken.
    #[cfg(feature = "serde")] // read by a read-back state's check alone
    pub(crate) fn restart_pending(&self) -> bool {
        self.restarted
    }

    /// The time the next sample must follow (None: any time, as before the first sample or
    /// after [`Fusion::restart_clock`]).
    pub(super) fn previous_sample(&self) -> Option<f64> {
        self.anchor.filter(|_| !self.restarted).map(|a| a.sample_t)
    }
}
