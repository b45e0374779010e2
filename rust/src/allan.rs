//! Allan-family variances for gyro noise characterisation (IEEE Std 952-1997 Annex C,
//! NIST SP 1065 section 5.2; Hong section 2.1 reads ARW and bias instability off this curve).
//!
//! The kernels work on *phase* data: for a gyro the phase is the angle `x_i` \[rad\], sampled
//! every `tau0` \[s\], and the averaged rate over `[i, i + m)` is `(x_{i+m} - x_i) / (m tau0)`.
//! So a rate log is integrated once ([`phase_from_rate`]) and each averaging time
//! `tau = m tau0` is then O(N) work on the phase, whatever `m` is. Each sum is cut into blocks
//! of consecutive terms, added in block order: the short averaging times share one sweep over
//! the record, and with `std` `variances_parallel` shares the blocks among threads with the
//! same result. Otherwise nothing here allocates; the caller owns every buffer, so the module
//! works without `std`.
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

use crate::error::check_range;
use crate::stage::check_len;
use crate::validate::{check_bounded, check_finite_all};
use crate::{Error, MAX_READING, MAX_TIME, MIN_INTERVAL};
use core::ops::Range;

mod differences;
mod phase;
use differences::{
    modified_block, rows, rows_sum, second, second_of, square, sum_of, third, third_of,
};
pub use phase::phase_from_rate;
#[cfg(feature = "std")]
pub use phase::phase_from_rate_stoppable;

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
    /// Every variance of the family, in the order of the module table.
    pub const ALL: [Variance; 5] = [
        Variance::Allan,
        Variance::OverlappingAllan,
        Variance::ModifiedAllan,
        Variance::Hadamard,
        Variance::OverlappingHadamard,
    ];

    /// Order of the phase difference: 2 for the Allan variances, 3 for the Hadamard ones.
    pub fn order(self) -> usize {
        match self {
            Variance::Allan | Variance::OverlappingAllan | Variance::ModifiedAllan => 2,
            Variance::Hadamard | Variance::OverlappingHadamard => 3,
        }
    }

    /// True for the kinds whose terms start at every sample (the overlapping estimators), where
    /// the others step by `m`.
    fn overlapping(self) -> bool {
        matches!(
            self,
            Variance::OverlappingAllan | Variance::OverlappingHadamard
        )
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
            // saturating: a factor beyond the record (up to usize::MAX) leaves no term
            Variance::OverlappingAllan => n.saturating_sub(m.saturating_mul(2)),
            Variance::OverlappingHadamard => n.saturating_sub(m.saturating_mul(3)),
            Variance::ModifiedAllan => n.saturating_add(1).saturating_sub(m.saturating_mul(3)),
        }
    }
}

/// The variance at each averaging factor `factors[k]` (`tau = factors[k] * tau0`) of the phase
/// `x` [rad, sampled every `tau0` s]: `variance[k]` [(rad/s)^2] and the number of terms it
/// averages, `terms[k]`. O(N) per factor, on one thread; no allocation. `variances_parallel`
/// gives the same numbers, bit for bit, from several threads.
///
/// Errors: `tau0` not finite and positive, an output of the wrong length, a non-finite phase
/// sample (or one beyond [`MAX_PHASE`] where a variance would overflow), a zero factor, or a
/// factor too long for the record (no term).
pub fn variances(
    x: &[f64],
    tau0: f64,
    factors: &[usize],
    kind: Variance,
    variance: &mut [f64],
    terms: &mut [u64],
) -> Result<(), Error> {
    summed(x, tau0, factors, kind, || true, variance, terms)
}

/// [`variances`] on this thread as long as `go_on()` (see [`visit_blocks`]).
fn summed(
    x: &[f64],
    tau0: f64,
    factors: &[usize],
    kind: Variance,
    go_on: impl Fn() -> bool,
    variance: &mut [f64],
    terms: &mut [u64],
) -> Result<(), Error> {
    check_request(x, tau0, factors, kind, variance, terms)?;
    variance.fill(0.0);
    // Each factor's blocks come in block order, so this is the block sums added in block order.
    let all = |_, blocks| 0..blocks;
    visit_blocks(x, kind, factors, all, &go_on, |k, _, sum| {
        variance[k] += sum
    });
    if !go_on() {
        return Ok(()); // stopped: the sums are partial, and nothing reads them
    }
    normalise(x.len(), tau0, factors, kind, variance, terms);
    check_phase(x, kind, factors, variance)
}

