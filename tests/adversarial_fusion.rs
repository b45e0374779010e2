//! The heading-fix filter and the fused pipeline on hostile but valid input: times at the limits,
//! fixes at block edges, at one time, before the first sample and far past the last, re-admission
//! at its edges (`readmit_after` 0 and inf); any cut of the samples into blocks (empty ones and
//! blocks of one sample included) and a copy read back at the cut give the bits of one call.

use gyrocore::{Fix, FusedOutputs, FusedPipeline, Fusion, FusionConfig, FusionOutputs, Preset};
use gyrocore::{GapAction, InputPolicy, NonFinite, Samples, MAX_TIME};
use proptest::prelude::*;

/// Increasing times from `t0` with steps from 1e-9 s to 1e5 s, and rates up to 30 rad/s.
fn samples(max: usize) -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
    let step = prop_oneof![Just(1e-9), 1e-3..0.1f64, Just(1e5)];
    let t0 = prop_oneof![Just(0.0), Just(-MAX_TIME * 0.999), Just(MAX_TIME * 0.99)];
    (
        t0,
        proptest::collection::vec((step, -30.0..30.0f64), 1..max),
    )
        .prop_map(|(t0, v)| {
            let mut t = Vec::with_capacity(v.len());
            let mut now = t0;
            for (dt, _) in &v {
                t.push(now);
                now += dt.max(now.abs() * 1e-15 * 4.0);
            }
            (t, v.into_iter().map(|(_, r)| r).collect())
        })
}

/// Fixes at sample times, between them, twice at one time, before the first sample and past the
/// last, with headings anywhere in +-2^20 and sigmas from 1e-12 to 2^20.
fn fixes(t: &[f64], picks: &[(usize, u8, f64, f64)]) -> Vec<Fix> {
    let (first, last) = (t[0], t[t.len() - 1]);
    let mut out: Vec<Fix> = picks
        .iter()
        .map(|&(k, how, heading, sigma)| {
            let k = k % t.len();
            let at = match how % 5 {
                0 => t[k],
                1 if k + 1 < t.len() => 0.5 * (t[k] + t[k + 1]),
                2 => first - 1.0,
                3 => (last + 1e6).min(MAX_TIME * 0.999),
                _ => t[k],
            };
            Fix {
                t: at,
                heading,
                sigma,
            }
        })
        .collect();
    out.sort_by(|a, b| a.t.total_cmp(&b.t));
    out
}

fn pick() -> impl Strategy<Value = (usize, u8, f64, f64)> {
    let sigma = prop_oneof![Just(1e-12), 1e-4..1.0f64, Just(1_048_576.0)];
    (
        any::<usize>(),
        any::<u8>(),
        -1_048_576.0..1_048_576.0f64,
        sigma,
    )
}

fn config() -> impl Strategy<Value = FusionConfig> {
    let readmit = prop_oneof![Just(0.0), Just(1e-3), Just(f64::INFINITY)];
    let gate = prop_oneof![Just(f64::MIN_POSITIVE), Just(1.0), Just(f64::INFINITY)];
    (
        readmit,
        gate,
        prop_oneof![Just(1e-9), Just(1e-3), Just(1e3)],
    )
        .prop_map(|(r, g, w)| FusionConfig {
            readmit_after: r,
            gate: g,
            arw: w,
            bias_walk: w,
            ..FusionConfig::default()
        })
}

type Cols = [Vec<f64>; 4];

/// A copy of `x` as a run resumed from a store gets it: read back from JSON with the `serde`
/// feature, a clone without.
#[cfg(feature = "serde")]
fn resumed<T: serde::Serialize + serde::de::DeserializeOwned>(x: &T) -> T {
    serde_json::from_str(&serde_json::to_string(x).unwrap()).unwrap()
}

#[cfg(not(feature = "serde"))]
fn resumed<T: Clone>(x: &T) -> T {
    x.clone()
}

