//! `ftwire.ShapeEstimator`: the wire's shape from F/T (paper §IV-C), with the confidence flag
//! of each sample: the rig layer's one path ([`ftwire_rig`]), the same `Measurement` and
//! `Stream` as `ftwire shape --log` and `ftwire ros2 estimate`.

use ftwire_rig::shape::{DEFAULT_JUMP_THRESHOLD, DEFAULT_POINTS};
use ftwire_rig::{
    Measurement, MeasurementParams, RawMap, Reading, Solved, Stream, StreamParams, WireBody,
    WireModelChoice,
};
use nalgebra::Vector3;
use numpy::PyArray3;
use numpy::ndarray::Array3;
use pyo3::prelude::*;
use rayon::prelude::*;

use crate::calibration::{Calibration, Mounting};
use crate::input::{self, value_error};
use crate::wire::Wire;

/// The wire's shape from each reading or configuration ã (paper §IV-C): the model's
/// centreline Φ(ã) (the weight-free Kirchhoff rod, or with gravity the loaded one), flagged
/// "confident", "not_stable" (ã ∉ A_stable), "jump" (ã changed from the previous sample by
/// more than jump_threshold in normalised units: a possible contact) or "no_shape". Keeps the
/// last sample for the jump test, across calls. The path of `ftwire shape --log`: the same
/// reading gives the same shape to the bit.
///
/// ShapeEstimator(wire, calibration=None, mounting=None, points=100, jump_threshold=2.0,
///                gravity=None)
///
/// - wire: the Wire.
/// - calibration: a Calibration: estimate() then takes raw readings (force first, sensor
///   frame) through it.
/// - mounting: a Mounting: with a calibration, the tool's weight it names is taken out of each
///   raw reading first (estimate()'s tool_gravity); without one, raw readings go through the
///   mounting alone. With neither, estimate() takes ã (torque first [N·m, N], base clamp
///   frame).
/// - points: points of each shape, 2 to 10 000.
/// - jump_threshold: finite > 0, normalised units (torque in c2/L, force in c2/L²).
/// - gravity: (3,) gravity in the base clamp frame [m/s²], norm in (0, 100]: the loaded model,
///   with the wire's weight and rest curvature (`--gravity-in-clamp`); None: weight-free.
#[pyclass(module = "ftwire")]
pub struct ShapeEstimator {
    measurement: Measurement,
    stream: Stream,
}

#[pymethods]
impl ShapeEstimator {
    #[new]
    #[pyo3(signature = (wire, calibration = None, mounting = None, points = DEFAULT_POINTS, jump_threshold = DEFAULT_JUMP_THRESHOLD, gravity = None))]
    fn new(
        wire: &Wire,
        calibration: Option<PyRef<'_, Calibration>>,
        mounting: Option<PyRef<'_, Mounting>>,
        points: usize,
        jump_threshold: f64,
        gravity: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let choice = match gravity.filter(|g| !g.is_none()) {
            None => WireModelChoice::Weightless,
            Some(g) => {
                let g = input::rows(g, "gravity", 3, "gravity [m/s²], base clamp frame")?;
                if g.batched {
                    return Err(value_error(
                        "gravity has a batch axis: one (3,) vector, base clamp frame",
                    ));
                }
                WireModelChoice::loaded([g.values[0], g.values[1], g.values[2]])
                    .map_err(|e| value_error(format!("gravity: {e}")))?
            }
        };
        let body = WireBody {
            params: wire.params,
            density: wire.spec.density,
            natural_curvature: Vector3::from(wire.spec.natural_curvature),
        };
        let model = choice
            .model(&body)
            .map_err(|e| value_error(format!("gravity: {e}")))?;
        let map = RawMap::new(
            calibration.map(|c| c.learnt.clone()),
            mounting.map(|m| m.spec.clone()),
        )
        .map_err(|e| value_error(format!("mounting: {e}")))?;
        let params = MeasurementParams {
            points,
            jump_threshold,
            model_error: None,
        };
        let measurement = Measurement::new(map, model, params).map_err(|e| {
            let name = if e.to_string().starts_with("points") {
                "points"
            } else {
                "jump_threshold"
            };
            value_error(format!("{name}: {e}"))
        })?;
        let stream = Stream::new(&measurement, StreamParams::default())
            .map_err(|e| value_error(format!("ShapeEstimator: {e}")))?;
        Ok(Self {
            measurement,
            stream,
        })
    }

    /// Forgets the last sample: the next one is not tested for a jump.
    fn reset(&mut self) {
        self.stream.reset_jump();
    }

