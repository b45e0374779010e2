//! Edits of a state written by `serde_json` for the adversarial read-back tests: every number
//! set to an extreme, every array emptied, shortened or lengthened, and the result read back and
//! run in a thread given 10 s.
#![allow(dead_code)]

use gyrocore::{MAX_READING, MAX_TIME};
use proptest::test_runner::TestCaseError;
use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::{json, Value};

/// Every number (and stored float word) of `v` by its JSON pointer, and every array as
/// `(pointer, None)`.
pub fn leaves(v: &Value, at: String, out: &mut Vec<(String, bool)>) {
    match v {
        Value::Number(_) | Value::Null => out.push((at, false)),
        Value::String(s) if ["inf", "-inf", "nan"].contains(&s.as_str()) => out.push((at, false)),
        Value::Array(a) => {
            out.push((at.clone(), true));
            for (i, x) in a.iter().enumerate() {
                leaves(x, format!("{at}/{i}"), out);
            }
        }
        Value::Object(o) => {
            for (k, x) in o {
                leaves(x, format!("{at}/{k}"), out);
            }
        }
        _ => {}
    }
}

pub fn extremes() -> Vec<Value> {
    vec![
        json!(1e308),
        json!(-1e308),
        json!(0.0),
        json!(-1),
        json!(5e-324),
        json!(u64::MAX),
        json!(i64::MIN),
        json!(MAX_TIME),
        json!(MAX_READING),
        json!(1e20),
        json!("inf"),
        json!("nan"),
    ]
}

/// `value` with leaf `pick` (modulo their number) edited by `how`: an extreme, or for an array
/// emptied, shortened or lengthened.
pub fn edited<T: Serialize>(value: &T, pick: usize, how: usize) -> (String, Value) {
    let mut v = serde_json::to_value(value).unwrap();
    let mut all = Vec::new();
    leaves(&v, String::new(), &mut all);
    let (at, array) = all[pick % all.len()].clone();
    let slot = v.pointer_mut(&at).unwrap();
    if array {
        let a = slot.as_array_mut().unwrap();
        match how % 3 {
            0 => a.clear(),
            1 => drop(a.pop()),
            _ => a.push(a.first().cloned().unwrap_or(json!(0))),
        }
        return (format!("{at}: {}", ["empty", "short", "long"][how % 3]), v);
    }
    let x = extremes()[how % extremes().len()].clone();
    *slot = x.clone();
    (format!("{at} = {x}"), v)
}

/// Reads `v` back as a `T` and runs it: no panic, and no hang (the run is given 10 s).
pub fn read_and_run<T: DeserializeOwned + Send + 'static>(
    what: String,
    v: Value,
    run: fn(T) -> Result<(), String>,
) -> Result<(), TestCaseError> {
    let (tx, rx) = std::sync::mpsc::channel();
    let name = what.clone();
    std::thread::spawn(move || {
        let result = match serde_json::from_value::<T>(v) {
            Ok(x) => run(x),
            Err(_) => Ok(()),
        };
        let _ = tx.send(result);
    });
    match rx.recv_timeout(std::time::Duration::from_secs(10)) {
        Ok(Ok(())) => Ok(()),
        Ok(Err(e)) => Err(TestCaseError::fail(format!("{name}: {e}"))),
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
            Err(TestCaseError::fail(format!("{what}: no answer in 10 s")))
        }
        Err(_) => Err(TestCaseError::fail(format!("{what}: panicked"))),
    }
}

/// Every field of `value` set to every extreme, and every array edited: refused, or `run`
/// succeeds.
pub fn every_edit<T: Serialize + DeserializeOwned + Send + 'static>(
    value: &T,
    run: fn(T) -> Result<(), String>,
) {
    let mut all = Vec::new();
    leaves(
        &serde_json::to_value(value).unwrap(),
        String::new(),
        &mut all,
    );
    for pick in 0..all.len() {
        for how in 0..extremes().len() {
            let (what, v) = edited(value, pick, how);
            read_and_run(what, v, run).unwrap();
        }
    }
}
