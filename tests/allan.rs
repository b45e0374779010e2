//! The Allan-family variances against Stable32's results for PHASE.DAT (read from
//! ../shared/data/allan at test time), the textbook definition from averaged rates, and the
//! closed form for white rate noise.

#[cfg(feature = "std")]
use gyrocore::allan::variances_parallel;
use gyrocore::allan::{phase_from_rate, variance, variances};
use gyrocore::{Error, Variance};
use std::path::PathBuf;

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/allan/phase_dat")
}

fn read_numbers(name: &str) -> Vec<Vec<f64>> {
    let path = data_dir().join(name);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (the tests read ../shared/data)", path.display()));
    text.lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            l.split_whitespace()
                .map(|v| v.parse::<f64>().unwrap())
                .collect()
        })
        .collect()
}

fn phase_dat() -> Vec<f64> {
    read_numbers("PHASE.DAT")
        .into_iter()
        .map(|r| r[0])
        .collect()
}

/// Stable32 rows: (averaging factor, number of terms, sigma).
fn stable32(name: &str) -> Vec<(usize, u64, f64)> {
    read_numbers(name)
        .into_iter()
        .map(|r| (r[0] as usize, r[2] as u64, r[5]))
        .collect()
}

/// Stable32 prints five significant digits, so 1e-4 relative holds for every row.
fn check_against_stable32(file: &str, kind: Variance, to_sigma: impl Fn(f64, f64) -> f64) {
    let x = phase_dat();
    assert_eq!(x.len(), 1001);
    let rows = stable32(file);
    assert!(rows.len() >= 8, "{file}: too few rows");
    let factors: Vec<usize> = rows.iter().map(|r| r.0).collect();
    let (mut var, mut terms) = (vec![0.0; rows.len()], vec![0u64; rows.len()]);
    variances(&x, 1.0, &factors, kind, &mut var, &mut terms).unwrap();
    for (k, &(m, n, sigma)) in rows.iter().enumerate() {
        assert_eq!(terms[k], n, "{file}: number of terms at m = {m}");
        let ours = to_sigma(var[k], m as f64);
        let rel = (ours - sigma).abs() / sigma;
        assert!(
            rel <= 1e-4,
            "{file}: m = {m}: {ours} vs Stable32 {sigma} ({rel:.2e})"
        );
    }
}

fn deviation(var: f64, _m: f64) -> f64 {
    var.sqrt()
}

#[test]
fn allan_deviation_matches_stable32() {
    check_against_stable32("phase_dat_adev.txt", Variance::Allan, deviation);
    check_against_stable32("phase_dat_adev_octave.txt", Variance::Allan, deviation);
}

#[test]
fn overlapping_allan_deviation_matches_stable32() {
    check_against_stable32("phase_dat_oadev.txt", Variance::OverlappingAllan, deviation);
    check_against_stable32(
        "phase_dat_oadev_octave.txt",
        Variance::OverlappingAllan,
        deviation,
    );
}

#[test]
fn modified_and_time_deviation_match_stable32() {
    check_against_stable32("phase_dat_mdev.txt", Variance::ModifiedAllan, deviation);
    // TDEV = tau MDEV / sqrt(3) (NIST SP 1065 eq 17); tau0 = 1 s, so tau = m.
    check_against_stable32("phase_dat_tdev.txt", Variance::ModifiedAllan, |v, m| {
        m * v.sqrt() / 3f64.sqrt()
    });
}

#[test]
fn hadamard_deviations_match_stable32() {
    check_against_stable32("phase_dat_hdev.txt", Variance::Hadamard, deviation);
    check_against_stable32(
        "phase_dat_ohdev.txt",
        Variance::OverlappingHadamard,
        deviation,
    );
}

/// Phase of white rate noise: the running sum of `normals`.
fn random_walk(n: usize, seed: u64) -> Vec<f64> {
    normals(n, seed)
        .iter()
        .scan(0.0, |s, w| {
            *s += w;
            Some(*s)
        })
        .collect()
}

