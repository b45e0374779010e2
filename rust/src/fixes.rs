//! Heading fixes: absolute headings `(t, heading, sigma)` (GNSS course over ground, a surveyed
//! landmark, map matching) fused with the gyro by a 3-state Kalman filter that estimates the
//! heading and the gyro's bias and scale online.
//!
//! The filter is the recursive form of Hong & Park's least-squares self-calibration (Hong eq 4-7).
//! Their eq 1 models the gyro as `r_m = (1 + s) r + b`; eq 3 inverts it to
//! `r = s_bar r_m + b_bar` with `s_bar = 1 / (1 + s)` and `b_bar = -b / (1 + s)`, and eq 4
//! propagates the heading as `psi(k+1) = psi(k) + h (s_bar r_m(k) + b_bar)`. The state is
//! therefore `x = [psi, s_bar, b_bar]`: in eq 3's coefficients the heading is *linear* in the
//! state, so the filter is an exact linear Kalman filter (no linearisation), and with no process
//! noise on `s_bar` and `b_bar` it is exactly the recursive least squares of eq 6-7. The outputs
//! report eq 1's `b` (what the gyro reads at rest, the project's bias convention) and `s`.
//!
//! Between two gyro samples the rate is taken as linear in time (the trapezoid rule of the
//! [`Integrator`](crate::Integrator)); a fix between two samples is applied at its own time by
//! propagating to it with the rate interpolated there, so that how the samples and fixes are
//! split into blocks changes nothing: a chunked run is bit-identical to one call. From one fix
//! to the next, the state and its covariance move in closed form (rust/src/fixes_segment.rs):
//! the same filter as a covariance step per sample, in a few operations per sample.
//!
//! Process noise comes from the gyro's Allan parameters: the angle random walk `N` drives the
//! heading, the rate random walk `K` the bias, and an optional scale random walk the scale.
//! Innovations are wrapped to (-pi, pi]; a fix whose normalised innovation squared exceeds the
//! gate (chi-square, one degree of freedom) is rejected and counted. A filter surer of itself
//! than its fixes allow rejects every fix after one it refused (the gate's lock-out): after
//! [`readmit_after`](FusionConfig::readmit_after) seconds of nothing but rejections, the next
//! fix within [`READMIT_REACH`] gate radii (or beyond, where the run's innovations drift away
//! steadily: rust/src/fixes_drift.rs) is applied with the covariance raised. Fixes before
//! the first gyro sample are counted and skipped (nothing to attach them to); a NaN, a
//! `sigma <= 0`, or a fix earlier than the one before it or than a sample already processed is
//! an error naming the fix.
//!
//! [`smooth`](crate::fixes_smooth::smooth) runs the Rauch-Tung-Striebel backward pass over the
//! knots [`Fusion::process_block_recording`] stores, and [`Fusion::process_block_smoothed`]
//! writes the smoothed estimates, for whole logs.

use core::f64::consts::PI;

pub use crate::fixes_config::{
    FusionConfig, MIN_FIX_SIGMA, READMIT_GAP, READMIT_MIN_REJECTED, READMIT_REACH,
};
pub use crate::fixes_error::{FixProblem, FusionError};
pub use crate::fixes_output::{Estimate, FusionOutputs};
use crate::fixes_segment::{Anchor, Segment};
use crate::fixes_smooth::Knot;
use crate::Error;

// Where the block loop writes: a child module, which sees the filter's fields.
#[path = "fixes_write.rs"]
mod write;
use write::{Columns, Smoothing, Write};

// A fix's update, the gate's lock-out and a restart of the clock: a child module, which sees
// the filter's fields.
#[path = "fixes_update.rs"]
mod update;

// The checks of a block's samples and fixes: a child module, which sees the filter's fields.
#[path = "fixes_checks.rs"]
mod checks;
pub use checks::reachable;

// The checks of a filter read back: a child module, which sees the filter's fields.
#[cfg(feature = "serde")]
#[path = "fixes_readback.rs"]
mod readback;

