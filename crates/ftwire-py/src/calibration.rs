//! `ftwire.Calibration` (the learnt F/T calibration) and `ftwire.Mounting` (the sensor's
//! mounting): raw readings (force first, sensor frame) to configurations ã (torque first,
//! base clamp frame).

use std::path::PathBuf;

use ftwire_estimate::Calibration as Learnt;
use ftwire_estimate::ft::{Mounting as Transform, MountingSpec};
use nalgebra::{Vector3, Vector6};
use numpy::ndarray::{Array1, Array2};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::input::{self, Rows, value_error};

/// Rows out as an array of the input's shape: `(N, 6)` for a batch, `(6,)` for one row.
pub fn rows_out(py: Python<'_>, rows: Vec<Vector6<f64>>, batched: bool) -> PyResult<Py<PyAny>> {
    let n = rows.len();
    let flat: Vec<f64> = rows.iter().flat_map(|r| r.iter().copied()).collect();
    if batched {
        let array = Array2::from_shape_vec((n, 6), flat)
            .map_err(|e| value_error(format!("output: {e}")))?;
        Ok(PyArray2::from_owned_array(py, array).into_any().unbind())
    } else {
        Ok(PyArray1::from_owned_array(py, Array1::from(flat))
            .into_any()
            .unbind())
    }
}

/// The times of `rows`: one per row, finite.
pub(crate) fn times(time: Option<&Bound<'_, PyAny>>, rows: &Rows) -> PyResult<Option<Vec<f64>>> {
    let Some(time) = time.filter(|t| !t.is_none()) else {
        return Ok(None);
    };
    let (shape, values) = input::finite_array(time, "time")?;
    let n = rows.values.len() / 6;
    let fits = if rows.batched {
        shape == [n]
    } else {
        shape.is_empty() || shape == [1]
    };
    if !fits {
        return Err(value_error(format!(
            "time has shape {shape:?}; allowed is one time [s] per reading: ({n},)"
        )));
    }
    Ok(Some(values))
}

/// The learnt F/T calibration (paper §IV-A): a raw reading (force first [N, N·m], sensor
/// frame, not tared) to ã (torque first [N·m, N], base clamp frame). Immutable; from the
/// weights file of `ftwire experiment calibrate` or `ftwire calibrate --log`.
#[pyclass(module = "ftwire", frozen)]
pub struct Calibration {
    pub(crate) learnt: Learnt,
}

#[pymethods]
impl Calibration {
    /// Reads a calibration's weights file (calibration.json). Raises ValueError naming the
    /// file when it cannot be read or is not a calibration.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        let learnt = Learnt::load(&path)
            .map_err(|e| value_error(format!("path {}: {e}", path.display())))?;
        Ok(Self { learnt })
    }

    /// Whether the map has a drift term (then apply(raw, time) adds rate·(time − t₀)).
    #[getter]
    fn has_drift(&self) -> bool {
        self.learnt.drift().is_some()
    }

    /// ã for raw readings.
    ///
    /// - raw: (6,) or (N, 6), force first (f1, f2, f3 [N], τ1, τ2, τ3 [N·m]), sensor frame.
    /// - time: None, or one time [s] per reading on the recording's clock: the drift term at
    ///   that time (`apply_at`), as `ftwire identify --log` uses it.
    ///
    /// Returns ã of raw's shape, torque first, base clamp frame. Readings far outside the
    /// training data are extrapolated.
    #[pyo3(signature = (raw, time = None))]
    fn apply(
        &self,
        py: Python<'_>,
        raw: &Bound<'_, PyAny>,
        time: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let rows = input::rows(raw, "raw", 6, "raw readings, force first, sensor frame")?;
        let times = times(time, &rows)?;
        let raw = input::vectors6(&rows);
        let out = match times {
            Some(t) => raw
                .iter()
                .zip(t)
                .map(|(r, t)| self.learnt.apply_at(r, t))
                .collect(),
            None => raw.iter().map(|r| self.learnt.apply(r)).collect(),
        };
        rows_out(py, out, rows.batched)
    }
}

/// The F/T sensor's mounting: where the wire's base clamp sits in the sensor frame, and the
/// tool below the sensor whose weight it reads. Immutable.
///
/// Mounting(clamp_position_in_sensor=(0, 0, 0.08), clamp_rotation_in_sensor=None,
///          tool_mass=0.0, tool_centre_of_mass=(0, 0, 0))
///
/// - clamp_position_in_sensor: (3,) [m], sensor frame.
/// - clamp_rotation_in_sensor: (3,) rotation vector [rad], the clamp frame in the sensor
///   frame; None: −(2π/3)/√3·(1, 1, 1) (clamp x, y, z along sensor z, x, y).
/// - tool_mass: [kg] in [0, 1000].
/// - tool_centre_of_mass: (3,) [m], sensor frame.
#[pyclass(module = "ftwire", frozen)]
pub struct Mounting {
    pub(crate) spec: MountingSpec,
    pub(crate) transform: Transform,
}

impl Mounting {
    pub(crate) fn from_spec(spec: MountingSpec) -> PyResult<Self> {
        let transform = spec
            .mounting()
            .map_err(|e| value_error(format!("Mounting: {e}")))?;
        Ok(Self { spec, transform })
    }
}

