//! A bias that walks at random, measured at rests: the one-state Kalman filter that the rest
//! tracker ([`crate::rest_tracker`]) runs as it streams, and the same filter run over a whole
//! log's rests at once ([`filter_rests`]), the forward and backward passes of whole mode's
//! smoother (Python `gyrocore._smoother`: the Rauch-Tung-Striebel smoother over the rests, and the
//! leave-one-out test that refuses rests the others contradict).
//!
//! Not in the papers, which measure the bias once (HDR eq 2). The model: the bias is a random walk,
//! `Var[b(t + dt) - b(t)] = q |dt|`; a rest is a measurement of it with variance `r`. Between two
//! rests the variance grows (`P += q |dt|`); a rest updates it with the gain `g = P / (P + r)`:
//! `b += g (z - b)`, `P = P r / (P + r)`.

use crate::error::check_range;
use crate::stage::check_outputs;
use crate::{check_block, Error, MAX_READING};

/// The largest variance of a rest's reading, of the floor and of the walk's intensity `q` that
/// [`filter_rests`] takes: the square of a reading's limit ([`MAX_READING`]), 2^40.
const MAX_VARIANCE: f64 = MAX_READING * MAX_READING;

/// The bias's estimate after a rest: its mean \[rad/s\] and variance \[rad^2/s^2\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BiasEstimate {
    /// The bias \[rad/s\].
    pub mean: f64,
    /// Its variance \[rad^2/s^2\].
    pub variance: f64,
}

impl BiasEstimate {
    /// The estimate after a rest that reads `z` with variance `r`, from this one predicted to
    /// the rest's time (the Kalman update of the module doc).
    #[inline]
    pub fn update(self, z: f64, r: f64) -> BiasEstimate {
        let total = self.variance + r;
        BiasEstimate {
            mean: self.mean + self.variance / total * (z - self.mean),
            // not (1 - gain) P: that loses the measurement's variance where P dwarfs it
            variance: self.variance * r / total,
        }
    }
}

/// The filter over rests at `times` (increasing), reading `values` \[rad/s\] with variances
/// `variances` \[rad^2/s^2\], the bias walking with intensity `q` \[rad^2/s^3\]; from the first
/// rest to the last, or from the last to the first where `backward`. Writes, at each rest's index,
/// its filtered `mean` and `variance` (never below `floor`: a rest read without noise would leave
/// 0, and a smoother's backward pass divides by it) and the variance `predicted` there from the
/// rests filtered before it (infinite at the first: a diffuse prior, so the first rest alone
/// gives the bias).
///
/// # Errors
/// As [`check_block`] for `times` and `values` (named `t` and `rate`): unequal
/// lengths, a value that is not finite or beyond [`MAX_READING`], times not
/// strictly increasing; an output of another length; a variance or `floor` not > 0 or beyond
/// 2^40 (the square of a reading's limit); `q` negative or beyond 2^40.
pub fn filter_rests(
    times: &[f64],
    values: &[f64],
    variances: &[f64],
    q: f64,
    floor: f64,
    backward: bool,
    out: (&mut [f64], &mut [f64], &mut [f64]),
) -> Result<(), Error> {
    let (mean, variance, predicted) = out;
    check_block(times, values, None, None, true)?;
    let slices = [
        ("variances", Some(variances)),
        ("mean", Some(&*mean)),
        ("variance", Some(&*variance)),
        ("predicted", Some(&*predicted)),
    ];
    check_outputs(slices, times.len())?;
    // Each within the square of a reading's limit, and `q` so over the longest span of time:
    // a variance of 1e308 (or a floor of it) overflowed the update's `P r`, and a `q` of 1e300
    // the prediction `P + q |dt|` (NaN means and infinite variances). Within them, `P` stays
    // below 2^82 and `P r` below 2^122.
    let valid = "finite, > 0 and at most 2^40 rad^2/s^2 (the square of a reading's limit)";
    for &r in variances {
        check_range("variances", r, f64::MIN_POSITIVE, MAX_VARIANCE, valid)?;
    }
    check_range("floor", floor, f64::MIN_POSITIVE, MAX_VARIANCE, valid)?;
    let valid = "finite, >= 0 and at most 2^40 rad^2/s^3";
    check_range("q", q, 0.0, MAX_VARIANCE, valid)?;
    let n = times.len();
    let order = |i: usize| if backward { n - 1 - i } else { i };
    let mut before: Option<(usize, BiasEstimate)> = None;
    for k in (0..n).map(order) {
        let (z, r) = (values[k], variances[k]);
        // the first rest alone gives the bias (a diffuse prior: `update` of an infinite
        // variance would be inf / inf)
        let (at, p) = match before {
            None => (
                BiasEstimate {
                    mean: z,
                    variance: r,
                },
                f64::INFINITY,
            ),
            Some((j, last)) => {
                let p = last.variance + q * libm::fabs(times[k] - times[j]);
                (
                    BiasEstimate {
                        variance: p,
                        ..last
                    }
                    .update(z, r),
                    p,
                )
            }
        };
        let at = BiasEstimate {
            variance: at.variance.max(floor),
            ..at
        };
        (mean[k], variance[k], predicted[k]) = (at.mean, at.variance, p);
        before = Some((k, at));
    }
    Ok(())
}
