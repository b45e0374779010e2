//! Public functions an embedding user calls with values at their limits: every call accepted
//! gives finite outputs.

use gyrocore::bias_walk::filter_rests;
use gyrocore::*;

/// `filter_rests` with a walk's intensity, a rest's variance or a floor near the largest float
/// (accepted as finite): the prediction `P + q |dt|` or the update's `P r` overflowed, NaN means
/// and infinite variances. Beyond 2^40 each is refused naming it; at 2^40, over rests 2^41 s
/// apart, every output is finite.
#[test]
fn filter_rests_at_its_limits_gives_finite_estimates() {
    let most = MAX_READING * MAX_READING;
    let t = [-MAX_TIME * 0.999, 0.0, MAX_TIME * 0.999];
    let v = [MAX_READING * 0.999, -MAX_READING * 0.999, 0.5];
    for (q, r, floor, name) in [
        (1e300, 1e-6, 1e-12, "q"),
        (1e-9, 1e308, 1e-12, "variances"),
        (1e-9, 3.0, 1e308, "floor"),
        (f64::MAX, 1.0, 1.0, "q"),
    ] {
        let (mut m, mut va, mut p) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        let err = filter_rests(&t, &v, &[r; 3], q, floor, false, (&mut m, &mut va, &mut p))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(&format!("invalid parameter {name} = ")),
            "{err}"
        );
    }
    for backward in [false, true] {
        for (q, r, floor) in [
            (most, most, most),
            (most, most, 1e-300),
            (0.0, 1e-300, most),
        ] {
            let (mut m, mut va, mut p) = ([0.0; 3], [0.0; 3], [0.0; 3]);
            filter_rests(
                &t,
                &v,
                &[r; 3],
                q,
                floor,
                backward,
                (&mut m, &mut va, &mut p),
            )
            .unwrap();
            assert!(
                m.iter().chain(&va).all(|x| x.is_finite()),
                "q {q:e} r {r:e} floor {floor:e}: {m:?} {va:?}"
            );
            assert!(p.iter().all(|x| !x.is_nan()), "{p:?}");
        }
    }
}
