//! Python arguments to Rust values: any array-like of numbers is read as `float64`, its shape
//! and values checked, and every refusal is a `ValueError` that names the argument, the index
//! and what is allowed.

use nalgebra::{Vector3, Vector6};
use numpy::{AllowTypeChange, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;

/// A `ValueError` with `message`.
pub fn value_error(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

/// The argument `name` as a C-ordered `float64` array: its shape and its values in row-major
/// order.
///
/// # Errors
/// `ValueError` naming `name` for an object NumPy cannot read as an array of numbers, and for
/// a value that is not finite (its index is named).
pub fn finite_array(value: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<usize>, Vec<f64>)> {
    let array: PyArrayLikeDyn<'_, f64, AllowTypeChange> = value.extract().map_err(|e| {
        value_error(format!(
            "{name}: cannot be read as an array of numbers ({e})"
        ))
    })?;
    let shape = array.shape().to_vec();
    // Row-major order whatever the layout: `as_slice` would also take a Fortran-ordered
    // array's memory as it lies, so it is used only for a C-ordered one.
    let values: Vec<f64> = match array.as_slice() {
        Ok(slice) if array.is_c_contiguous() => slice.to_vec(),
        _ => array.as_array().iter().copied().collect(),
    };
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(value_error(format!(
            "{name}{} = {} is not allowed: every value must be a finite number",
            index_text(&shape, i),
            values[i]
        )));
    }
    Ok((shape, values))
}

/// `[i, j, ...]` of flat index `flat` in an array of `shape` (row-major).
fn index_text(shape: &[usize], mut flat: usize) -> String {
    let mut index = vec![0; shape.len()];
    for (k, &n) in shape.iter().enumerate().rev() {
        if n > 0 {
            index[k] = flat % n;
            flat /= n;
        }
    }
    let parts: Vec<String> = index.iter().map(ToString::to_string).collect();
    format!("[{}]", parts.join(", "))
}

/// Rows of `width` numbers: an argument of shape `(width,)` (one row, `batched` false) or
/// `(N, width)` with `N ≥ 1` (`batched` true).
pub struct Rows {
    /// The rows' values, row-major.
    pub values: Vec<f64>,
    /// Whether the argument had a leading batch axis.
    pub batched: bool,
}

/// The argument `name` as rows of `width` finite numbers ([`Rows`]); `what` says what a row
/// is, for the error message.
///
/// # Errors
/// `ValueError` naming `name`: not an array of numbers, a shape other than `(width,)` or
/// `(N, width)` with `N ≥ 1`, or a value that is not finite.
pub fn rows(value: &Bound<'_, PyAny>, name: &str, width: usize, what: &str) -> PyResult<Rows> {
    let (shape, values) = finite_array(value, name)?;
    let batched = match shape.as_slice() {
        [n] if *n == width => false,
        [n, w] if *w == width && *n > 0 => true,
        _ => {
            return Err(value_error(format!(
                "{name} has shape {shape:?}; allowed are ({width},) and (N, {width}) with N ≥ 1: \
                 {what}"
            )));
        }
    };
    Ok(Rows { values, batched })
}

/// The rows of [`rows`] as 6-vectors.
pub fn vectors6(rows: &Rows) -> Vec<Vector6<f64>> {
    rows.values
        .chunks_exact(6)
        .map(Vector6::from_column_slice)
        .collect()
}

/// The argument `name` as exactly `N` finite numbers.
///
/// # Errors
/// `ValueError` naming `name` for another shape or a value that is not finite.
pub fn fixed<const N: usize>(
    value: &Bound<'_, PyAny>,
    name: &str,
    what: &str,
) -> PyResult<[f64; N]> {
    let (shape, values) = finite_array(value, name)?;
    values.as_slice().try_into().map_err(|_| {
        value_error(format!(
            "{name} has shape {shape:?}; allowed is ({N},): {what}"
        ))
    })
}

/// The optional argument `name` as a 3-vector.
///
/// # Errors
/// As [`fixed`].
pub fn vector3(
    value: Option<&Bound<'_, PyAny>>,
    name: &str,
    what: &str,
) -> PyResult<Option<Vector3<f64>>> {
    value
        .filter(|v| !v.is_none())
        .map(|v| fixed::<3>(v, name, what).map(Vector3::from))
        .transpose()
}

/// `value` if it is finite and greater than zero.
///
/// # Errors
/// `ValueError` naming `name`, the value and the unit.
pub fn positive(value: f64, name: &str, unit: &str) -> PyResult<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(value_error(format!(
            "{name} = {value} is not allowed: a finite number > 0 [{unit}]"
        )))
    }
}

/// Largest output one call allocates \[bytes\]: 4 GiB. A bigger answer is refused before any
/// work, so that a too-large request is a `ValueError`, never an aborted interpreter.
pub const MAX_OUTPUT_BYTES: u128 = 4 << 30;

/// Checks that an output of `values` float64 numbers fits in [`MAX_OUTPUT_BYTES`], and that
/// the process can allocate it now: the memory is reserved once and given back, so that under a
/// memory limit (`ulimit -v`, a container's) the call raises `MemoryError` before any work
/// instead of aborting the interpreter halfway.
///
/// # Errors
/// `ValueError` naming `what` (the arguments that set the size) and the bytes asked for;
/// `MemoryError` with the same when they cannot be allocated.
pub fn check_output(what: &str, values: u128) -> PyResult<()> {
    let bytes = values.saturating_mul(8);
    if bytes > MAX_OUTPUT_BYTES {
        return Err(value_error(format!(
            "{what} ask for {bytes} bytes of output, more than the {MAX_OUTPUT_BYTES} allowed: \
             split the batch or take fewer points"
        )));
    }
    let mut probe: Vec<f64> = Vec::new();
    let count = usize::try_from(values).unwrap_or(usize::MAX);
    if probe.try_reserve_exact(count).is_err() {
        return Err(PyMemoryError::new_err(format!(
            "{what} ask for {bytes} bytes of output, which this process cannot allocate now: \
             split the batch or take fewer points"
        )));
    }
    Ok(())
}