/// One absolute heading.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Fix {
    /// Time \[s\], on the gyro's clock.
    pub t: f64,
    /// Heading \[rad\], counter-clockwise from east, within +-2^20 (any turn: only its value
    /// modulo 2 pi counts).
    pub heading: f64,
    /// Its standard deviation \[rad\], in \[[`MIN_FIX_SIGMA`], 2^20\].
    pub sigma: f64,
}

/// How the fixes given so far were used. Each count saturates at `u64::MAX`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FixCounts {
    /// Applied as a measurement.
    pub applied: u64,
    /// Rejected by the outlier gate.
    pub rejected: u64,
    /// Skipped because they came before the first gyro sample.
    pub before_start: u64,
    /// Of those applied, the ones applied after a run of rejections that lasted `readmit_after`
    /// ([`FusionConfig::readmit_after`]): each one a filter surer than the fixes allowed.
    #[cfg_attr(feature = "serde", serde(default))]
    pub readmitted: u64,
}

/// The streaming filter: a validated config and its state (`Copy`, serialisable). Between fixes
/// the state moves in closed form from the last fix applied (rust/src/fixes_segment.rs).
///
/// Read back (`serde` feature), its configuration is checked as [`Fusion::new`] checks it, and
/// its state: times within +-2^40 s, values finite and in range, a covariance that is one.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(remote = "Self")
)]
pub struct Fusion {
    config: FusionConfig,
    segment: Segment,
    anchor: Option<Anchor>,
    last_fix: Option<f64>,
    counts: FixCounts,
    /// The fixes the gate has rejected since the last one applied: the first one's time and how
    /// many (None: the last fix was applied, or none was rejected yet).
    #[cfg_attr(feature = "serde", serde(default))]
    rejected_run: Option<(f64, u64)>,
    /// The line through that run's innovations (None: no run, or a run read back from a filter
    /// stored before it was kept, which is then judged by its reach alone).
    #[cfg_attr(feature = "serde", serde(default))]
    drift: Option<crate::fixes_drift::Drift>,
    /// The shortest time between two consecutive fixes processed, > 0 (infinity: none yet): the
    /// fixes' pace, against which a gap in them is an outage ([`READMIT_GAP`]).
    #[cfg_attr(
        feature = "serde",
        serde(with = "crate::serde_float", default = "crate::fixes_config::never")
    )]
    fix_interval: f64,
    /// The time of the outages within the run of rejections ([`READMIT_GAP`]; 0 without a run),
    /// left out of its length.
    #[cfg_attr(feature = "serde", serde(default))]
    run_outages: f64,
    /// True from [`Fusion::restart_clock`] to the next sample taken, which starts the new time
    /// base.
    #[cfg_attr(feature = "serde", serde(default))]
    restarted: bool,
    /// How many restarts of the clock the filter has taken (a sample after each): each left a
    /// knot for the smoother, which the smoothed pass counts past with the fixes applied.
    #[cfg_attr(feature = "serde", serde(default))]
    restarts: u64,
}

/// Wraps an angle to (-pi, pi]: the IEEE remainder of `a` by `2 pi`, exact (`a - 2 pi ceil(..)`
/// rounded to just above pi near an odd multiple of pi, and gave 0 beyond 2^53), -pi taken as pi.
#[inline]
pub fn wrap_angle(a: f64) -> f64 {
    let r = libm::remainder(a, 2.0 * PI);
    if r == -PI {
        PI
    } else {
        r
    }
}