/// [`variances`] with the blocks shared among `threads` threads (`std` only): the same numbers,
/// bit for bit, whatever the number of threads. Each thread takes an equal share of every
/// factor's blocks; each block sum goes to its place in one table (one number per 8192 terms),
/// which is then added up in block order. A record too short to be worth the threads is summed
/// on the calling thread.
///
/// Errors: as [`variances`].
#[cfg(feature = "std")]
pub fn variances_parallel(
    x: &[f64],
    tau0: f64,
    factors: &[usize],
    kind: Variance,
    threads: usize,
    variance: &mut [f64],
    terms: &mut [u64],
) -> Result<(), Error> {
    let never = std::sync::atomic::AtomicBool::new(false);
    variances_stoppable(x, tau0, factors, kind, threads, &never, variance, terms)
}

/// [`variances_parallel`] that gives up once `stop` is set (by another thread: a Ctrl-C of a
/// long record), each thread at its next block of 8192 terms; `variance` and `terms` are then
/// unspecified, and the caller that set `stop` knows not to read them. A long record at a
/// modified variance takes tens of seconds; looking at `stop` costs a load per block.
///
/// Errors: as [`variances`].
#[cfg(feature = "std")]
#[allow(clippy::too_many_arguments)]
pub fn variances_stoppable(
    x: &[f64],
    tau0: f64,
    factors: &[usize],
    kind: Variance,
    threads: usize,
    stop: &std::sync::atomic::AtomicBool,
    variance: &mut [f64],
    terms: &mut [u64],
) -> Result<(), Error> {
    use std::sync::atomic::Ordering;
    let go_on = || !stop.load(Ordering::Relaxed);
    check_request(x, tau0, factors, kind, variance, terms)?;
    let counts: Vec<usize> = factors
        .iter()
        .map(|&m| Blocks::new(kind, x.len(), m).count())
        .collect();
    let total = counts.iter().sum();
    let threads = threads.min(total / MIN_BLOCKS_PER_THREAD);
    if threads <= 1 {
        return summed(x, tau0, factors, kind, go_on, variance, terms);
    }
    let mut table = vec![0.0; total];
    std::thread::scope(|scope| {
        for (t, mut rows) in thread_shares(&mut table, &counts, threads)
            .into_iter()
            .enumerate()
        {
            let counts = &counts;
            scope.spawn(move || {
                let mine = |_: usize, blocks: usize| share(blocks, t, threads);
                visit_blocks(x, kind, factors, mine, go_on, |k, b, sum| {
                    rows[k][b - share(counts[k], t, threads).start] = sum;
                });
            });
        }
    });
    if !go_on() {
        return Ok(()); // stopped: the sums are partial, and nothing reads them
    }
    let mut sums = table.as_slice();
    for (v, &count) in variance.iter_mut().zip(&counts) {
        let (row, rest) = sums.split_at(count);
        *v = row.iter().fold(0.0, |total, sum| total + sum);
        sums = rest;
    }
    normalise(x.len(), tau0, factors, kind, variance, terms);
    check_phase(x, kind, factors, variance)
}

/// One point of [`variances`]: `(variance [(rad/s)^2], number of terms)` at factor `m`.
pub fn variance(x: &[f64], tau0: f64, m: usize, kind: Variance) -> Result<(f64, u64), Error> {
    let (mut v, mut n) = ([0.0], [0u64]);
    variances(x, tau0, &[m], kind, &mut v, &mut n)?;
    Ok((v[0], n[0]))
}

/// Terms per block of the sums (the modified variance's blocks are longer, see [`Blocks`]).
/// Each factor's sum is its block sums added in block order, so the rounding does not depend
/// on who summed which block. 2^13 terms keep a block's window of `x` (64 KiB plus the
/// factor's span) in L2 cache, and a block sum adds only 1024 terms per lane.
const BLOCK: usize = 1 << 13;

/// The longest span `order * m` [samples] of an overlapping factor that is summed together with
/// the other short ones, block by block: their windows overlap and all fit in L2 cache, so the
/// record is read from memory once for all of them rather than once per factor.
const SHORT_SPAN: usize = 1 << 16;

