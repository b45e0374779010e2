//! The sums of squared differences of the phase that every Allan-family variance is made of
//! (second differences `d_i(m)` for the Allan variances, third `h_i(m)` for the Hadamard ones; see
//! the table of the parent module), over one block of consecutive terms.

/// The `K` slices `x[start + k m ..][..len]`: row `k` holds sample `k` of `len` consecutive
/// overlapping terms.
#[inline(always)]
pub(super) fn rows<const K: usize>(x: &[f64], start: usize, m: usize, len: usize) -> [&[f64]; K] {
    core::array::from_fn(|k| &x[start + k * m..][..len])
}

/// Lanes of [`rows_sum`]: eight independent sums keep the additions pipelined, in SIMD registers.
const LANES: usize = 8;

/// `sum_i difference(row_0[i], .., row_{K-1}[i])^2` over rows of equal length, in [`LANES`]
/// partial sums. The rows are walked in whole chunks, which the compiler turns into SIMD code
/// with no bounds checks (1.6 times as fast as indexing `x` term by term). The lanes are added
/// one after the other at the end: a pairwise tree there makes the compiler pair the lanes
/// across registers and load the samples one by one.
#[inline(always)]
pub(super) fn rows_sum<const K: usize>(
    rows: [&[f64]; K],
    difference: impl Fn([f64; K]) -> f64,
) -> f64 {
    let len = rows[0].len();
    let whole = len / LANES * LANES;
    let mut chunks = rows.map(|row| row[..whole].chunks_exact(LANES));
    let mut acc = [0.0_f64; LANES];
    for _ in 0..whole / LANES {
        let chunk = chunks.each_mut().map(|c| c.next().unwrap());
        for (lane, a) in acc.iter_mut().enumerate() {
            *a += square(difference(core::array::from_fn(|k| chunk[k][lane])));
        }
    }
    let tail = (whole..len).map(|i| square(difference(core::array::from_fn(|k| rows[k][i]))));
    acc[0] = tail.fold(acc[0], |sum, term| sum + term);
    acc.iter().fold(0.0, |sum, a| sum + a)
}

#[inline(always)]
pub(super) fn square(v: f64) -> f64 {
    v * v
}

/// `x_{i+2m} - 2 x_{i+m} + x_i` from `[x_i, x_{i+m}, x_{i+2m}]`.
#[inline(always)]
pub(super) fn second_of([a, b, c]: [f64; 3]) -> f64 {
    c - 2.0 * b + a
}

/// `x_{i+3m} - 3 x_{i+2m} + 3 x_{i+m} - x_i` from `[x_i, x_{i+m}, x_{i+2m}, x_{i+3m}]`.
#[inline(always)]
pub(super) fn third_of([a, b, c, d]: [f64; 4]) -> f64 {
    d - 3.0 * (c - b) - a
}

/// `x_{i+2m} - 2 x_{i+m} + x_i`.
#[inline(always)]
pub(super) fn second(x: &[f64], i: usize, m: usize) -> f64 {
    second_of([x[i], x[i + m], x[i + 2 * m]])
}

/// `x_{i+3m} - 3 x_{i+2m} + 3 x_{i+m} - x_i`.
#[inline(always)]
pub(super) fn third(x: &[f64], i: usize, m: usize) -> f64 {
    third_of([x[i], x[i + m], x[i + 2 * m], x[i + 3 * m]])
}

/// `sum_{i<len} f(i)` with four partial sums: the additions pipelined (about 3x faster on one
/// core than one running sum) and the rounding error grows four times more slowly.
#[inline(always)]
pub(super) fn sum_of(len: usize, f: impl FnMut(usize) -> f64) -> f64 {
    sum_of_while(len, usize::MAX, || true, f).unwrap_or(0.0)
}

