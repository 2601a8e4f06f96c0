//! `ftwire.Controller`: one step of the paper's Jacobian controller (§III-C, eq. 13–14) at a
//! time, `ftwire_control::Controller::plan_step`, for a loop the caller runs on its own robot.

use ftwire_control::{ControlParams, Controller as Inner, StepPlan};
use ftwire_core::Pose;
use ftwire_estimate::{KirchhoffModel, WireModel};
use nalgebra::Vector6;
use numpy::PyArray1;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::input::{self, value_error};
use crate::pose;
use crate::wire::Wire;

/// The Jacobian controller of the paper (§III-C): from the measured configuration ã and the
/// goal a_g, one step commands
///
///     δb = s K J(L; ã) (a_g − ã)        (eq. 13)
///     b' = b M(δb)                      (eq. 14)
///
/// with the step scaled down (s ≤ 1) to max_translation and max_rotation, then halved (at
/// most max_shrinks times) until the model predicts ã + s K (a_g − ã) in A_stable.
///
/// Controller(wire, gain=0.2, epsilon=0.05, max_translation=0.05, max_rotation=0.3,
///            max_shrinks=6, gravity=None)
///
/// - wire: the Wire the model steers by (an identified one).
/// - gain: K in (0, 1].
/// - epsilon: the stop ‖a_g − ã‖ < ε in normalised units (torque in c2/L, force in c2/L²).
/// - max_translation: the largest |δx| of one step [m], > 0.
/// - max_rotation: the largest |δθ| of one step [rad], > 0.
/// - max_shrinks: the most halvings of a step the stability guard may take.
/// - gravity: (3,) [m/s²] in the base clamp frame: the loaded model (the wire's weight from
///   its density and radius); None: weightless, the paper's model.
///
/// Configurations are torque first [N·m, N] in the base clamp frame; a pose b is the second
/// gripper's clamp pose in the base clamp frame. Raises ValueError naming a bad argument.
#[pyclass(module = "ftwire", frozen)]
pub struct Controller {
    inner: Inner<KirchhoffModel>,
}

