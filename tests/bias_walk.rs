//! The random-walk bias filter over rests (`bias_walk::filter_rests`), against closed forms: no
//! walk gives the inverse-variance mean; the backward pass is the forward pass over the rests in
//! reverse; a walk weighs a rest less the further it lies; bad input is refused by name.

use gyrocore::bias_walk::{filter_rests, BiasEstimate};
use gyrocore::Error;
use proptest::prelude::*;

type Filtered = (Vec<f64>, Vec<f64>, Vec<f64>);

fn run(times: &[f64], values: &[f64], variances: &[f64], q: f64, backward: bool) -> Filtered {
    let n = times.len();
    let (mut m, mut v, mut p) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    filter_rests(
        times,
        values,
        variances,
        q,
        1e-24,
        backward,
        (&mut m, &mut v, &mut p),
    )
    .unwrap();
    (m, v, p)
}

fn rests() -> impl Strategy<Value = (Vec<f64>, Vec<f64>, Vec<f64>)> {
    (2usize..12).prop_flat_map(|n| {
        (
            proptest::collection::vec(0.5f64..100.0, n),
            proptest::collection::vec(-0.1f64..0.1, n),
            proptest::collection::vec(1e-8f64..1e-4, n),
        )
            .prop_map(|(gaps, values, variances)| {
                let times = gaps
                    .iter()
                    .scan(0.0, |t, g| {
                        *t += g;
                        Some(*t)
                    })
                    .collect();
                (times, values, variances)
            })
    })
}

proptest! {
    #[test]
    fn without_a_walk_the_last_rest_holds_the_inverse_variance_mean((t, z, r) in rests()) {
        let (m, v, _) = run(&t, &z, &r, 0.0, false);
        let info: f64 = r.iter().map(|r| 1.0 / r).sum();
        let mean = z.iter().zip(&r).map(|(z, r)| z / r).sum::<f64>() / info;
        let last = t.len() - 1;
        prop_assert!((m[last] - mean).abs() <= 1e-12 * (1.0 + mean.abs()));
        prop_assert!((v[last] * info - 1.0).abs() <= 1e-12);
    }

    #[test]
    fn the_backward_pass_is_the_forward_pass_over_the_rests_reversed((t, z, r) in rests(), q in 0.0f64..1e-6) {
        let back = run(&t, &z, &r, q, true);
        let reversed = |a: &[f64]| a.iter().rev().copied().collect::<Vec<_>>();
        let negated: Vec<f64> = t.iter().rev().map(|t| -t).collect();  // increasing, the same gaps
        let (m, v, p) = run(&negated, &reversed(&z), &reversed(&r), q, false);
        prop_assert_eq!(back, (reversed(&m), reversed(&v), reversed(&p)));
    }
}

#[test]
fn a_walk_weighs_the_earlier_rest_less_the_further_it_lies() {
    // two rests read 0 and 1 with variance r; after dt the first's variance is r + q dt, so the
    // second gets the gain (r + q dt) / (2 r + q dt)
    let (r, q) = (1e-6, 1e-9);
    for dt in [1.0, 1000.0, 1e6] {
        let m = run(&[0.0, dt], &[0.0, 1.0], &[r, r], q, false).0[1];
        let gain = (r + q * dt) / (2.0 * r + q * dt);
        assert!((m - gain).abs() < 1e-15, "{dt}: {m} against {gain}");
    }
}

#[test]
fn the_update_is_the_textbook_gain() {
    let at = BiasEstimate {
        mean: 1.0,
        variance: 3.0,
    }
    .update(2.0, 1.0);
    assert_eq!(
        at,
        BiasEstimate {
            mean: 1.75,
            variance: 0.75
        }
    );
}

#[test]
fn bad_rests_are_refused_by_name() {
    let (mut m, mut v, mut p) = (vec![0.0; 2], vec![0.0; 2], vec![0.0; 2]);
    let mut call = |t: &[f64], z: &[f64], r: &[f64], q: f64| {
        filter_rests(t, z, r, q, 1e-24, false, (&mut m, &mut v, &mut p))
    };
    assert!(matches!(
        call(&[1.0, 1.0], &[0.0; 2], &[1e-6; 2], 0.0),
        Err(Error::NotIncreasing { index: 1, .. })
    ));
    assert!(matches!(
        call(&[0.0, 1.0], &[0.0, f64::NAN], &[1e-6; 2], 0.0),
        Err(Error::NonFinite {
            what: "rate",
            index: 1,
            ..
        })
    ));
    assert!(matches!(
        call(&[0.0, 1.0], &[0.0; 2], &[1e-6, 0.0], 0.0),
        Err(Error::InvalidParameter {
            name: "variances",
            ..
        })
    ));
    assert!(matches!(
        call(&[0.0, 1.0], &[0.0; 2], &[1e-6; 2], -1.0),
        Err(Error::InvalidParameter { name: "q", .. })
    ));
    assert!(matches!(
        call(&[0.0, 1.0], &[0.0; 2], &[1e-6], 0.0),
        Err(Error::LengthMismatch {
            what: "variances",
            len: 1,
            expected: 2
        })
    ));
    assert!(call(&[], &[], &[], 0.0).is_err()); // the outputs are longer than no rest
    let mut short = [0.0];
    let err = filter_rests(
        &[0.0, 1.0],
        &[0.0; 2],
        &[1e-6; 2],
        0.0,
        1e-24,
        false,
        (&mut m, &mut short, &mut p),
    );
    assert!(matches!(
        err,
        Err(Error::LengthMismatch {
            what: "variance",
            len: 1,
            expected: 2
        })
    ));
    let (e, mut none) = ([0.0; 0], [0.0; 0]);
    let (mut a, mut b) = ([0.0; 0], [0.0; 0]);
    assert!(filter_rests(&e, &e, &e, 0.0, 1e-24, false, (&mut none, &mut a, &mut b)).is_ok());
}

#[test]
fn no_rest_leaves_a_variance_below_the_floor_not_even_the_first() {
    // Rests read far more precisely than the floor: each filtered variance is the floor, the
    // first's too (it was its own reading's, 1e-30, below the floor the doc promises).
    let (t, z, r) = ([1.0, 2.0, 3.0], [0.01, 0.02, 0.03], [1e-30; 3]);
    for backward in [false, true] {
        let (mut m, mut v, mut p) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        filter_rests(&t, &z, &r, 0.0, 1e-24, backward, (&mut m, &mut v, &mut p)).unwrap();
        assert_eq!(v, [1e-24; 3], "backward {backward}");
    }
}
