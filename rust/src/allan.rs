//! Allan-family variances for gyro noise characterisation (IEEE Std 952-1997 Annex C,
//! NIST SP 1065 section 5.2; Hong section 2.1 reads ARW and bias instability off this curve).
//!
//! The kernels work on *phase* data: for a gyro the phase is the angle `x_i` [rad], sampled
//! every `tau0` [s], and the averaged rate over `[i, i + m)` is `(x_{i+m} - x_i) / (m tau0)`.
//! So a rate log is integrated once ([`phase_from_rate`]) and each averaging time
//! `tau = m tau0` is then one pass over the phase: O(N) per tau, whatever `m` is. Nothing here
//! allocates; the caller owns every buffer, so the module works without `std`.
//!
//! With `d_i(m) = x_{i+2m} - 2 x_{i+m} + x_i` (second difference) and
//! `h_i(m) = x_{i+3m} - 3 x_{i+2m} + 3 x_{i+m} - x_i` (third difference), for `N` phase samples:
//!
//! | [`Variance`] | estimate | terms |
//! |---|---|---|
//! | `Allan` | `sum d_i^2 / (2 tau^2 M)`, `i = 0, m, 2m, ...` | `M = floor((N-1)/m) - 1` |
//! | `OverlappingAllan` | `sum d_i^2 / (2 tau^2 M)`, every `i` | `M = N - 2m` |
//! | `ModifiedAllan` | `sum_j (sum_{i=j}^{j+m-1} d_i)^2 / (2 m^2 tau^2 M)` | `M = N - 3m + 1` |
//! | `Hadamard` | `sum h_i^2 / (6 tau^2 M)`, `i = 0, m, 2m, ...` | `M = floor((N-1)/m) - 2` |
//! | `OverlappingHadamard` | `sum h_i^2 / (6 tau^2 M)`, every `i` | `M = N - 3m` |
//!
//! These are Stable32's estimators; `tests/allan.rs` checks them against its output.

use crate::error::check_positive;
use crate::stage::check_len;
use crate::validate::check_finite_all;
use crate::Error;

/// Which variance of the Allan family to estimate (see the module table).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variance {
    /// Allan variance, non-overlapping (stride `m`).
    Allan,
    /// Overlapping Allan variance (stride 1): the same quantity with more terms.
    OverlappingAllan,
    /// Modified Allan variance (always overlapping); separates white from flicker angle noise.
    ModifiedAllan,
    /// Hadamard variance, non-overlapping: insensitive to a linear rate drift.
    Hadamard,
    /// Overlapping Hadamard variance.
    OverlappingHadamard,
}

impl Variance {
    /// Order of the phase difference: 2 for the Allan variances, 3 for the Hadamard ones.
    pub fn order(self) -> usize {
        match self {
            Variance::Allan | Variance::OverlappingAllan | Variance::ModifiedAllan => 2,
            Variance::Hadamard | Variance::OverlappingHadamard => 3,
        }
    }

    /// Number of terms averaged at factor `m` over `n` phase samples (0: not computable).
    pub fn terms(self, n: usize, m: usize) -> usize {
        if m == 0 || n == 0 {
            return 0;
        }
        let spans = (n - 1) / m; // whole steps of m that fit in the record
        match self {
            Variance::Allan => spans.saturating_sub(1),
            Variance::Hadamard => spans.saturating_sub(2),
            Variance::OverlappingAllan => n.saturating_sub(2 * m),
            Variance::OverlappingHadamard => n.saturating_sub(3 * m),
            Variance::ModifiedAllan => (n + 1).saturating_sub(3 * m),
        }
    }
}

/// Integrates a regularly sampled rate into phase for the kernels: `x_0 = 0`,
/// `x_{i+1} = x_i + (r_i - r_mean) dt` [rad], so `x` holds `rate.len() + 1` samples.
///
/// The mean rate is taken out first: every estimator here differences the phase at least twice,
/// which cancels a linear phase trend exactly, and a phase that stays near zero keeps its
/// significant digits over 10^8 samples. The sum is compensated (Neumaier), so the rounding
/// error of `x` does not grow with the length of the log.
///
/// Errors: `dt` not finite and positive, `x` of the wrong length, a non-finite rate (by index).
pub fn phase_from_rate(rate: &[f64], dt: f64, x: &mut [f64]) -> Result<(), Error> {
    check_positive("dt", dt)?;
    check_len("phase", x.len(), rate.len() + 1)?;
    check_finite_all("rate", rate)?;
    let mean = if rate.is_empty() {
        0.0
    } else {
        sum_of(rate.len(), |i| rate[i]) / rate.len() as f64
    };
    let (mut sum, mut compensation) = (0.0_f64, 0.0_f64);
    x[0] = 0.0;
    for (xi, &r) in x[1..].iter_mut().zip(rate) {
        let step = (r - mean) * dt;
        let next = sum + step;
        compensation += if libm::fabs(sum) >= libm::fabs(step) {
            (sum - next) + step
        } else {
            (step - next) + sum
        };
        sum = next;
        *xi = sum + compensation;
    }
    Ok(())
}

