//! `ftwire.read_log(path)`: a rig's JSON Lines log (format: `ftwire_estimate::log`) as a dict
//! of NumPy arrays, one row per record.

use std::path::PathBuf;

use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{PyArray1, PyArray2, PyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::input::value_error;

/// Reads the log at `path` (JSON Lines: time, raw or a, b, markers, gravity on each record;
/// docs in `ftwire_estimate::log`) into a dict of float64 arrays with one row per record:
///
/// - "line" (N,) int64: the record's line in the file, from 1;
/// - "time" (N,) [s]: the rig's clock;
/// - "a" (N, 6): ã, torque first [N·m, N], base clamp frame; NaN on records with `raw`;
/// - "raw" (N, 6): raw F/T reading, force first [N, N·m], sensor frame; NaN on records with `a`;
/// - "b" (N, 6): the second gripper's clamp pose in the base clamp frame, position [m] then
///   rotation vector [rad] (axis × angle), as the log writes it; NaN where missing;
/// - "markers" (N, M, 3) [m], base clamp frame, NaN for a missing marker (only if a record has
///   markers; M is the most markers on a record);
/// - "gravity" (N, 3) [m/s²], sensor frame; NaN where missing.
///
/// Raises ValueError naming the file and the line of a bad record, or an empty log.
#[pyfunction]
pub fn read_log(py: Python<'_>, path: PathBuf) -> PyResult<Py<PyDict>> {
    let lines = ftwire_lab::log::read_log(&path).map_err(|e| value_error(format!("path: {e}")))?;
    let n = lines.len();
    let nan = f64::NAN;
    let mut line = Vec::with_capacity(n);
    let mut time = Vec::with_capacity(n);
    let mut a = vec![nan; n * 6];
    let mut raw = vec![nan; n * 6];
    let mut b = vec![nan; n * 6];
    let mut gravity = vec![nan; n * 3];
    let markers_count = lines
        .iter()
        .filter_map(|l| l.record.markers.as_ref().map(Vec::len))
        .max();
    let m = markers_count.unwrap_or(0);
    // Every record gets the most markers any record has: one record with many markers would
    // multiply the log's size.
    crate::input::check_output(
        &format!("{n} records of up to {m} markers"),
        (n as u128) * (m as u128) * 3,
    )?;
    let mut markers = vec![nan; n * m * 3];
    for (i, l) in lines.iter().enumerate() {
        let r = &l.record;
        line.push(i64::try_from(l.line).unwrap_or(i64::MAX));
        time.push(r.time);
        if let Some(v) = r.a {
            a[6 * i..6 * i + 6].copy_from_slice(&v);
        }
        if let Some(v) = r.raw {
            raw[6 * i..6 * i + 6].copy_from_slice(&v);
        }
        if let Some(pose) = r.b {
            b[6 * i..6 * i + 3].copy_from_slice(&pose.position);
            b[6 * i + 3..6 * i + 6].copy_from_slice(&pose.rotation);
        }
        if let Some(g) = r.gravity {
            gravity[3 * i..3 * i + 3].copy_from_slice(&g);
        }
        for (k, p) in r.markers.iter().flatten().enumerate() {
            if let Some(p) = p {
                let at = 3 * (i * m + k);
                markers[at..at + 3].copy_from_slice(p);
            }
        }
    }
    let dict = PyDict::new(py);
    let shape_error = |e: numpy::ndarray::ShapeError| value_error(format!("log arrays: {e}"));
    dict.set_item("line", PyArray1::from_owned_array(py, Array1::from(line)))?;
    dict.set_item("time", PyArray1::from_owned_array(py, Array1::from(time)))?;
    let two = |v: Vec<f64>, w: usize| Array2::from_shape_vec((n, w), v).map_err(shape_error);
    dict.set_item("a", PyArray2::from_owned_array(py, two(a, 6)?))?;
    dict.set_item("raw", PyArray2::from_owned_array(py, two(raw, 6)?))?;
    dict.set_item("b", PyArray2::from_owned_array(py, two(b, 6)?))?;
    dict.set_item("gravity", PyArray2::from_owned_array(py, two(gravity, 3)?))?;
    if markers_count.is_some() {
        let markers = Array3::from_shape_vec((n, m, 3), markers).map_err(shape_error)?;
        dict.set_item("markers", PyArray3::from_owned_array(py, markers))?;
    }
    Ok(dict.unbind())
}