/// The configuration argument `name` as a 6-vector.
fn configuration(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Vector6<f64>> {
    Ok(Vector6::from(input::fixed::<6>(
        value,
        name,
        "a configuration (τ1, τ2, τ3, f1, f2, f3) [N·m, N], torque first, base clamp frame",
    )?))
}

impl Controller {
    /// The planned step from `a` toward `goal` with the second gripper at `b` (`None`: Γ(ã)
    /// of the model); `None` when no step passes the stability guard.
    fn plan(
        &self,
        a: &Bound<'_, PyAny>,
        goal: &Bound<'_, PyAny>,
        b: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Option<StepPlan>> {
        let a = configuration(a, "a_measured")?;
        let goal = configuration(goal, "a_goal")?;
        let tip: Pose = match b.filter(|b| !b.is_none()) {
            Some(b) => pose::pose(b, "b")?,
            None => self.inner.model().tip(&a).map_err(|e| {
                value_error(format!("a_measured: the model has no tip pose there ({e})"))
            })?,
        };
        self.inner
            .plan_step(&a, &goal, &tip)
            .map_err(|e| value_error(format!("a_measured: {e}")))
    }
}

#[pymethods]
impl Controller {
    #[new]
    #[pyo3(signature = (wire, gain = 0.2, epsilon = 0.05, max_translation = 0.05, max_rotation = 0.3, max_shrinks = 6, gravity = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        wire: &Wire,
        gain: f64,
        epsilon: f64,
        max_translation: f64,
        max_rotation: f64,
        max_shrinks: usize,
        gravity: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let gravity = input::vector3(
            gravity,
            "gravity",
            "the gravity vector [m/s²], base clamp frame",
        )?;
        let model = KirchhoffModel::from_rod(wire.rod(gravity)?);
        let settings = ControlParams {
            gain,
            epsilon,
            max_translation,
            max_rotation,
            max_shrinks,
            ..ControlParams::default()
        };
        let inner = Inner::new(model, settings).map_err(|e| value_error(e.to_string()))?;
        Ok(Self { inner })
    }

    /// The gain K.
    #[getter]
    fn gain(&self) -> f64 {
        self.inner.settings().gain
    }

    /// The stop threshold ε [normalised].
    #[getter]
    fn epsilon(&self) -> f64 {
        self.inner.settings().epsilon
    }

    /// The second gripper's next pose b' (4, 4), base clamp frame [m], for the measured
    /// configuration a_measured and the goal a_goal ((6,) each, torque first [N·m, N], base
    /// clamp frame), with the gripper now at b ((4, 4), (6,) or (7,); None: Γ(a_measured) of
    /// the model, what it is by the model).
    ///
    /// Raises ValueError for bad input or an a_measured the model cannot solve at;
    /// RuntimeError when no step passes the stability guard (the model predicts every
    /// allowed step leaves A_stable).
    #[pyo3(signature = (a_measured, a_goal, b = None))]
    fn step<'py>(
        &self,
        py: Python<'py>,
        a_measured: &Bound<'py, PyAny>,
        a_goal: &Bound<'py, PyAny>,
        b: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        let plan = self.plan(a_measured, a_goal, b)?.ok_or_else(|| {
            PyRuntimeError::new_err(
                "step: no step passes the stability guard: the model predicts every allowed \
                 step leaves A_stable",
            )
        })?;
        Ok(pose::to_array(py, &plan.next_tip))
    }

    /// As step(), with what the model expects: a dict with "b" (4, 4) the next pose,
    /// "delta_b" (6,) δb (rotation [rad] first, then translation [m], body frame of b),
    /// "predicted_da" (6,) the δa the model predicts [N·m, N] (s K (a_goal − a_measured)),
    /// "scale" s in (0, 1]; None when no step passes the stability guard.
    #[pyo3(signature = (a_measured, a_goal, b = None))]
    fn plan_step<'py>(
        &self,
        py: Python<'py>,
        a_measured: &Bound<'py, PyAny>,
        a_goal: &Bound<'py, PyAny>,
        b: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(plan) = self.plan(a_measured, a_goal, b)? else {
            return Ok(None);
        };
        let dict = PyDict::new(py);
        dict.set_item("b", pose::to_array(py, &plan.next_tip))?;
        dict.set_item("delta_b", PyArray1::from_slice(py, plan.delta_b.as_slice()))?;
        dict.set_item(
            "predicted_da",
            PyArray1::from_slice(py, plan.predicted_da.as_slice()),
        )?;
        dict.set_item("scale", plan.scale)?;
        Ok(Some(dict))
    }

    /// ‖a_goal − a‖ in normalised units (torque in c2/L, force in c2/L²).
    fn distance(&self, a: &Bound<'_, PyAny>, a_goal: &Bound<'_, PyAny>) -> PyResult<f64> {
        Ok(self
            .inner
            .distance(&configuration(a, "a")?, &configuration(a_goal, "a_goal")?))
    }

    /// Whether a is within ε of a_goal (the controller's stop rule).
    fn reached(&self, a: &Bound<'_, PyAny>, a_goal: &Bound<'_, PyAny>) -> PyResult<bool> {
        Ok(self.distance(a, a_goal)? < self.inner.settings().epsilon)
    }

    /// Raises ValueError unless a_goal is finite and in the model's A_stable.
    fn check_goal(&self, a_goal: &Bound<'_, PyAny>) -> PyResult<()> {
        self.inner
            .check_goal(&configuration(a_goal, "a_goal")?)
            .map_err(|e| value_error(format!("a_goal: {e}")))
    }

    fn __repr__(&self) -> String {
        let s = self.inner.settings();
        format!(
            "Controller(gain={:?}, epsilon={:?}, max_translation={:?}, max_rotation={:?}, \
             max_shrinks={})",
            s.gain, s.epsilon, s.max_translation, s.max_rotation, s.max_shrinks
        )
    }
}