/// The variance at each averaging factor `factors[k]` (`tau = factors[k] * tau0`) of the phase
/// `x` [rad, sampled every `tau0` s]: `variance[k]` [(rad/s)^2] and the number of terms it
/// averages, `terms[k]`. One pass over `x` per factor; no allocation.
///
/// Errors: `tau0` not finite and positive, an output of the wrong length, a non-finite phase
/// sample, a zero factor, or a factor too long for the record (no term).
pub fn variances(
    x: &[f64],
    tau0: f64,
    factors: &[usize],
    kind: Variance,
    variance: &mut [f64],
    terms: &mut [u64],
) -> Result<(), Error> {
    check_positive("tau0", tau0)?;
    check_len("variance", variance.len(), factors.len())?;
    check_len("terms", terms.len(), factors.len())?;
    check_finite_all("phase", x)?;
    for &m in factors {
        check_factor(kind, x.len(), m)?;
    }
    for ((&m, v), n) in factors
        .iter()
        .zip(variance.iter_mut())
        .zip(terms.iter_mut())
    {
        let count = kind.terms(x.len(), m);
        let tau = m as f64 * tau0;
        let sum = match kind {
            Variance::Allan => sum_of(count, |j| square(second(x, j * m, m))),
            Variance::OverlappingAllan => sum_of(count, |i| square(second(x, i, m))),
            Variance::Hadamard => sum_of(count, |j| square(third(x, j * m, m))),
            Variance::OverlappingHadamard => sum_of(count, |i| square(third(x, i, m))),
            Variance::ModifiedAllan => modified_sum(x, m, count),
        };
        *v = match kind {
            Variance::Allan | Variance::OverlappingAllan => sum / (2.0 * tau * tau * count as f64),
            Variance::ModifiedAllan => {
                let mf = m as f64;
                sum / (2.0 * mf * mf * tau * tau * count as f64)
            }
            Variance::Hadamard | Variance::OverlappingHadamard => {
                sum / (6.0 * tau * tau * count as f64)
            }
        };
        *n = count as u64;
    }
    Ok(())
}

/// One point of [`variances`]: `(variance [(rad/s)^2], number of terms)` at factor `m`.
pub fn variance(x: &[f64], tau0: f64, m: usize, kind: Variance) -> Result<(f64, u64), Error> {
    let (mut v, mut n) = ([0.0], [0u64]);
    variances(x, tau0, &[m], kind, &mut v, &mut n)?;
    Ok((v[0], n[0]))
}

fn check_factor(kind: Variance, n: usize, m: usize) -> Result<(), Error> {
    if m == 0 {
        return Err(Error::InvalidParameter {
            name: "averaging factor",
            value: 0.0,
            valid: ">= 1",
        });
    }
    if kind.terms(n, m) == 0 {
        // The shortest record with one term: order * m + 1 samples (3m for the modified variance).
        let needed = match kind {
            Variance::ModifiedAllan => 3 * m,
            _ => kind.order() * m + 1,
        };
        return Err(Error::TooShort { needed, len: n });
    }
    Ok(())
}

#[inline(always)]
fn square(v: f64) -> f64 {
    v * v
}

/// `x_{i+2m} - 2 x_{i+m} + x_i`.
#[inline(always)]
fn second(x: &[f64], i: usize, m: usize) -> f64 {
    x[i + 2 * m] - 2.0 * x[i + m] + x[i]
}

/// `x_{i+3m} - 3 x_{i+2m} + 3 x_{i+m} - x_i`.
#[inline(always)]
fn third(x: &[f64], i: usize, m: usize) -> f64 {
    x[i + 3 * m] - 3.0 * (x[i + 2 * m] - x[i + m]) - x[i]
}

/// `sum_{i<len} f(i)` with four partial sums: the additions pipeline (about 3x faster on one
/// core than one running sum) and the rounding error grows four times more slowly.
#[inline(always)]
fn sum_of(len: usize, mut f: impl FnMut(usize) -> f64) -> f64 {
    let mut acc = [0.0_f64; 4];
    let whole = len / 4 * 4;
    let mut i = 0;
    while i < whole {
        acc[0] += f(i);
        acc[1] += f(i + 1);
        acc[2] += f(i + 2);
        acc[3] += f(i + 3);
        i += 4;
    }
    while i < len {
        acc[0] += f(i);
        i += 1;
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// `sum_j (sum_{i=j}^{j+m-1} d_i)^2` for `j < count`: the inner sum slides by one each step,
/// `s_{j+1} = s_j + d_{j+m} - d_j = s_j + h_j` (a third difference), so the pass is O(N) for
/// any `m`. The slide is restarted from an exact O(m) sum every `max(2^16, 64 m)` steps, which
/// bounds the rounding drift of the running sum on long records for at most 1/64 more work.
fn modified_sum(x: &[f64], m: usize, count: usize) -> f64 {
    let restart = (1usize << 16).max(64 * m);
    let exact = |j: usize| sum_of(m, |i| second(x, j + i, m));
    let mut inner = 0.0;
    sum_of(count, |j| {
        inner = if j % restart == 0 {
            exact(j)
        } else {
            inner + third(x, j - 1, m)
        };
        square(inner)
    })
}