/// [`sum_of`] that asks `go_on()` after every `every` terms (or so: whole groups of four) and
/// gives up (None) when it says no: the same sum, bit for bit, when it goes to the end. For the
/// terms of a sum long enough that a Ctrl-C should not wait for its end.
#[inline(always)]
pub(super) fn sum_of_while(
    len: usize,
    every: usize,
    go_on: impl Fn() -> bool,
    mut f: impl FnMut(usize) -> f64,
) -> Option<f64> {
    let mut acc = [0.0_f64; 4];
    let whole = len / 4 * 4;
    let mut i = 0;
    while i < whole {
        // Groups stay aligned to four, so each term goes to the partial sum it would in one pass.
        let end = whole.min(i.saturating_add(every));
        while i < end {
            acc[0] += f(i);
            acc[1] += f(i + 1);
            acc[2] += f(i + 2);
            acc[3] += f(i + 3);
            i += 4;
        }
        if !go_on() {
            return None;
        }
    }
    while i < len {
        acc[0] += f(i);
        i += 1;
    }
    Some((acc[0] + acc[1]) + (acc[2] + acc[3]))
}

/// `sum_j (sum_{i=j}^{j+m-1} d_i)^2` for `start <= j < start + len`: the inner sum slides by one
/// each step, `s_{j+1} = s_j + d_{j+m} - d_j = s_j + h_j` (a third difference), so the pass is
/// O(N) for any `m`. Each block starts from an exact O(m) sum, which bounds the rounding drift
/// of the running sum on long records; blocks of at least `64 m` terms keep that extra work
/// under 1/64. Such a block is long (10^8 terms at `m` = 2^20, a third of a second), so `go_on()`
/// is asked every [`BLOCK`](super::BLOCK) terms, as between the blocks of the other variances;
/// once it says no the sum is None.
pub(super) fn modified_block(
    x: &[f64],
    m: usize,
    start: usize,
    len: usize,
    go_on: impl Fn() -> bool,
) -> Option<f64> {
    let mut inner = 0.0;
    sum_of_while(len, super::BLOCK, go_on, |j| {
        inner = if j == 0 {
            sum_of(m, |i| second(x, start + i, m))
        } else {
            inner + third(x, start + j - 1, m)
        };
        square(inner)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::cell::Cell;

    #[test]
    fn a_sum_asked_to_go_on_is_the_one_pass_sum_bit_for_bit() {
        let terms = |i: usize| 1.0 / (i as f64 + 0.3) - 0.5 * (i % 7) as f64;
        for len in [0, 1, 3, 4, 5, 8191, 8192, 8193, 40_003] {
            let one_pass = sum_of(len, terms);
            for every in [1, 4, 6, 8192] {
                let got = sum_of_while(len, every, || true, terms);
                assert_eq!(
                    got.map(f64::to_bits),
                    Some(one_pass.to_bits()),
                    "{len} {every}"
                );
            }
        }
    }

    #[test]
    fn a_long_modified_block_looks_at_go_on_every_block_and_stops_at_the_first_no() {
        // an array, not a Vec: the crate's tests build without std too
        let x: [f64; 30_000] = core::array::from_fn(|i| (i as f64 * 0.37).sin());
        let len = 30_000 - 3 * 5;
        let asked = Cell::new(0);
        let whole = modified_block(&x, 5, 0, len, || {
            asked.set(asked.get() + 1);
            true
        });
        assert_eq!(asked.get(), len.div_ceil(super::super::BLOCK));
        let mut inner = 0.0;
        let expected = sum_of(len, |j| {
            inner = if j == 0 {
                sum_of(5, |i| second(&x, i, 5))
            } else {
                inner + third(&x, j - 1, 5)
            };
            square(inner)
        });
        assert_eq!(whole.map(f64::to_bits), Some(expected.to_bits()));
        asked.set(0);
        let stopped = modified_block(&x, 5, 0, len, || {
            asked.set(asked.get() + 1);
            false
        });
        assert_eq!((stopped, asked.get()), (None, 1));
    }
}
