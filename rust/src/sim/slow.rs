//! The slow stochastic bias `d` of the simulated gyro (Hong eq 10-11): bias instability as a sum of
//! first-order Gauss-Markov processes plus a rate random walk, on its own time grid.

use super::random::Gaussian;
use super::{GyroModelConfig, MAX_FLICKER_TERMS, STREAM_DRIFT};

/// The slow bias `d` on its grid: the value at the grid points on either side of the current time.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct SlowBias {
    rng: Gaussian,
    /// Gauss-Markov states at grid point `index + 1` [rad/s].
    flicker: [f64; MAX_FLICKER_TERMS],
    /// Rate random walk state at grid point `index + 1` [rad/s].
    walk: f64,
    /// Grid point at or before the current time.
    index: u64,
    /// `d` at grid points `index` and `index + 1` [rad/s].
    before: f64,
    after: f64,
}

/// Per-term constants of the slow bias, derived from the configuration once.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct SlowTerms {
    count: usize,
    /// `exp(-drift_step / T_k)`.
    decay: [f64; MAX_FLICKER_TERMS],
    /// Standard deviation of each term's innovation per grid step: `q_k sqrt(1 - decay^2)`.
    innovation: [f64; MAX_FLICKER_TERMS],
    /// Stationary standard deviation `q_k` (the state at the first grid point).
    stationary: [f64; MAX_FLICKER_TERMS],
    /// Standard deviation of the random walk's step: `K sqrt(drift_step)`.
    walk_step: f64,
}

impl SlowTerms {
    pub(super) fn new(config: &GyroModelConfig) -> Self {
        let mut terms = SlowTerms {
            count: config.flicker_terms(),
            decay: [0.0; MAX_FLICKER_TERMS],
            innovation: [0.0; MAX_FLICKER_TERMS],
            stationary: [0.0; MAX_FLICKER_TERMS],
            walk_step: config.rrw * libm::sqrt(config.drift_step),
        };
        for k in 0..terms.count {
            let (correlation, sd) = config.flicker_term(k);
            // Exact discretisation of dx/dt = -x/T + noise over one grid step.
            let decay = libm::exp(-config.drift_step / correlation);
            terms.decay[k] = decay;
            terms.innovation[k] = sd * libm::sqrt(1.0 - decay * decay);
            terms.stationary[k] = sd;
        }
        terms
    }
}

impl SlowBias {
    /// Grid points 0 and 1, the Gauss-Markov terms drawn from their stationary distribution and the
    /// random walk starting at 0 (its start is part of the bias).
    pub(super) fn start(seed: u64, terms: &SlowTerms) -> Self {
        let mut slow = SlowBias {
            rng: Gaussian::new(seed, STREAM_DRIFT),
            flicker: [0.0; MAX_FLICKER_TERMS],
            walk: 0.0,
            index: 0,
            before: 0.0,
            after: 0.0,
        };
        for k in 0..terms.count {
            slow.flicker[k] = terms.stationary[k] * slow.rng.sample();
        }
        // `advance` moves `after` to `before`: start with grid point 0 there.
        slow.after = slow.sum(terms);
        slow.advance(terms);
        slow.index = 0;
        slow
    }

    fn sum(&self, terms: &SlowTerms) -> f64 {
        self.flicker[..terms.count].iter().sum::<f64>() + self.walk
    }

    /// Moves the state one grid step on.
    fn advance(&mut self, terms: &SlowTerms) {
        for k in 0..terms.count {
            self.flicker[k] =
                terms.decay[k] * self.flicker[k] + terms.innovation[k] * self.rng.sample();
        }
        if terms.walk_step > 0.0 {
            self.walk += terms.walk_step * self.rng.sample();
        }
        self.before = self.after;
        self.after = self.sum(terms);
        self.index = self.index.saturating_add(1);
    }

    /// Longest stretch of grid steps taken one by one.
    const JUMP: u64 = 1 << 22;

    /// Moves the state `steps` grid steps on with one draw per term (exact in distribution: decay
    /// `a^steps`, innovation `q sqrt(1 - a^(2 steps))`, walk step `K sqrt(steps h)`). Used only
    /// across gaps of more than [`SlowBias::JUMP`] steps, so a far-off timestamp cannot stall the
    /// model; the realisation after such a gap depends on the gap.
    fn jump(&mut self, terms: &SlowTerms, steps: u64) {
        let m = steps as f64;
        for k in 0..terms.count {
            let decay = libm::pow(terms.decay[k], m);
            let sd = terms.stationary[k] * libm::sqrt(1.0 - decay * decay);
            self.flicker[k] = decay * self.flicker[k] + sd * self.rng.sample();
        }
        if terms.walk_step > 0.0 {
            self.walk += terms.walk_step * libm::sqrt(m) * self.rng.sample();
        }
        self.after = self.sum(terms);
        self.index = self.index.saturating_add(steps);
    }

    /// `d` at `elapsed` seconds after the first sample, interpolated between grid points.
    ///
    /// Time only moves forward here: an earlier time than the last one gets the value of the
    /// current grid interval's start.
    pub(super) fn at(&mut self, terms: &SlowTerms, step: f64, elapsed: f64) -> f64 {
        if terms.count == 0 && terms.walk_step == 0.0 {
            return 0.0;
        }
        let target = libm::floor(elapsed / step);
        // Saturating: a state read back may hold any index (u64::MAX overflowed, a panic in a
        // debug build); one reached by stepping stays below 1e18.
        if target > self.index.saturating_add(Self::JUMP) as f64 && target < 1e18 {
            // A gap of days: land one step short of the target, then step as usual.
            self.jump(terms, target as u64 - 1 - self.index);
        }
        while elapsed >= self.index.saturating_add(1) as f64 * step && elapsed < 1e18 * step {
            self.advance(terms);
        }
        let fraction = (elapsed / step - self.index as f64).clamp(0.0, 1.0);
        self.before + fraction * (self.after - self.before)
    }
}
