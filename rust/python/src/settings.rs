//! Flat dicts of SI numbers onto the core's configuration structs. One table per struct names
//! each key, says what it is with its unit, and points at its field: the keys accepted, the names
//! listed to Python and the values read back are one list.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One key of a configuration `C`: its name, what it is with its unit, and its field.
pub(crate) type Field<C> = (&'static str, &'static str, fn(&mut C) -> &mut f64);

/// Sets every key of `dict` on `config` (`what` names such a key in errors: "gyro parameter").
pub(crate) fn set_all<C>(
    config: &mut C,
    dict: &Bound<'_, PyDict>,
    table: &[Field<C>],
    what: &str,
) -> PyResult<()> {
    for (key, value) in dict.iter() {
        let name: String = key.extract()?;
        let Some((_, _, field)) = table.iter().find(|(n, ..)| *n == name) else {
            let valid: Vec<&str> = table.iter().map(|(n, ..)| *n).collect();
            return Err(PyValueError::new_err(format!(
                "unknown {what} '{name}'; valid names: {}",
                valid.join(", ")
            )));
        };
        *field(config) = value
            .extract()
            .map_err(|_| PyValueError::new_err(format!("{what} '{name}' must be a number")))?;
    }
    Ok(())
}

/// Every key with what it is and its unit.
pub(crate) fn names<C>(table: &[Field<C>]) -> Vec<(&'static str, &'static str)> {
    table.iter().map(|(n, d, _)| (*n, *d)).collect()
}

/// Every key with its value in `config`.
pub(crate) fn values<C: Copy>(config: &C, table: &[Field<C>]) -> Vec<(&'static str, f64)> {
    let mut c = *config;
    table
        .iter()
        .map(|(n, _, field)| (*n, *field(&mut c)))
        .collect()
}
