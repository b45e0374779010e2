//! Heading tables as CSV text, formatted with the GIL released (pyarrow's float-to-text cast
//! formats about 4 million values per second; Żmij several times more).

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::interrupt::{detach_watched, pieces, Stop};

/// Appends `x` in the shortest form that reads back to the same `f64` (Żmij, the formatter of
/// serde_json; exponent notation for very small and very large magnitudes); NaN and infinities as
/// `NaN`, `inf`, `-inf`.
fn push_float(out: &mut String, buffer: &mut zmij::Buffer, x: f64) {
    out.push_str(buffer.format(x));
}

/// Rows of CSV text (`a,b,c\n`), one per index of the equally long `columns`, until `stop` (the
/// text is then thrown away).
fn csv_rows(columns: &[&[f64]], stop: &Stop) -> String {
    let n = columns.first().map_or(0, |c| c.len());
    let mut out = String::with_capacity(n * columns.len() * 20);
    let mut buffer = zmij::Buffer::new();
    let _ = pieces(n, stop, |range| {
        for i in range {
            for (k, column) in columns.iter().enumerate() {
                if k > 0 {
                    out.push(',');
                }
                push_float(&mut out, &mut buffer, column[i]);
            }
            out.push('\n');
        }
        Ok::<(), ()>(())
    });
    out
}

/// CSV rows of float64 columns (no header), as a uint8 array of UTF-8 text (moved into numpy, not
/// copied; a file's `write` takes it as it is); every value reads back bit-identically.
#[pyfunction]
fn format_csv_rows<'py>(
    py: Python<'py>,
    columns: Vec<PyReadonlyArray1<'py, f64>>,
) -> PyResult<Bound<'py, PyArray1<u8>>> {
    let slices = columns
        .iter()
        .enumerate()
        .map(|(k, a)| {
            a.as_slice().map_err(|_| {
                PyValueError::new_err(format!("column {k} must be a contiguous float64 array"))
            })
        })
        .collect::<PyResult<Vec<&[f64]>>>()?;
    if let Some(first) = slices.first() {
        if let Some((k, c)) = slices
            .iter()
            .enumerate()
            .find(|(_, c)| c.len() != first.len())
        {
            return Err(PyValueError::new_err(format!(
                "column {k} has {} values but column 0 has {}",
                c.len(),
                first.len()
            )));
        }
    }
    let rows = slices.first().map_or(0, |c| c.len());
    let text = detach_watched(py, rows, |stop| csv_rows(&slices, stop))?;
    Ok(PyArray1::from_vec(py, text.into_bytes()))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(format_csv_rows, m)?)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_are_short_and_read_back_exactly() {
        let values = [
            1651541251.8307054,
            0.1,
            -0.0,
            1e-300,
            f64::MAX,
            5e-324,
            1.0 / 3.0,
            123456789.12345679,
            1e16,
            9.999e-6,
        ];
        let text = csv_rows(&[&values], &Stop::default());
        let back: Vec<f64> = text.lines().map(|l| l.parse().unwrap()).collect();
        for (a, b) in values.iter().zip(&back) {
            assert_eq!(a.to_bits(), b.to_bits(), "{a} -> {b}");
        }
        assert!(
            text.starts_with("1651541251.8307054\n0.1\n-0.0\n1e-300\n"),
            "{text}"
        );
    }

    #[test]
    fn non_finite_values_are_spelled_for_csv_readers() {
        assert_eq!(
            csv_rows(
                &[&[f64::NAN, 1.0], &[f64::INFINITY, -f64::INFINITY]],
                &Stop::default()
            ),
            "NaN,inf\n1.0,-inf\n"
        );
    }
}
