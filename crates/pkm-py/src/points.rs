//! N × k arrays of float64 from any Python value: a float64 array of any strides is read in
//! place; another real dtype, a list or a nested sequence is converted (once the shape is
//! checked, so a huge input is refused before anything is allocated); anything else raises
//! `pkm.InvalidInput`.

use crate::errors;
use numpy::{
    PyArray1, PyArrayDescrMethods, PyArrayMethods, PyReadonlyArray2, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;

/// Largest number of rows a kernel takes in one call (10⁷: a 6 × 3 Jacobian per row is then
/// 1.4 GB of output); larger inputs are refused before any output is allocated.
pub(crate) const MAX_POINTS: usize = 10_000_000;

/// `value` as a read-only N × `columns` float64 array, checked: 2-D, `columns` wide, at most
/// [`MAX_POINTS`] rows.
///
/// # Errors
/// `pkm.InvalidInput` naming `name` for anything else.
pub(crate) fn rows<'py>(
    value: &Bound<'py, PyAny>,
    name: &str,
    columns: usize,
) -> PyResult<PyReadonlyArray2<'py, f64>> {
    let py = value.py();
    let array = match value.cast::<PyUntypedArray>() {
        Ok(array) => array.clone(),
        Err(_) => as_array(value, name)?,
    };
    check_shape(py, array.shape(), name, columns)?;
    let float64 = match array.cast::<numpy::PyArray2<f64>>() {
        Ok(a) => a.clone(),
        Err(_) => to_float64(&array, name)?,
    };
    float64
        .try_readonly()
        .map_err(|e| errors::invalid(py, format!("{name}: {e}")))
}

/// The number of columns of `value` read as a 2-D array (`None` for another shape), so that
/// a caller that takes several widths can pass it to [`rows`].
///
/// # Errors
/// `pkm.InvalidInput` naming `name` for a value that is not an array of numbers.
pub(crate) fn columns_of(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Option<usize>> {
    let array = match value.cast::<PyUntypedArray>() {
        Ok(array) => array.clone(),
        Err(_) => as_array(value, name)?,
    };
    Ok(match array.shape() {
        [_, columns] => Some(*columns),
        _ => None,
    })
}

/// `numpy.asarray(value)` for a value that is not an array yet (a list of rows).
fn as_array<'py>(value: &Bound<'py, PyAny>, name: &str) -> PyResult<Bound<'py, PyUntypedArray>> {
    let py = value.py();
    let numpy = py.import("numpy")?;
    let array = numpy
        .call_method1("asarray", (value,))
        .map_err(|e| errors::invalid(py, format!("{name}: not an array of numbers ({e})")))?;
    array
        .cast_into::<PyUntypedArray>()
        .map_err(|_| errors::invalid(py, format!("{name}: not an array of numbers")))
}

fn check_shape(py: Python<'_>, shape: &[usize], name: &str, columns: usize) -> PyResult<()> {
    if shape.len() != 2 || shape[1] != columns {
        return Err(errors::invalid(
            py,
            format!("{name}: expected an N × {columns} array, got shape {shape:?}"),
        ));
    }
    if shape[0] > MAX_POINTS {
        return Err(errors::invalid(
            py,
            format!(
                "{name}: {} rows, at most {MAX_POINTS} in one call (split the array)",
                shape[0]
            ),
        ));
    }
    Ok(())
}

/// A real-valued array of another dtype (integers, float32, big-endian float64, booleans)
/// converted to float64; complex, object and text arrays are refused.
fn to_float64<'py>(
    array: &Bound<'py, PyUntypedArray>,
    name: &str,
) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
    let py = array.py();
    let dtype = array.dtype();
    let kind = dtype.kind();
    if !matches!(kind, b'f' | b'i' | b'u' | b'b') {
        return Err(errors::invalid(
            py,
            format!("{name}: expected real numbers, got dtype {dtype}"),
        ));
    }
    let converted = array.call_method1("astype", ("float64",))?;
    converted.cast_into::<numpy::PyArray2<f64>>().map_err(|_| {
        errors::invalid(
            py,
            format!("{name}: cannot convert dtype {dtype} to float64"),
        )
    })
}

/// A NumPy array of shape `shape` holding `values` (row-major), without a copy.
pub(crate) fn array<'py>(
    py: Python<'py>,
    values: Vec<f64>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, values).reshape(shape)?.into_any())
}

/// A boolean NumPy array holding `mask`.
pub(crate) fn mask<'py>(py: Python<'py>, mask: Vec<bool>) -> Bound<'py, PyAny> {
    PyArray1::from_vec(py, mask).into_any()
}