/// Fewer blocks than this per thread are not worth starting a thread for.
#[cfg(feature = "std")]
const MIN_BLOCKS_PER_THREAD: usize = 16;

/// The errors [`variances`] reports before any work (the phase is checked with the sums, see
/// [`check_phase`]).
fn check_request(
    x: &[f64],
    tau0: f64,
    factors: &[usize],
    kind: Variance,
    variance: &[f64],
    terms: &[u64],
) -> Result<(), Error> {
    check_interval("tau0", tau0)?;
    check_len("variance", variance.len(), factors.len())?;
    check_len("terms", terms.len(), factors.len())?;
    for &m in factors {
        check_factor(kind, x.len(), m)?;
    }
    Ok(())
}

/// The largest magnitude of a phase sample \[rad\]: readings within [`MAX_READING`] over
/// [`MAX_TIME`], 2^60. Within it every variance is finite (a difference of the fourth order is
/// below 2^64, its square times any number of terms over the shortest `tau` far from overflow).
pub const MAX_PHASE: f64 = MAX_READING * MAX_TIME;

/// Fails with [`Error::NonFinite`] at the first NaN or infinity of `x`, given the `variances` at
/// `factors`, or with [`Error::OutOfRange`] at the first sample beyond [`MAX_PHASE`] where a
/// variance overflowed (a phase of 1e308 gave an infinite variance). A non-finite sample makes
/// every variance that reads it non-finite, so finite variances, one of whose terms read every
/// sample, vouch for all of `x`, and spare a pass over it (the cost of one more factor).
fn check_phase(
    x: &[f64],
    kind: Variance,
    factors: &[usize],
    variances: &[f64],
) -> Result<(), Error> {
    if !variances.iter().all(|v| v.is_finite()) {
        return check_bounded("phase", x, MAX_PHASE);
    }
    let vouched = factors
        .iter()
        .any(|&m| reads_every_sample(kind, x.len(), m));
    if vouched {
        Ok(())
    } else {
        check_finite_all("phase", x)
    }
}

/// Whether the terms at factor `m` read every one of the `n` samples. An overlapping sum (and
/// any sum at `m = 1`) reads the rows `[k m, k m + terms)`, `k = 0..=order`, whose union is
/// `[0, n)` when they overlap, i.e. with at least `m` terms. (The modified variance reads its
/// samples in another pattern; it is left to the plain check.)
fn reads_every_sample(kind: Variance, n: usize, m: usize) -> bool {
    let overlapping = kind.overlapping() || (m == 1 && kind != Variance::ModifiedAllan);
    overlapping && kind.terms(n, m) >= m
}

/// A sample interval within [`MIN_INTERVAL`], [`MAX_TIME`]: a variance divides by its square
/// (1e-300 s gave infinity, 1e300 s a silent 0).
fn check_interval(name: &'static str, value: f64) -> Result<(), Error> {
    let valid = "between 1e-12 s and 2^40 s";
    check_range(name, value, MIN_INTERVAL, MAX_TIME, valid)
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
            Variance::ModifiedAllan => m.saturating_mul(3),
            _ => m.saturating_mul(kind.order()).saturating_add(1),
        };
        return Err(Error::TooShort { needed, len: n });
    }
    Ok(())
}

/// Turns the sums of squared differences in `variance` into variances and fills `terms`.
fn normalise(
    n: usize,
    tau0: f64,
    factors: &[usize],
    kind: Variance,
    variance: &mut [f64],
    terms: &mut [u64],
) {
    for ((&m, v), t) in factors.iter().zip(variance).zip(terms) {
        let count = kind.terms(n, m);
        let tau = m as f64 * tau0;
        *v /= match kind {
            Variance::Allan | Variance::OverlappingAllan => 2.0 * tau * tau * count as f64,
            Variance::ModifiedAllan => {
                let mf = m as f64;
                2.0 * mf * mf * tau * tau * count as f64
            }
            Variance::Hadamard | Variance::OverlappingHadamard => 6.0 * tau * tau * count as f64,
        };
        *t = count as u64;
    }
}

/// One factor's terms, cut into blocks of `len` consecutive terms (the last one shorter).
#[derive(Debug, Clone, Copy)]
struct Blocks {
    kind: Variance,
    m: usize,
    terms: usize,
    len: usize,
}