    /// The shapes of samples, solved in parallel (GIL released), flagged in order.
    ///
    /// - samples: (6,) or (N, 6): raw readings (force first, sensor frame) with a calibration
    ///   or mounting, else ã (torque first [N·m, N], base clamp frame).
    /// - time: with a calibration, one time [s] per sample for its drift term; None: the
    ///   calibration without its drift.
    /// - tool_gravity: with a mounting that has a tool, gravity in the sensor frame [m/s²],
    ///   (3,) or one row per sample, to take the tool's weight out of each raw reading.
    ///
    /// Returns a dict: "a" (N, 6) ã; "shape" (N, points, 3) [m], base clamp frame (NaN where
    /// the model has no shape); "flag" list of "confident", "not_stable", "jump" or
    /// "no_shape"; "error" list of None or why the model has no shape. The leading axis is
    /// dropped for a (6,) input.
    #[pyo3(signature = (samples, time = None, tool_gravity = None))]
    fn estimate<'py>(
        &mut self,
        py: Python<'py>,
        samples: &Bound<'py, PyAny>,
        time: Option<&Bound<'py, PyAny>>,
        tool_gravity: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let rows = input::rows(samples, "samples", 6, "raw readings or configurations ã")?;
        let batched = rows.batched;
        let points = self.measurement.params().points;
        input::check_output(
            &format!(
                "samples ({} rows) and points = {points}",
                rows.values.len() / 6
            ),
            (rows.values.len() as u128 / 6) * (3 * points as u128 + 6),
        )?;
        let values = input::vectors6(&rows);
        let n = values.len();
        let times = crate::calibration::times(time, &rows)?;
        let gravity = tool_gravity_rows(tool_gravity, n)?;
        let map = self.measurement.map();
        // Without a time, the calibration at its own reference time: no drift term.
        let no_time = map
            .calibration()
            .and_then(|c| c.drift())
            .map_or(0.0, |d| d.reference_time);
        let mut a = Vec::with_capacity(n);
        for (i, v) in values.iter().enumerate() {
            let t = times.as_ref().map_or(no_time, |t| t[i]);
            let reading = if map.maps_raw() {
                Reading::raw(t, *v).with_gravity(gravity[i])
            } else {
                Reading::configuration(t, *v)
            };
            let mapped = self
                .stream
                .push(&self.measurement, &reading)
                .ok_or_else(|| value_error("samples: the stream holds a sample back"))?
                .map_err(|e| value_error(format!("samples[{i}]: {e}")))?;
            a.push(mapped.1);
        }
        let measurement = &self.measurement;
        let solved: Vec<Result<Solved, String>> =
            py.detach(|| a.par_iter().map(|a| measurement.solve(a, None)).collect());
        let mut shape = vec![f64::NAN; n * points * 3];
        let mut flags = Vec::with_capacity(n);
        let mut errors = Vec::with_capacity(n);
        for (i, (a, s)) in a.iter().zip(&solved).enumerate() {
            let flag = self.stream.flag(a, s);
            match s {
                Ok(s) => {
                    for (k, p) in s.shape.positions.iter().enumerate() {
                        let at = 3 * (i * points + k);
                        shape[at..at + 3].copy_from_slice(&[p.x, p.y, p.z]);
                    }
                    errors.push(None);
                }
                Err(e) => errors.push(Some(e.clone())),
            }
            flags.push(flag.name());
        }
        let dict = pyo3::types::PyDict::new(py);
        let shape = Array3::from_shape_vec((n, points, 3), shape)
            .map_err(|e| value_error(format!("shape: {e}")))?;
        let shape = PyArray3::from_owned_array(py, shape);
        let a_out = crate::calibration::rows_out(py, a, true)?;
        if batched {
            dict.set_item("a", a_out)?;
            dict.set_item("shape", shape)?;
            dict.set_item("flag", flags)?;
            dict.set_item("error", errors)?;
        } else {
            dict.set_item("a", a_out.bind(py).get_item(0)?)?;
            dict.set_item("shape", shape.get_item(0)?)?;
            dict.set_item("flag", flags[0])?;
            dict.set_item("error", errors[0].clone())?;
        }
        Ok(dict)
    }
}

/// `tool_gravity` as one vector per sample (`None` for each without it).
fn tool_gravity_rows(
    tool_gravity: Option<&Bound<'_, PyAny>>,
    n: usize,
) -> PyResult<Vec<Option<Vector3<f64>>>> {
    let Some(g) = tool_gravity.filter(|g| !g.is_none()) else {
        return Ok(vec![None; n]);
    };
    let g = input::rows(g, "tool_gravity", 3, "gravity [m/s²], sensor frame")?;
    let g: Vec<Option<Vector3<f64>>> = g
        .values
        .chunks_exact(3)
        .map(|v| Some(Vector3::from_column_slice(v)))
        .collect();
    match g.len() {
        1 => Ok(vec![g[0]; n]),
        k if k == n => Ok(g),
        k => Err(value_error(format!(
            "tool_gravity has {k} rows and samples {n}: one, or one per sample"
        ))),
    }
}
