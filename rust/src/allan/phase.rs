//! Rate to phase, the one pass over a rate log before its variances.

use super::differences::sum_of_while;
use super::{check_interval, BLOCK};
use crate::stage::check_len;
use crate::validate::{all_below, check_bounded};
use crate::{Error, MAX_READING};

/// Integrates a regularly sampled rate into phase for the kernels: `x_0 = 0`,
/// `x_{i+1} = x_i + (r_i - r_mean) dt` \[rad\], so `x` holds `rate.len() + 1` samples.
///
/// The mean rate is taken out first: every estimator here differences the phase at least twice,
/// which cancels a linear phase trend exactly, and a phase that stays near zero keeps its
/// significant digits over 10^8 samples. The sum is compensated (Neumaier), so the rounding
/// error of `x` does not grow with the length of the log.
///
/// Errors: `dt` not finite and positive, `x` of the wrong length, a non-finite rate (by index).
pub fn phase_from_rate(rate: &[f64], dt: f64, x: &mut [f64]) -> Result<(), Error> {
    phase_while(rate, dt, x, || true)
}

/// [`phase_from_rate`] that gives up once `stop` is set (by another thread: a Ctrl-C of a long
/// log), looking at it every few thousand samples; `x` is then unspecified. The same phase, bit
/// for bit, when it runs to the end (10^8 samples take a third of a second).
///
/// Errors: as [`phase_from_rate`].
#[cfg(feature = "std")]
pub fn phase_from_rate_stoppable(
    rate: &[f64],
    dt: f64,
    x: &mut [f64],
    stop: &std::sync::atomic::AtomicBool,
) -> Result<(), Error> {
    use std::sync::atomic::Ordering;
    phase_while(rate, dt, x, || !stop.load(Ordering::Relaxed))
}

/// [`phase_from_rate`] as long as `go_on()`, asked every [`BLOCK`] samples of each pass.
fn phase_while(
    rate: &[f64],
    dt: f64,
    x: &mut [f64],
    go_on: impl Fn() -> bool,
) -> Result<(), Error> {
    check_interval("dt", dt)?;
    check_len("phase", x.len(), rate.len() + 1)?;
    // Readings within +-2^20 (as the pipeline's), so that the phase stays finite: 1e308 and
    // -1e308 summed to a finite mean and a NaN phase. Looked over piece by piece (a tenth of a
    // second for 10^8 samples); the whole check names the first bad one, as it always did.
    for piece in rate.chunks(BLOCK) {
        if !go_on() {
            return Ok(());
        }
        if !all_below(piece, MAX_READING) {
            check_bounded("rate", rate, MAX_READING)?;
        }
    }
    let Some(total) = sum_of_while(rate.len(), BLOCK, &go_on, |i| rate[i]) else {
        return Ok(());
    };
    let mean = if rate.is_empty() {
        0.0
    } else {
        total / rate.len() as f64
    };
    let (mut sum, mut compensation) = (0.0_f64, 0.0_f64);
    x[0] = 0.0;
    for (xs, rs) in x[1..].chunks_mut(BLOCK).zip(rate.chunks(BLOCK)) {
        for (xi, &r) in xs.iter_mut().zip(rs) {
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
        if !go_on() {
            return Ok(());
        }
    }
    Ok(())
}