/// The filter over `t[from..to]` with the fixes still to come; returns how many it used.
fn fusion_block(
    f: &mut Fusion,
    t: &[f64],
    r: &[f64],
    fx: &[Fix],
    cols: &mut Cols,
    from: usize,
    to: usize,
) -> usize {
    let [h, s, b, c] = cols;
    let out = FusionOutputs::all(
        &mut h[from..to],
        &mut s[from..to],
        &mut b[from..to],
        &mut c[from..to],
    );
    f.process_block(&t[from..to], &r[from..to], fx, out)
        .unwrap()
}

fn bits(cols: &Cols) -> Vec<Vec<u64>> {
    cols.iter()
        .map(|c| c.iter().map(|v| v.to_bits()).collect())
        .collect()
}

/// Cuts (sorted, within `0..=n`, repeated: empty blocks) with a copy read back at each.
fn run_fusion(
    config: FusionConfig,
    t: &[f64],
    r: &[f64],
    fx: &[Fix],
    cuts: &[usize],
) -> (Cols, Fusion) {
    let n = t.len();
    let mut cols: Cols = core::array::from_fn(|_| vec![0.0; n]);
    let mut f = Fusion::new(config).unwrap();
    let mut used = 0;
    let mut from = 0;
    let mut ends: Vec<usize> = cuts.iter().map(|&c| c % (n + 1)).collect();
    ends.sort_unstable();
    ends.push(n);
    for to in ends {
        used += fusion_block(&mut f, t, r, &fx[used..], &mut cols, from, to);
        f = resumed(&f);
        from = to;
    }
    // the fixes past the last sample wait, unused
    assert_eq!(used, fx.iter().filter(|x| x.t <= t[n - 1]).count());
    (cols, f)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn a_filter_cut_anywhere_and_read_back_gives_the_bits_of_one_call(
        (t, r) in samples(40),
        picks in proptest::collection::vec(pick(), 0..12),
        config in config(),
        cuts in proptest::collection::vec(any::<usize>(), 0..6),
    ) {
        let fx = fixes(&t, &picks);
        let (whole, f1) = run_fusion(config, &t, &r, &fx, &[]);
        let (cut, f2) = run_fusion(config, &t, &r, &fx, &cuts);
        prop_assert_eq!(bits(&cut), bits(&whole));
        prop_assert_eq!(f1, f2);
        for (c, col) in whole.iter().enumerate() {
            prop_assert!(col.iter().all(|v| v.is_finite()), "column {} of {:?}", c, col);
        }
        prop_assert!(whole[1].iter().all(|&s| s > 0.0));
        let k = f1.counts();
        prop_assert!(k.readmitted <= k.applied);
        if config.readmit_after == f64::INFINITY {
            prop_assert_eq!(k.readmitted, 0);
        }
    }

    #[test]
    fn a_fused_pipeline_cut_anywhere_and_read_back_gives_the_bits_of_one_call(
        (t, r) in samples(40),
        picks in proptest::collection::vec(pick(), 0..12),
        config in config(),
        cuts in proptest::collection::vec(any::<usize>(), 0..6),
        speed in proptest::collection::vec(prop_oneof![Just(0.0), 0.0..20.0f64, Just(f64::NAN)], 40),
        nan in proptest::collection::vec(any::<usize>(), 0..8),
        (skip, reset, gap) in (any::<bool>(), any::<bool>(), prop_oneof![Just(1e-6), Just(0.05), Just(f64::INFINITY)]),
    ) {
        let fx = fixes(&t, &picks);
        let n = t.len();
        // readings the pipeline holds or skips, and gaps it bridges or restarts at
        let mut r = r;
        for k in nan {
            r[k % n] = f64::NAN;
        }
        let mut pipeline = Preset::Tracked.config();
        pipeline.input = InputPolicy {
            non_finite: if skip { NonFinite::Skip } else { NonFinite::Hold },
            gap_limit: gap,
            gap_action: if reset { GapAction::Reset } else { GapAction::Bridge },
        };
        let run = |cuts: &[usize]| {
            let mut p = FusedPipeline::new(pipeline, config).unwrap();
            let mut cols: [Vec<f64>; 6] = core::array::from_fn(|_| vec![0.0; n]);
            let mut ends: Vec<usize> = cuts.iter().map(|&c| c % (n + 1)).collect();
            ends.sort_unstable();
            ends.push(n);
            let (mut from, mut used) = (0, 0);
            for to in ends {
                let [h, s, b, c, rate, d] = &mut cols;
                let out = FusedOutputs {
                    heading: &mut h[from..to],
                    heading_sigma: Some(&mut s[from..to]),
                    bias: Some(&mut b[from..to]),
                    scale: Some(&mut c[from..to]),
                    rate: &mut rate[from..to],
                    drift: Some(&mut d[from..to]),
                };
                let samples = Samples { speed: Some(&speed[from..to]), ..Samples::new(&t[from..to], &r[from..to]) };
                used += p.process_block(samples, &fx[used..], out).unwrap();
                p = resumed(&p);
                from = to;
            }
            let finite = cols_finite(&cols);
            (cols.map(|c| c.iter().map(|v| v.to_bits()).collect::<Vec<u64>>()), p, finite)
        };
        let (whole, p1, finite) = run(&[]);
        let (cut, p2, _) = run(&cuts);
        prop_assert_eq!(cut, whole);
        prop_assert_eq!(p1, p2);
        prop_assert!(finite);
    }
}