impl Blocks {
    fn new(kind: Variance, n: usize, m: usize) -> Self {
        let len = match kind {
            // A block restarts the modified variance's running inner sum (see modified_block).
            Variance::ModifiedAllan => BLOCK.max(m.saturating_mul(64)),
            _ => BLOCK,
        };
        Blocks {
            kind,
            m,
            terms: kind.terms(n, m),
            len,
        }
    }

    /// Number of blocks.
    fn count(self) -> usize {
        self.terms.div_ceil(self.len)
    }

    /// Whether the factor is summed together with the other short ones (see [`SHORT_SPAN`]).
    fn is_short(self) -> bool {
        self.kind.overlapping() && self.kind.order() * self.m <= SHORT_SPAN
    }

    /// The sum of the squared differences of block `b`, as long as `go_on()` (a long block of
    /// the modified variance asks it within; NaN once stopped: nothing reads the sums then).
    fn sum(self, x: &[f64], b: usize, go_on: impl Fn() -> bool) -> f64 {
        let (m, start) = (self.m, b * self.len);
        let len = self.len.min(self.terms - start);
        match self.kind {
            Variance::OverlappingAllan => rows_sum(rows(x, start, m, len), second_of),
            Variance::OverlappingHadamard => rows_sum(rows(x, start, m, len), third_of),
            Variance::Allan => sum_of(len, |j| square(second(x, (start + j) * m, m))),
            Variance::Hadamard => sum_of(len, |j| square(third(x, (start + j) * m, m))),
            Variance::ModifiedAllan => modified_block(x, m, start, len, go_on).unwrap_or(f64::NAN),
        }
    }
}

/// Calls `visit(k, b, sum)` with the sum of every block `b` in `share(k, number of blocks)` of
/// factor `factors[k]`, each factor's blocks in increasing order, as long as `go_on()` (asked
/// before each block). The short factors go block
/// by block, all of them at each block, while its window of `x` is in cache; then the others
/// one after the other (each reads its three or four streams of `x` from memory anyway).
fn visit_blocks(
    x: &[f64],
    kind: Variance,
    factors: &[usize],
    share: impl Fn(usize, usize) -> Range<usize>,
    go_on: impl Fn() -> bool,
    mut visit: impl FnMut(usize, usize, f64),
) {
    let blocks = |k: usize| Blocks::new(kind, x.len(), factors[k]);
    let mine = |k: usize| share(k, blocks(k).count());
    let short = (0..factors.len()).filter(|&k| blocks(k).is_short());
    let first = short.clone().map(|k| mine(k).start).min().unwrap_or(0);
    let end = short.clone().map(|k| mine(k).end).max().unwrap_or(0);
    for b in first..end {
        if !go_on() {
            return;
        }
        for k in short.clone().filter(|&k| mine(k).contains(&b)) {
            visit(k, b, blocks(k).sum(x, b, &go_on));
        }
    }
    for k in (0..factors.len()).filter(|&k| !blocks(k).is_short()) {
        for b in mine(k) {
            if !go_on() {
                return;
            }
            visit(k, b, blocks(k).sum(x, b, &go_on));
        }
    }
}

/// Thread `t`'s share of `count` blocks among `threads`: consecutive, equal to within one.
#[cfg(feature = "std")]
fn share(count: usize, t: usize, threads: usize) -> Range<usize> {
    count * t / threads..count * (t + 1) / threads
}

/// Each thread's part of the table of block sums, which holds one row of `counts[k]` sums per
/// factor, one row after the other: `parts[t][k]` is the slice of row `k` for the blocks
/// `share(counts[k], t, threads)`.
#[cfg(feature = "std")]
fn thread_shares<'a>(
    mut table: &'a mut [f64],
    counts: &[usize],
    threads: usize,
) -> Vec<Vec<&'a mut [f64]>> {
    let mut parts: Vec<Vec<&mut [f64]>> = (0..threads).map(|_| Vec::new()).collect();
    for &count in counts {
        for (t, part) in parts.iter_mut().enumerate() {
            let (piece, rest) =
                core::mem::take(&mut table).split_at_mut(share(count, t, threads).len());
            part.push(piece);
            table = rest;
        }
    }
    parts
}
