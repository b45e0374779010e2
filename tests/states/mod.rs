//! What the read-back tests share: a filter's state, and states edited by hand, refused or read.
#![allow(dead_code)] // each test binary uses its own subset of the helpers

use gyrocore::*;
use serde_json::{json, Value};

/// A filter after a few fixes, its covariance correlated.
pub fn fusion() -> Fusion {
    let t: Vec<f64> = (0..500).map(|i| i as f64 * 0.01).collect();
    let rate = vec![0.2; t.len()];
    let fixes: Vec<Fix> = (0..5)
        .map(|s| Fix {
            t: s as f64 + 0.5,
            heading: 0.2 * (s as f64 + 0.5),
            sigma: 0.05,
        })
        .collect();
    let mut f = Fusion::new(FusionConfig::default()).unwrap();
    let mut h = vec![0.0; t.len()];
    f.process_block(&t, &rate, &fixes, FusionOutputs::heading(&mut h))
        .unwrap();
    f
}

/// The error reading `v` back as a `T`, which must be refused.
pub fn refused<T: serde::de::DeserializeOwned + core::fmt::Debug>(v: Value) -> String {
    serde_json::from_value::<T>(v).unwrap_err().to_string()
}

/// Reads a state back as one type, its error as text.
pub type Reader = fn(Value) -> Result<(), String>;

/// Reads `v` back as a `T` ([`Reader`]).
pub fn read<T: serde::de::DeserializeOwned>(v: Value) -> Result<(), String> {
    serde_json::from_value::<T>(v)
        .map(|_| ())
        .map_err(|e| e.to_string())
}

/// `v` with each `(pointer, value)` of `edits` set: a state edited by hand.
pub fn edited(v: &Value, edits: &[(&str, f64)]) -> Value {
    let mut e = v.clone();
    for &(at, value) in edits {
        *e.pointer_mut(at).unwrap() = json!(value);
    }
    e
}

/// Reading `v` with `edits` back as a `T` is refused, the error holding `message`.
pub fn refuses<T: serde::de::DeserializeOwned + core::fmt::Debug>(
    v: &Value,
    edits: &[(&str, f64)],
    message: &str,
) {
    let err = refused::<T>(edited(v, edits));
    assert!(err.contains(message), "{edits:?}: {err}");
}