impl Fusion {
    /// A filter before its first sample.
    pub fn new(config: FusionConfig) -> Result<Self, Error> {
        config.validate()?;
        let mut p = [[0.0; 3]; 3];
        p[0][0] = config.initial_heading_sigma * config.initial_heading_sigma;
        // d s_bar / d s = -1/(1+s)^2 and d b_bar / d b = -1/(1+s): both -1 at s = 0.
        p[1][1] = config.initial_scale_sigma * config.initial_scale_sigma;
        p[2][2] = config.initial_bias_sigma * config.initial_bias_sigma;
        let x = [config.initial_heading, 1.0, -config.initial_bias];
        Ok(Fusion {
            config,
            segment: Segment::new(0.0, x, p),
            anchor: None,
            last_fix: None,
            counts: FixCounts::default(),
            rejected_run: None,
            drift: None,
            fix_interval: f64::INFINITY,
            run_outages: 0.0,
            restarted: false,
            restarts: 0,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &FusionConfig {
        &self.config
    }

    /// How the fixes were used so far.
    pub fn counts(&self) -> FixCounts {
        self.counts
    }

    /// The current estimate.
    pub fn estimate(&self) -> Estimate {
        let (s, now) = (&self.segment, self.now());
        Estimate::of(&s.state(now), &s.covariance(now, &self.config))
    }

    /// The time the state stands at: the last sample or fix processed, or before the first
    /// sample the knot's (0, where nothing has moved).
    #[inline(always)]
    fn now(&self) -> f64 {
        self.anchor.map_or(0.0, |a| a.t)
    }

    /// The time the state stands at (the last sample or fix processed), or None.
    pub fn last_time(&self) -> Option<f64> {
        self.anchor.map(|a| a.t)
    }

    /// Returns the filter to its state before the first sample.
    pub fn reset(&mut self) {
        if let Ok(fresh) = Fusion::new(self.config) {
            *self = fresh;
        }
    }

    /// Processes a block of gyro samples with the fixes that fall in it (sorted by time), writing
    /// the estimate after each sample. Returns how many fixes it used (applied, rejected or before
    /// the first sample): the rest lie after the block's last sample and belong to the next call.
    /// Nothing is processed from a block with a bad sample or a bad fix among those it checks
    /// ([`reachable`]: the ones it reaches, and the first past them).
    pub fn process_block(
        &mut self,
        t: &[f64],
        rate: &[f64],
        fixes: &[Fix],
        out: FusionOutputs<'_>,
    ) -> Result<usize, FusionError> {
        self.process_block_recording(t, rate, fixes, out, |_| {})
    }

    /// [`process_block`](Self::process_block), handing `record` a [`Knot`] for the smoother at
    /// the first sample and at every fix applied.
    pub fn process_block_recording(
        &mut self,
        t: &[f64],
        rate: &[f64],
        fixes: &[Fix],
        mut out: FusionOutputs<'_>,
        mut record: impl FnMut(Knot),
    ) -> Result<usize, FusionError> {
        self.check_inputs(t, rate, fixes, &out)?;
        Ok(self.run(t, rate, fixes, &mut out, &mut record))
    }

    /// The second forward pass of the smoother: [`process_block`](Self::process_block) of a
    /// fresh filter (the same configuration as the pass that recorded `knots`) over the same
    /// samples and fixes, writing each sample's smoothed estimate, given the knots after
    /// [`smooth`](crate::smooth). Knots that do not belong to these samples give no error, only
    /// estimates that are not smoothed (where a knot is missing) or wrong.
    ///
    /// ```
    /// use gyrocore::{smooth, Fix, Fusion, FusionConfig, FusionOutputs, Knot};
    /// let t: Vec<f64> = (0..3000).map(|i| i as f64 * 0.01).collect();
    /// let rate = vec![0.1 + 0.002; t.len()]; // a steady turn, read with a bias of 0.002 rad/s
    /// // a fix a second, none from 10 s to 25 s
    /// let fixes: Vec<Fix> = (0..30)
    ///     .filter(|&s| !(10..25).contains(&s))
    ///     .map(|s| Fix { t: s as f64, heading: 0.1 * s as f64, sigma: 0.01 })
    ///     .collect();
    /// let config = FusionConfig::default();
    /// let n = t.len();
    /// let mut cols = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    /// let [heading, sigma, bias, scale] = &mut cols;
    /// // forward, keeping a knot at the first sample and at every fix applied
    /// let mut knots: Vec<Knot> = Vec::new();
    /// let mut forward = Fusion::new(config).unwrap();
    /// let out = FusionOutputs::heading(heading);
    /// forward.process_block_recording(&t, &rate, &fixes, out, |k| knots.push(k)).unwrap();
    /// assert_eq!(smooth(&mut knots), 0);
    /// // again from the start, writing the smoothed estimates
    /// let out = FusionOutputs::all(heading, sigma, bias, scale);
    /// let mut again = Fusion::new(config).unwrap();
    /// again.process_block_smoothed(&t, &rate, &fixes, &knots, out).unwrap();
    /// let k = 1750; // 17.5 s, inside the gap, bracketed by fixes
    /// assert!((cols[0][k] - 0.1 * 17.5).abs() < 0.01);
    /// assert!(cols[1][k] < 0.05); // sigma [rad]
    /// ```
    pub fn process_block_smoothed(
        &mut self,
        t: &[f64],
        rate: &[f64],
        fixes: &[Fix],
        knots: &[Knot],
        out: FusionOutputs<'_>,
    ) -> Result<usize, FusionError> {
        self.check_inputs(t, rate, fixes, &out)?;
        let n = t.len();
        let mut out = Smoothing { out, knots };
        Ok(self.run_into((&t[..n], &rate[..n], fixes), &mut out, &mut |_| {}))
    }

    /// The samples of a block (`t` and `rate` as long as `out`) with their fixes, writing the
    /// estimate after each; returns how many fixes it used. The caller has checked the times and
    /// the fixes ([`check_block`], [`Fusion::check_fixes`]); a sample whose rate is not finite
    /// (one the pipeline skipped) is left out, and its row repeats the estimate before it.
    #[inline(always)]
    pub(crate) fn run(
        &mut self,
        t: &[f64],
        rate: &[f64],
        fixes: &[Fix],
        out: &mut FusionOutputs<'_>,
        record: &mut impl FnMut(Knot),
    ) -> usize {
        // The loop compiled with and without the bias and scale columns, so that a caller who
        // wants neither does not test for them on every sample.
        let n = t.len();
        let input = (&t[..n], &rate[..n], fixes);
        let out = out.first(n);
        if out.wants_calibration() {
            self.run_into(input, &mut Columns::<true>(out), record)
        } else {
            self.run_into(input, &mut Columns::<false>(out), record)
        }
    }

    /// [`Fusion::run`] over `(t, rate, fixes)` (`rate` as long as `t`, and `out` too), each
    /// sample's estimate through `out`.
    #[inline(always)]
    fn run_into(
        &mut self,
        (t, rate, fixes): (&[f64], &[f64], &[Fix]),
        out: &mut impl Write,
        record: &mut impl FnMut(Knot),
    ) -> usize {
        // The filter runs on a copy, which the compiler can keep in registers.
        let mut fusion = *self;
        let n = t.len();
        let rate = &rate[..n];
        let (mut k, mut used) = (0, 0);
        while k < n {
            // Up to the next fix, a sample only moves the segment on: a loop with nothing else
            // in it, which takes the segment's calibration once.
            let next_fix = fixes.get(used).map_or(f64::INFINITY, |f| f.t);
            let calibration = fusion.segment.calibration();
            // After a restart of the clock the next sample takes the slow path.
            if let Some(mut a) = fusion.anchor.filter(|_| !fusion.restarted) {
                while k < n && t[k] < next_fix {
                    if rate[k].is_finite() {
                        fusion.take_sample(&mut a, t[k], rate[k]);
                    }
                    out.write(k, &fusion, a.t, calibration);
                    k += 1;
                }
                fusion.anchor = Some(a);
            }
            // The first sample, or one at or past a fix: the fixes up to it, then the sample.
            if k < n {
                if rate[k].is_finite() {
                    used += fusion.sample(t[k], rate[k], &fixes[used..], record);
                }
                let calibration = fusion.segment.calibration();
                out.write(k, &fusion, fusion.now(), calibration);
                k += 1;
            }
        }
        *self = fusion;
        used
    }

    /// One gyro sample and the fixes up to its time; returns how many fixes it used. The caller
    /// has checked the sample and the fixes ([`check_block`], [`Fusion::check_fixes`]). A
    /// `record` that keeps nothing costs nothing: the knots are built only for it.
    #[inline(always)]
    fn sample(&mut self, t: f64, rate: f64, fixes: &[Fix], record: &mut impl FnMut(Knot)) -> usize {
        let mut used = 0;
        if self.restarted {
            // The first sample on the new clock: the segment so far ends at a knot, from which
            // the new one starts at `t` with the estimate and covariance of the jump. The knot
            // takes no measurement, and its transition ends at `now`, on the old clock.
            self.restarted = false;
            self.restarts = self.restarts.saturating_add(1);
            let now = self.now();
            let (x, p) = (
                self.segment.state(now),
                self.segment.covariance(now, &self.config),
            );
            record(Knot::new(t, self.segment.a(), (x, p), x, p).jumped_from(now));
            self.segment = Segment::new(t, x, p);
            self.anchor = Some(Anchor::of_sample(t, rate));
            used = fixes.iter().take_while(|f| f.t < t).count();
            self.counts.before_start = self.counts.before_start.saturating_add(used as u64);
        }
        let mut a = self.anchor.unwrap_or(Anchor::of_sample(t, rate));
        if self.anchor.is_none() {
            used = fixes.iter().take_while(|f| f.t < t).count();
            self.counts.before_start = self.counts.before_start.saturating_add(used as u64);
            self.segment = self.segment.starting_at(t);
            let (x, p) = (
                self.segment.state(t),
                self.segment.covariance(t, &self.config),
            );
            record(Knot::new(t, 0.0, (x, p), x, p));
        }
        for f in fixes[used..].iter().take_while(|f| f.t <= t) {
            // The rate is linear between samples: its value at the fix's time.
            let at_fix = if f.t == t {
                rate
            } else {
                let frac = (f.t - a.sample_t) / (t - a.sample_t);
                a.sample_rate + (rate - a.sample_rate) * frac
            };
            self.advance(&mut a, f.t, at_fix);
            let (x, mut p) = (
                self.segment.state(f.t),
                self.segment.covariance(f.t, &self.config),
            );
            // `p` is the prediction the update used: raised where the fix was re-admitted
            if let Some((x_fixed, p_fixed)) = self.correct(f, x, &mut p) {
                record(Knot::new(f.t, self.segment.a(), (x, p), x_fixed, p_fixed));
                self.segment = Segment::new(f.t, x_fixed, p_fixed);
            }
            if let Some(gap) = self.last_fix.map(|last| f.t - last).filter(|&g| g > 0.0) {
                self.fix_interval = self.fix_interval.min(gap);
            }
            self.last_fix = Some(f.t);
            used += 1;
        }
        self.take_sample(&mut a, t, rate);
        self.anchor = Some(a);
        used
    }

    /// Moves from the anchor `a` to the gyro sample `(t, rate)`, which becomes its sample.
    #[inline(always)]
    fn take_sample(&mut self, a: &mut Anchor, t: f64, rate: f64) {
        self.advance(a, t, rate);
        (a.sample_t, a.sample_rate) = (t, rate);
    }

    /// Moves the state from the anchor `a` to `t` where the rate reads `rate` (Hong eq 4 with
    /// the mean rate of the interval; the covariance follows in closed form, see [`Segment`]),
    /// and the anchor there.
    #[inline(always)]
    fn advance(&mut self, a: &mut Anchor, t: f64, rate: f64) {
        let dt = t - a.t;
        let m = 0.5 * (a.rate + rate);
        (a.t, a.rate) = (t, rate);
        if dt > 0.0 {
            self.segment.extend(dt, m);
        }
    }
}