#[pymethods]
impl Mounting {
    #[new]
    #[pyo3(signature = (clamp_position_in_sensor = None, clamp_rotation_in_sensor = None, tool_mass = 0.0, tool_centre_of_mass = None))]
    fn new(
        clamp_position_in_sensor: Option<&Bound<'_, PyAny>>,
        clamp_rotation_in_sensor: Option<&Bound<'_, PyAny>>,
        tool_mass: f64,
        tool_centre_of_mass: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let default = MountingSpec::default();
        let v = |value, name, what, default: [f64; 3]| -> PyResult<[f64; 3]> {
            Ok(input::vector3(value, name, what)?.map_or(default, Into::into))
        };
        let spec = MountingSpec {
            clamp_position_in_sensor: v(
                clamp_position_in_sensor,
                "clamp_position_in_sensor",
                "the clamp point [m], sensor frame",
                default.clamp_position_in_sensor,
            )?,
            clamp_rotation_in_sensor: v(
                clamp_rotation_in_sensor,
                "clamp_rotation_in_sensor",
                "a rotation vector [rad]",
                default.clamp_rotation_in_sensor,
            )?,
            tool_mass,
            tool_centre_of_mass: v(
                tool_centre_of_mass,
                "tool_centre_of_mass",
                "the tool's centre of mass [m], sensor frame",
                default.tool_centre_of_mass,
            )?,
        };
        if !(tool_mass.is_finite()
            && (0.0..=ftwire_estimate::ft::MAX_TOOL_MASS).contains(&tool_mass))
        {
            return Err(value_error(format!(
                "tool_mass = {tool_mass} is not allowed: a mass in [0, {}] kg",
                ftwire_estimate::ft::MAX_TOOL_MASS
            )));
        }
        Self::from_spec(spec)
    }

    /// A mounting file (TOML; keys as the constructor's, docs/config.md). Raises ValueError
    /// naming the file, line and key.
    #[staticmethod]
    fn from_toml(path: PathBuf) -> PyResult<Self> {
        let spec = ftwire_lab::setup::mounting::load(Some(&path))
            .map_err(|e| value_error(format!("path: {e}")))?;
        Self::from_spec(spec)
    }

    /// The clamp point [m], sensor frame.
    #[getter]
    fn clamp_position_in_sensor(&self) -> [f64; 3] {
        self.spec.clamp_position_in_sensor
    }

    /// The clamp frame's orientation in the sensor frame, rotation vector [rad].
    #[getter]
    fn clamp_rotation_in_sensor(&self) -> [f64; 3] {
        self.spec.clamp_rotation_in_sensor
    }

    /// The tool's mass [kg].
    #[getter]
    fn tool_mass(&self) -> f64 {
        self.spec.tool_mass
    }

    /// The tool's centre of mass [m], sensor frame.
    #[getter]
    fn tool_centre_of_mass(&self) -> [f64; 3] {
        self.spec.tool_centre_of_mass
    }

    /// ã through the mounting alone (uncalibrated): the tool's weight taken out, then the
    /// wrench moved from the sensor to the clamp and reordered torque first.
    ///
    /// - raw: (6,) or (N, 6), force first [N, N·m], sensor frame.
    /// - gravity: (3,) or (N, 3) [m/s²], sensor frame; needed when tool_mass > 0.
    ///
    /// Returns ã of raw's shape, torque first [N·m, N], base clamp frame.
    #[pyo3(signature = (raw, gravity = None))]
    fn to_configuration(
        &self,
        py: Python<'_>,
        raw: &Bound<'_, PyAny>,
        gravity: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let rows = input::rows(raw, "raw", 6, "raw readings, force first, sensor frame")?;
        let raw = input::vectors6(&rows);
        let gravity: Vec<Option<Vector3<f64>>> = match gravity.filter(|g| !g.is_none()) {
            None => vec![None; raw.len()],
            Some(g) => {
                let g = input::rows(g, "gravity", 3, "gravity [m/s²], sensor frame")?;
                let g: Vec<_> = g
                    .values
                    .chunks_exact(3)
                    .map(|v| Some(Vector3::from_column_slice(v)))
                    .collect();
                match g.len() {
                    1 => vec![g[0]; raw.len()],
                    n if n == raw.len() => g,
                    n => {
                        return Err(value_error(format!(
                            "gravity has {n} rows and raw {}: one, or one per reading",
                            raw.len()
                        )));
                    }
                }
            }
        };
        let out = raw
            .iter()
            .zip(&gravity)
            .enumerate()
            .map(|(i, (r, g))| {
                let r = self
                    .spec
                    .compensate(r, g.as_ref())
                    .map_err(|e| value_error(format!("gravity (reading {i}): {e}")))?;
                Ok(self.transform.to_configuration(&r))
            })
            .collect::<PyResult<Vec<_>>>()?;
        rows_out(py, out, rows.batched)
    }

    /// The sensor's reading (force first [N, N·m], sensor frame) of configurations a (torque
    /// first, base clamp frame): the inverse of to_configuration without a tool.
    fn to_sensor(&self, py: Python<'_>, a: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let rows = input::rows(a, "a", 6, "configurations, torque first, base clamp frame")?;
        let out = input::vectors6(&rows)
            .iter()
            .map(|a| self.transform.to_sensor(a))
            .collect();
        rows_out(py, out, rows.batched)
    }
}