/// Deterministic standard normal samples (xorshift64* and Box-Muller), so no dependency is needed.
fn normals(n: usize, mut seed: u64) -> Vec<f64> {
    let mut uniform = move || {
        seed ^= seed >> 12;
        seed ^= seed << 25;
        seed ^= seed >> 27;
        ((seed.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let (u, v) = (uniform(), uniform());
            (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
        })
        .collect()
}

fn phase(rate: &[f64], dt: f64) -> Vec<f64> {
    let mut x = vec![0.0; rate.len() + 1];
    phase_from_rate(rate, dt, &mut x).unwrap();
    x
}

#[test]
fn white_rate_noise_of_density_q_has_adev_q_over_sqrt_tau() {
    // Rate noise of density q [rad/s/sqrt(Hz)] sampled every dt has sigma = q / sqrt(dt) per
    // sample, and ADEV(tau) = q / sqrt(tau) (IEEE 952 Annex C, angle random walk).
    let (q, dt, n) = (2e-3_f64, 0.01_f64, 1usize << 20);
    let rate: Vec<f64> = normals(n, 7)
        .into_iter()
        .map(|w| 0.3 + w * q / dt.sqrt()) // plus a constant bias, which ADEV ignores
        .collect();
    let x = phase(&rate, dt);
    for kind in [Variance::Allan, Variance::OverlappingAllan] {
        for m in [1usize, 4, 16, 64, 256, 1024] {
            let (v, terms) = variance(&x, dt, m, kind).unwrap();
            let tau = m as f64 * dt;
            let expected = q / tau.sqrt();
            // The estimate's relative standard deviation is about 1/sqrt(2 * terms) for the
            // non-overlapping estimator (fewer independent terms than that when overlapping).
            let tolerance = 5.0 / (2.0 * (n / m) as f64).sqrt();
            let rel = (v.sqrt() - expected).abs() / expected;
            assert!(
                rel < tolerance,
                "{kind:?} m = {m} ({terms} terms): {} vs {expected} ({rel:.3e} > {tolerance:.3e})",
                v.sqrt()
            );
        }
    }
}

/// The textbook definition: half the mean square difference of adjacent rate averages over tau.
fn avar_from_averages(rate: &[f64], m: usize, overlapping: bool) -> f64 {
    let avg = |k: usize| rate[k..k + m].iter().sum::<f64>() / m as f64;
    let stride = if overlapping { 1 } else { m };
    let diffs: Vec<f64> = (0..)
        .map(|j| j * stride)
        .take_while(|&k| k + 2 * m <= rate.len())
        .map(|k| avg(k + m) - avg(k))
        .collect();
    diffs.iter().map(|d| d * d).sum::<f64>() / (2.0 * diffs.len() as f64)
}

#[test]
fn rate_route_equals_the_definition_from_averaged_rates() {
    let rate: Vec<f64> = normals(5000, 11)
        .iter()
        .enumerate()
        .map(|(i, w)| 0.05 * w + 1e-4 * i as f64 + 1.5)
        .collect();
    let dt = 0.004;
    let x = phase(&rate, dt);
    for (kind, overlapping) in [(Variance::Allan, false), (Variance::OverlappingAllan, true)] {
        for m in [1usize, 2, 3, 7, 50, 333, 1666] {
            let (v, _) = variance(&x, dt, m, kind).unwrap();
            let expected = avar_from_averages(&rate, m, overlapping);
            assert!(
                ((v - expected) / expected).abs() < 1e-9,
                "{kind:?} m = {m}: {v} vs {expected}"
            );
        }
    }
}

#[test]
fn constant_rate_has_zero_deviation() {
    // A constant rate is a linear phase: every second difference is 0 (to rounding), even with
    // a large rate over a long record.
    let rate = vec![0.068; 100_000];
    let x = phase(&rate, 0.01);
    for kind in [Variance::OverlappingAllan, Variance::ModifiedAllan] {
        let (v, _) = variance(&x, 0.01, 1000, kind).unwrap();
        assert!(v.sqrt() < 1e-14, "{kind:?}: {}", v.sqrt());
    }
}

#[test]
fn modified_variance_running_sum_equals_the_double_sum() {
    // 200_000 terms at m = 3 pass several restarts of the running inner sum.
    let x: Vec<f64> = random_walk(200_010, 3);
    let m = 3;
    let (v, terms) = variance(&x, 1.0, m, Variance::ModifiedAllan).unwrap();
    assert_eq!(terms as usize, x.len() - 3 * m + 1);
    let mut sum = 0.0;
    for j in 0..terms as usize {
        let inner: f64 = (j..j + m)
            .map(|i| x[i + 2 * m] - 2.0 * x[i + m] + x[i])
            .sum();
        sum += inner * inner;
    }
    let expected = sum / (2.0 * (m * m * m * m) as f64 * terms as f64);
    assert!(
        ((v - expected) / expected).abs() < 1e-10,
        "{v} vs {expected}"
    );
}

#[test]
fn bad_input_is_an_error_naming_what_and_where() {
    let x: Vec<f64> = (0..11).map(|i| i as f64).collect();
    assert!(matches!(
        variance(&x, 1.0, 0, Variance::Allan),
        Err(Error::InvalidParameter { .. })
    ));
    // 11 samples hold one Allan term at m = 5 and none at m = 6.
    assert_eq!(variance(&x, 1.0, 5, Variance::Allan).unwrap().1, 1);
    assert_eq!(
        variance(&x, 1.0, 6, Variance::Allan),
        Err(Error::TooShort {
            needed: 13,
            len: 11
        })
    );
    // A factor far beyond the record (its spans overflowed usize): too short, not a panic.
    for kind in Variance::ALL {
        for m in [usize::MAX / 3 + 1, usize::MAX / 2 + 1, usize::MAX] {
            assert!(
                matches!(
                    variance(&x, 1.0, m, kind),
                    Err(Error::TooShort { len: 11, .. })
                ),
                "{kind:?} m = {m}"
            );
            assert_eq!(kind.terms(x.len(), m), 0);
        }
    }
    assert!(matches!(
        variance(&x, 0.0, 1, Variance::Allan),
        Err(Error::InvalidParameter { name: "tau0", .. })
    ));
    let mut y = x.clone();
    y[4] = f64::NAN;
    assert!(matches!(
        variance(&y, 1.0, 1, Variance::Allan),
        Err(Error::NonFinite {
            what: "phase",
            index: 4,
            ..
        })
    ));
    let mut rate = vec![0.0; 10];
    rate[7] = f64::INFINITY;
    let mut out = vec![0.0; 11];
    assert!(matches!(
        phase_from_rate(&rate, 0.1, &mut out),
        Err(Error::NonFinite {
            what: "rate",
            index: 7,
            ..
        })
    ));
    assert!(matches!(
        phase_from_rate(&rate, 0.1, &mut out[..10]),
        Err(Error::LengthMismatch { .. })
    ));
    // 1e308 and -1e308 sum to a finite mean, and gave a NaN phase.
    let huge = [0.0, 1e308, -1e308, 0.0];
    assert!(matches!(
        phase_from_rate(&huge, 0.1, &mut out[..5]),
        Err(Error::OutOfRange {
            what: "rate",
            index: 1,
            ..
        })
    ));
    // A variance divides by tau0^2: 1e-300 s gave infinity, 1e300 s a silent 0.
    for tau0 in [1e-300, 1e300] {
        assert!(matches!(
            variance(&x, tau0, 1, Variance::Allan),
            Err(Error::InvalidParameter { name: "tau0", .. })
        ));
    }
    let (mut v, mut n) = (vec![0.0; 1], vec![0u64; 2]);
    assert!(matches!(
        variances(&x, 1.0, &[1], Variance::Allan, &mut v, &mut n),
        Err(Error::LengthMismatch { what: "terms", .. })
    ));
    assert!(Error::TooShort {
        needed: 13,
        len: 11
    }
    .to_string()
    .contains("13 needed"));
}

#[test]
fn a_non_finite_phase_sample_is_found_wherever_it_is() {
    // Whether or not the factors' terms read every sample (m = 7 non-overlapping reads every
    // seventh), the error names the first bad sample.
    let x: Vec<f64> = (0..1000).map(|i| (i as f64 * 0.37).sin()).collect();
    for kind in Variance::ALL {
        for factors in [&[1usize, 2, 7][..], &[7], &[300]] {
            for (index, bad) in [
                (0, f64::NAN),
                (500, f64::INFINITY),
                (999, f64::NEG_INFINITY),
            ] {
                let mut y = x.clone();
                y[index] = bad;
                let (mut v, mut n) = (vec![0.0; factors.len()], vec![0u64; factors.len()]);
                let result = variances(&y, 1.0, factors, kind, &mut v, &mut n);
                assert!(
                    matches!(result, Err(Error::NonFinite { what: "phase", index: i, .. }) if i == index),
                    "{kind:?} {factors:?} bad at {index}: {result:?}"
                );
            }
        }
    }
}

#[cfg(feature = "std")]
#[test]
fn parallel_variances_equal_the_sequential_ones_bit_for_bit() {
    // Long enough for many blocks per factor, with short factors (summed together), long ones
    // and, for the modified variance, blocks longer than the default.
    let x: Vec<f64> = random_walk(300_001, 5);
    let factors = [1usize, 2, 3, 8, 100, 1024, 20_000, 33_333, 70_000];
    for kind in Variance::ALL {
        let (mut expected, mut expected_terms) = (vec![0.0; 9], vec![0u64; 9]);
        variances(&x, 0.5, &factors, kind, &mut expected, &mut expected_terms).unwrap();
        for threads in [1, 2, 3, 4] {
            let (mut v, mut terms) = (vec![0.0; 9], vec![0u64; 9]);
            variances_parallel(&x, 0.5, &factors, kind, threads, &mut v, &mut terms).unwrap();
            assert_eq!(terms, expected_terms, "{kind:?}, {threads} threads");
            for (a, b) in v.iter().zip(&expected) {
                assert_eq!(a.to_bits(), b.to_bits(), "{kind:?}, {threads} threads");
            }
        }
        let mut y = x.clone();
        y[123_456] = f64::NAN;
        let (mut v, mut terms) = (vec![0.0; 9], vec![0u64; 9]);
        assert!(matches!(
            variances_parallel(&y, 0.5, &factors, kind, 2, &mut v, &mut terms),
            Err(Error::NonFinite {
                what: "phase",
                index: 123_456,
                ..
            })
        ));
    }
}

#[cfg(feature = "std")]
#[test]
fn stoppable_variances_stop_at_once_when_told_and_are_the_parallel_ones_otherwise() {
    use gyrocore::allan::variances_stoppable;
    use std::sync::atomic::AtomicBool;
    let x: Vec<f64> = random_walk(300_001, 6);
    let factors = [1usize, 3, 100, 20_000, 70_000];
    for kind in Variance::ALL {
        let (mut expected, mut expected_terms) = (vec![0.0; 5], vec![0u64; 5]);
        variances_parallel(
            &x,
            0.5,
            &factors,
            kind,
            2,
            &mut expected,
            &mut expected_terms,
        )
        .unwrap();
        let (mut v, mut terms) = (vec![0.0; 5], vec![0u64; 5]);
        let go = AtomicBool::new(false);
        for threads in [1, 2] {
            variances_stoppable(&x, 0.5, &factors, kind, threads, &go, &mut v, &mut terms).unwrap();
            assert_eq!(terms, expected_terms, "{kind:?}");
            let bits = |v: &[f64]| v.iter().map(|a| a.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&v), bits(&expected), "{kind:?}");
        }
        // Told to stop before the first block: no block is summed, whatever the threads.
        let stop = AtomicBool::new(true);
        for threads in [1, 2] {
            let r =
                variances_stoppable(&x, 0.5, &factors, kind, threads, &stop, &mut v, &mut terms);
            assert!(r.is_ok(), "{kind:?}: {r:?}");
            assert!(v.iter().all(|&s| s == 0.0), "{kind:?}: {v:?}");
        }
    }
}

#[cfg(feature = "std")]
#[test]
fn a_stoppable_phase_and_bias_test_stop_when_told_and_are_the_plain_ones_otherwise() {
    use gyrocore::allan::phase_from_rate_stoppable;
    use gyrocore::{static_bias_test, static_bias_test_stoppable};
    use std::sync::atomic::AtomicBool;
    let rate: Vec<f64> = random_walk(200_003, 9);
    let t: Vec<f64> = (0..rate.len()).map(|i| i as f64 * 0.01).collect();
    let (go, stop) = (AtomicBool::new(false), AtomicBool::new(true));
    let (mut expected, mut x) = (vec![0.0; rate.len() + 1], vec![0.0; rate.len() + 1]);
    phase_from_rate(&rate, 0.01, &mut expected).unwrap();
    phase_from_rate_stoppable(&rate, 0.01, &mut x, &go).unwrap();
    let bits = |v: &[f64]| v.iter().map(|a| a.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&x), bits(&expected));
    // told to stop before the first piece: nothing of the phase is written
    let mut untouched = vec![7.0; rate.len() + 1];
    phase_from_rate_stoppable(&rate, 0.01, &mut untouched, &stop).unwrap();
    assert!(untouched.iter().all(|&v| v == 7.0));
    let whole = static_bias_test(&t, &rate, 10.0, 1500.0).unwrap();
    let same = static_bias_test_stoppable(&t, &rate, 10.0, 1500.0, &go).unwrap();
    assert_eq!(same, Some(whole));
    assert_eq!(
        static_bias_test_stoppable(&t, &rate, 10.0, 1500.0, &stop),
        Ok(None)
    );
}
