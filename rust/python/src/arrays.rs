//! NumPy arrays across the binding: contiguous views of the inputs, fresh outputs allocated by
//! numpy, the caller's own output arrays checked, and the views filled while their pages fault in.

use crate::prefault;
use numpy::{BorrowError, PyArray1, PyArrayMethods, PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A contiguous view of a float64 array (the Python layer converts other dtypes and strides).
pub(crate) fn slice<'a>(name: &str, a: &'a PyReadonlyArray1<'_, f64>) -> PyResult<&'a [f64]> {
    a.as_slice()
        .map_err(|_| PyValueError::new_err(format!("{name} must be a contiguous float64 array")))
}

/// A float64 numpy array owned by Python.
pub(crate) type Array<'py> = Bound<'py, PyArray1<f64>>;

/// A new zeroed float64 array of `n` samples, allocated by numpy: its allocator asks the kernel for
/// huge pages, where a fresh `Vec` handed over with `from_vec` costs a page fault every 4 KiB (at
/// 10^7 samples that was most of the time of a call).
pub(crate) fn zeros(py: Python<'_>, n: usize) -> Array<'_> {
    PyArray1::zeros(py, n, false)
}

/// Runs `f` on mutable views of `arrays` (fresh, contiguous arrays from [`zeros`]), their pages
/// faulted in on another core meanwhile (see [`prefault`]).
pub(crate) fn fill<const N: usize, R>(
    arrays: [&Array<'_>; N],
    f: impl FnOnce([&mut [f64]; N]) -> R,
) -> PyResult<R> {
    // Every array is given, so every view is there.
    fill_some(arrays.map(|a| Some(("output array", a))), |slices| {
        f(slices.map(Option::unwrap_or_default))
    })
}

/// [`fill`] for outputs that may not be asked for (`None`), each named for its errors: a
/// caller's array (see [`output`]) may be read-only, or overlap an input still borrowed for
/// reading or another output.
pub(crate) fn fill_some<const N: usize, R>(
    arrays: [Option<(&str, &Array<'_>)>; N],
    f: impl FnOnce([Option<&mut [f64]>; N]) -> R,
) -> PyResult<R> {
    let mut guards = Vec::with_capacity(N);
    for (name, a) in arrays.into_iter().flatten() {
        guards.push(a.try_readwrite().map_err(|e| {
            PyValueError::new_err(match e {
                BorrowError::NotWriteable => format!("{name} is read-only: give a writeable array"),
                _ => format!(
                    "{name} overlaps an input or another output: give it an array of its own"
                ),
            })
        })?);
    }
    let mut views = Vec::with_capacity(N);
    for g in &mut guards {
        views.push(
            g.as_slice_mut()
                .map_err(|_| PyValueError::new_err("output array is not contiguous"))?,
        );
    }
    // The views back in the places of the arrays they view, in order.
    let mut views = views.into_iter();
    let slices = arrays.map(|a| a.and_then(|_| views.next()));
    let pages = prefault::Pages::of(slices.iter().flatten());
    Ok(pages.while_faulting_in(|| f(slices)))
}

/// The array output `name` goes into: the caller's `given` array (one element per sample,
/// C-contiguous; whether it is writeable and apart from the inputs [`fill_some`] checks), or a
/// fresh one if the output is `wanted`. An array given for an output not asked for is an error.
pub(crate) fn output<'py>(
    py: Python<'py>,
    name: &str,
    given: Option<Array<'py>>,
    n: usize,
    wanted: bool,
) -> PyResult<Option<Array<'py>>> {
    let Some(a) = given else {
        return Ok(wanted.then(|| zeros(py, n)));
    };
    if !wanted {
        return Err(PyValueError::new_err(format!(
            "{name} is given, but that output is not asked for: ask for it in outputs, or give None"
        )));
    }
    if a.len() != n {
        return Err(PyValueError::new_err(format!(
            "{name} has {} elements but t has {n} samples: give one element per sample",
            a.len()
        )));
    }
    if !a.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "{name} is not C-contiguous: give a contiguous float64 array, e.g. numpy.empty(len(t))"
        )));
    }
    Ok(Some(a))
}