fn cols_finite(cols: &[Vec<f64>; 6]) -> bool {
    cols[..4].iter().all(|c| c.iter().all(|v| v.is_finite()))
}

/// The smoother's second pass over `cuts` (the knots of one forward run over all samples).
fn smoothed(
    config: FusionConfig,
    t: &[f64],
    r: &[f64],
    fx: &[Fix],
    knots: &[gyrocore::Knot],
    cuts: &[usize],
) -> Cols {
    let n = t.len();
    let mut cols: Cols = core::array::from_fn(|_| vec![0.0; n]);
    let mut f = Fusion::new(config).unwrap();
    let mut ends: Vec<usize> = cuts.iter().map(|&c| c % (n + 1)).collect();
    ends.sort_unstable();
    ends.push(n);
    let (mut from, mut used) = (0, 0);
    for to in ends {
        let [h, s, b, c] = &mut cols;
        let out = FusionOutputs::all(
            &mut h[from..to],
            &mut s[from..to],
            &mut b[from..to],
            &mut c[from..to],
        );
        used += f
            .process_block_smoothed(&t[from..to], &r[from..to], &fx[used..], knots, out)
            .unwrap();
        f = resumed(&f);
        from = to;
    }
    cols
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    #[test]
    fn the_smoothers_pass_cut_anywhere_gives_the_bits_of_one_call_and_is_no_less_sure(
        (t, r) in samples(40),
        picks in proptest::collection::vec(pick(), 0..12),
        config in config(),
        cuts in proptest::collection::vec(any::<usize>(), 0..6),
    ) {
        let fx = fixes(&t, &picks);
        let n = t.len();
        let mut knots = Vec::new();
        let mut causal: Cols = core::array::from_fn(|_| vec![0.0; n]);
        let [h, s, b, c] = &mut causal;
        Fusion::new(config)
            .unwrap()
            .process_block_recording(&t, &r, &fx, FusionOutputs::all(h, s, b, c), |k| knots.push(k))
            .unwrap();
        prop_assert_eq!(gyrocore::smooth(&mut knots), 0);
        let whole = smoothed(config, &t, &r, &fx, &knots, &[]);
        let cut = smoothed(config, &t, &r, &fx, &knots, &cuts);
        prop_assert_eq!(bits(&cut), bits(&whole));
        for (c, col) in whole.iter().enumerate() {
            prop_assert!(col.iter().all(|v| v.is_finite()), "column {} of {:?}", c, col);
        }
        // the fixes after a sample can only add to what is known of it (to a nanoradian: at a
        // 1e-12 rad fix after a gap of 1e5 s the smoothed sigma rounds to 1.3 % above it)
        for k in 0..n {
            prop_assert!(whole[1][k] <= causal[1][k] + 1e-9, "sample {}: {} > {}", k, whole[1][k], causal[1][k]);
        }
    }
}
