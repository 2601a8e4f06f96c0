//! `ftwire.ShapeEstimator`: the wire's shape from F/T (paper §IV-C), with the confidence flag
//! of each sample, as `ftwire shape --log` gives it.

use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::WireModel;
use ftwire_estimate::shape::{
    Confidence, EstimatorParams, MIN_ESTIMATE_NODES, ShapeEstimator as Estimator,
};
use nalgebra::Vector6;
use numpy::PyArray3;
use numpy::ndarray::Array3;
use pyo3::prelude::*;
use rayon::prelude::*;

use crate::calibration::{Calibration, Mounting};
use crate::input::{self, value_error};
use crate::wire::Wire;

/// The wire's shape from each calibrated configuration ã (paper §IV-C): the weightless
/// Kirchhoff model's centreline Φ(ã), flagged "confident", "not_stable" (ã ∉ A_stable) or
/// "jump" (ã changed from the previous sample by more than jump_threshold in normalised
/// units: a possible contact). Keeps the last sample for the jump test, across calls.
///
/// ShapeEstimator(wire, calibration=None, mounting=None, points=64, jump_threshold=2.0)
///
/// - wire: the Wire.
/// - calibration: a Calibration: estimate() then takes raw readings (force first, sensor
///   frame) through it.
/// - mounting: a Mounting (without a calibration): raw readings through the mounting alone.
///   With neither, estimate() takes ã (torque first [N·m, N], base clamp frame).
/// - points: shape nodes, 50 to 1 000 000.
/// - jump_threshold: finite > 0, normalised units (torque in c2/L, force in c2/L²).
#[pyclass(module = "ftwire")]
pub struct ShapeEstimator {
    estimator: Estimator<KirchhoffModel>,
    calibration: Option<Py<Calibration>>,
    mounting: Option<Py<Mounting>>,
}

#[pymethods]
impl ShapeEstimator {
    #[new]
    #[pyo3(signature = (wire, calibration = None, mounting = None, points = 64, jump_threshold = 2.0))]
    fn new(
        wire: &Wire,
        calibration: Option<Py<Calibration>>,
        mounting: Option<Py<Mounting>>,
        points: usize,
        jump_threshold: f64,
    ) -> PyResult<Self> {
        if !(MIN_ESTIMATE_NODES..=ftwire_rod::rod::MAX_NODES).contains(&points) {
            return Err(value_error(format!(
                "points = {points} is not allowed: {MIN_ESTIMATE_NODES} to {} shape nodes",
                ftwire_rod::rod::MAX_NODES
            )));
        }
        if !(jump_threshold.is_finite() && jump_threshold > 0.0) {
            return Err(value_error(format!(
                "jump_threshold = {jump_threshold} is not allowed: finite and > 0 (normalised units)"
            )));
        }
        let estimator = Estimator::new(KirchhoffModel::new(wire.params))
            .with_config(EstimatorParams {
                nodes: points,
                jump_threshold,
            })
            .map_err(|e| value_error(format!("ShapeEstimator: {e}")))?;
        Ok(Self {
            estimator,
            calibration,
            mounting,
        })
    }

    /// Forgets the last sample: the next one is not tested for a jump.
    fn reset(&mut self) {
        self.estimator.reset();
    }

    /// The shapes of samples, solved in parallel (GIL released), flagged in order.
    ///
    /// - samples: (6,) or (N, 6): raw readings (force first, sensor frame) with a calibration
    ///   or mounting, else ã (torque first [N·m, N], base clamp frame).
    /// - time: with a calibration, one time [s] per sample for its drift term; else None.
    ///
    /// Returns a dict: "a" (N, 6) ã; "shape" (N, points, 3) [m], base clamp frame (NaN where
    /// the model has no shape); "flag" list of "confident", "not_stable", "jump" or
    /// "no_shape"; "error" list of None or why the model has no shape. The leading axis is
    /// dropped for a (6,) input.
    #[pyo3(signature = (samples, time = None))]
    fn estimate<'py>(
        &mut self,
        py: Python<'py>,
        samples: &Bound<'py, PyAny>,
        time: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let rows = input::rows(samples, "samples", 6, "raw readings or configurations ã")?;
        let batched = rows.batched;
        let a: Vec<Vector6<f64>> = match (&self.calibration, &self.mounting) {
            (Some(c), _) => {
                let out = c.bind(py).call_method1("apply", (samples, time))?;
                input::vectors6(&input::rows(&out, "calibrated samples", 6, "ã")?)
            }
            (None, Some(m)) => {
                let out = m.bind(py).call_method1("to_configuration", (samples,))?;
                input::vectors6(&input::rows(&out, "mounted samples", 6, "ã")?)
            }
            (None, None) => input::vectors6(&rows),
        };
        let model = *self.estimator.model();
        let points = self.estimator.config().nodes;
        let solved: Vec<Result<(ftwire_rod::Shape, bool), String>> = py.detach(|| {
            a.par_iter()
                .map(|a| {
                    let shape = model.shape(a, points).map_err(|e| e.to_string())?;
                    let stable = model.is_stable(a).map_err(|e| e.to_string())?;
                    Ok((shape, stable))
                })
                .collect()
        });
        let n = a.len();
        let mut shape = vec![f64::NAN; n * points * 3];
        let mut flags = Vec::with_capacity(n);
        let mut errors = Vec::with_capacity(n);
        for (i, (a, s)) in a.iter().zip(&solved).enumerate() {
            match s {
                Ok((s, stable)) => {
                    for (k, p) in s.positions.iter().enumerate() {
                        let at = 3 * (i * points + k);
                        shape[at..at + 3].copy_from_slice(&[p.x, p.y, p.z]);
                    }
                    flags.push(match self.estimator.flag_solved(a, *stable) {
                        Confidence::Confident => "confident",
                        Confidence::NotStable => "not_stable",
                        Confidence::Jump { .. } => "jump",
                    });
                    errors.push(None);
                }
                Err(e) => {
                    flags.push("no_shape");
                    errors.push(Some(e.clone()));
                }
            }
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
