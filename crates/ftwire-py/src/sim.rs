//! `ftwire.sim.Rig`: the ground-truth simulator (`ftwire_sim::SimRig`: the discrete elastic
//! rod, the F/T sensor, motion capture, execution error) as the experiments set it up
//! (`ftwire_lab::experiment::rig`), for trying the estimation and control code on a wire whose
//! truth is known.

use ftwire_core::{FtSample, Pose, Rig as _};
use ftwire_estimate::ft::{MountingSpec, RestAverage};
use ftwire_lab::error::from_sim;
use ftwire_lab::experiment::rig::{TARE_SAMPLES, place_among, true_centreline, true_rod};
use ftwire_lab::experiment::{Gravity, ModelKind};
use ftwire_lab::setup::SimSetup;
use ftwire_lab::wire::WireSpec;
use ftwire_sim::SimRig;
use nalgebra::Vector6;
use numpy::ndarray::{Array1, Array2};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::calibration::Mounting;
use crate::error::lab_error;
use crate::input::{self, value_error};
use crate::pose;
use crate::wire::Wire;

/// The start configuration a0 by default, in normalised units (torque in c2/L, force in
/// c2/L²): a moderate out-of-plane bend, stable for every preset wire with and without
/// gravity.
const DEFAULT_START: [f64; 6] = [0.3, 1.5, -1.0, 1.0, 0.5, -0.5];

/// A simulated dual-arm rig holding a wire: the ground truth the estimators are tried on.
///
/// Rig(wire="nitinol-3mm-820", sensor="distorted", gravity=True, seed=0, a0=None, rig=None)
///
/// - wire: a preset name, a wire file (TOML) or a Wire: the true wire (the estimators are
///   not told it).
/// - sensor: "distorted" (the default: offsets, cross-talk, drift, noise, dropouts),
///   "undistorted" (noise only), "real-like", or a sensor file (TOML, docs/config.md).
/// - gravity: standard gravity (0, 0, −9.81) m/s² along the base clamp frame's −z; False:
///   weightless, the paper's model holds exactly.
/// - seed: every random choice of the rig (sensor noise, drift, dropouts, markers, execution
///   error): the same seed and calls give the same numbers.
/// - a0: (6,) the configuration the wire is picked up in, torque first [N·m, N], base clamp
///   frame: the second gripper starts at Γ(a0) of the true wire's weightless model (with
///   gravity it then sags from a0); None: a moderate out-of-plane bend.
/// - rig: a rig file (TOML: markers, execution error, speeds); None: the library's rig.
///
/// Frames: the base clamp is at the world origin, so world = base clamp frame (x along the
/// wire at its base, z up). Raw F/T readings are force first [N, N·m] in the sensor frame;
/// Rig.mounting maps them to ã. Raises ValueError for bad input, RuntimeError when the
/// simulator finds no equilibrium.
#[pyclass(module = "ftwire.sim", name = "Rig")]
pub struct SimulatedRig {
    rig: SimRig,
    wire: Wire,
    gravity: Gravity,
    mounting: Py<Mounting>,
}

/// A lab error of the simulator as a Python exception.
fn sim_error(error: ftwire_sim::SimError, what: &str) -> PyErr {
    lab_error(&from_sim(error, what), what)
}

#[pymethods]
impl SimulatedRig {
    #[new]
    #[pyo3(signature = (wire = None, sensor = "distorted", gravity = true, seed = 0, a0 = None, rig = None))]
    fn new(
        py: Python<'_>,
        wire: Option<&Bound<'_, PyAny>>,
        sensor: &str,
        gravity: bool,
        seed: u64,
        a0: Option<&Bound<'_, PyAny>>,
        rig: Option<std::path::PathBuf>,
    ) -> PyResult<Self> {
        let spec = match wire {
            None => WireSpec::load("nitinol-3mm-820"),
            Some(w) => match w.extract::<PyRef<'_, Wire>>() {
                Ok(w) => Ok(w.spec.clone()),
                Err(_) => WireSpec::load(&w.extract::<String>().map_err(|_| {
                    value_error("wire: allowed are a preset name, a wire file (TOML) or a Wire")
                })?),
            },
        }
        .map_err(|e| value_error(format!("wire: {e}")))?;
        let wire = Wire::from_spec(spec.clone())?;
        let setup = SimSetup::load(Some(sensor), rig.as_deref())
            .map_err(|e| value_error(format!("sensor/rig: {e}")))?;
        let gravity = if gravity { Gravity::On } else { Gravity::Off };
        let a0 = match a0.filter(|v| !v.is_none()) {
            Some(v) => Vector6::from(input::fixed::<6>(
                v,
                "a0",
                "the start configuration (τ1, τ2, τ3, f1, f2, f3) [N·m, N]",
            )?),
            None => ftwire_rod::from_normalised(&wire.params, &Vector6::from(DEFAULT_START)),
        };
        let config = setup.rig_config(seed);
        let sensor_params = config.sensor.clone();
        let sim = py
            .detach(|| place_among(&spec, gravity, ModelKind::Weightless, &a0, config, &[]))
            .map_err(|e| lab_error(&e, "Rig"))?;
        let mounting = Mounting::from_spec(MountingSpec {
            clamp_position_in_sensor: sensor_params.clamp_position_in_sensor,
            clamp_rotation_in_sensor: sensor_params.clamp_rotation_in_sensor,
            ..MountingSpec::default()
        })?;
        Ok(Self {
            rig: sim,
            wire,
            gravity,
            mounting: Py::new(py, mounting)?,
        })
    }

    /// The true wire (what identification should find).
    #[getter]
    fn wire(&self) -> Wire {
        self.wire.clone()
    }

    /// (3,) gravity [m/s²] in the base clamp frame, or None when it is off.
    #[getter]
    fn gravity<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        match self.gravity {
            Gravity::On => Some(PyArray1::from_slice(py, self.gravity.vector().as_slice())),
            Gravity::Off => None,
        }
    }

    /// The sensor's mounting the robot knows from its drawings (the clamp pose in the sensor
    /// frame, no tool mass): Mounting.to_configuration maps a tared raw reading to ã. On the
    /// "distorted" sensor ã so read keeps the sensor's cross-talk and scale errors (a
    /// Calibration learns them away).
    #[getter]
    fn mounting(&self, py: Python<'_>) -> Py<Mounting> {
        self.mounting.clone_ref(py)
    }

    /// The rig's clock [s]: each F/T sample takes one tick of the sensor (1 kHz by default),
    /// each move the time the grippers need plus the settle time.
    #[getter]
    fn time(&self) -> f64 {
        self.rig.time()
    }

    /// (4, 4) the second gripper's clamp pose in the base clamp frame as the robot believes it
    /// (the commanded one) [m].
    #[getter]
    fn b<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let poses = self
            .rig
            .gripper_poses()
            .map_err(|e| sim_error(e, "gripper poses"))?;
        Ok(pose::to_array(py, &poses.relative()))
    }

    /// (4, 4) ground truth: where the second gripper actually is relative to the base clamp,
    /// the execution error included [m].
    #[getter]
    fn true_b<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        pose::to_array(py, &self.rig.actual_poses().relative())
    }

    /// (6,) ground truth: the wrench of the wire on the base gripper, torque first [N·m, N],
    /// base clamp frame (the true configuration a).
    #[getter]
    fn true_configuration<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let a = self.rig.equilibrium().base_wrench.to_vector();
        PyArray1::from_slice(py, a.as_slice())
    }

    /// Moves the second gripper to the relative pose b (base clamp frame; (4, 4), (6,)
    /// position [m] + rotation vector [rad], or (7,) position + quaternion (x, y, z, w)),
    /// quasi-statically, the base gripper staying put. It lands with the rig's execution error
    /// (none by default). A refused or failed move changes nothing. Releases the GIL.
    ///
    /// Raises ValueError for a bad pose or grippers farther apart than the wire is long;
    /// RuntimeError when the simulator finds no equilibrium on the way.
    fn place(&mut self, py: Python<'_>, b: &Bound<'_, PyAny>) -> PyResult<()> {
        let b = pose::pose(b, "b")?;
        self.move_to(py, b)
    }

    /// Moves the second gripper to Γ(a) of the true wire's model (as Rig.place): model
    /// "weightless" (the paper's) or "loaded" (its weight under the rig's gravity and its rest
    /// curvature: the true wire's base wrench is then a, up to the simulator's
    /// discretisation). a: (6,) torque first [N·m, N], base clamp frame. Returns the (4, 4)
    /// pose moved to.
    #[pyo3(signature = (a, model = "weightless"))]
    fn place_configuration<'py>(
        &mut self,
        py: Python<'py>,
        a: &Bound<'py, PyAny>,
        model: &str,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let a = Vector6::from(input::fixed::<6>(
            a,
            "a",
            "a configuration (τ1, τ2, τ3, f1, f2, f3) [N·m, N]",
        )?);
        let g = match model {
            "weightless" => Gravity::Off.vector(),
            "loaded" => self.gravity.vector(),
            other => {
                return Err(value_error(format!(
                    "model = {other:?} is not allowed: \"weightless\" or \"loaded\""
                )));
            }
        };
        let rod = true_rod(&self.wire.spec, g).map_err(|e| lab_error(&e, "model"))?;
        let b = rod
            .tip(&a)
            .map_err(|e| crate::wire::rod_error(&e, "a", None))?;
        self.move_to(py, b)?;
        Ok(pose::to_array(py, &b))
    }

    /// The F/T sensor averaged over a rest: reads `samples` samples (one per sensor tick),
    /// skips dropouts and saturated or non-finite samples, and returns the (6,) mean raw
    /// reading, force first [N, N·m], sensor frame, sensor offset and drift included (subtract
    /// Rig.tare()'s reading). 4 ≤ samples ≤ 10⁶. Raises RuntimeError when fewer than half survive.
    #[pyo3(signature = (samples = 100))]
    fn rest<'py>(
        &mut self,
        py: Python<'py>,
        samples: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let average = rest_average(samples)?;
        let rig = &mut self.rig;
        let read: Vec<Option<FtSample>> = (0..samples).map(|_| rig.read_ft().ok()).collect();
        mean(py, &average, &read, "rest")
    }

    /// The tare: the (6,) mean raw reading with nothing in the base gripper, force first
    /// [N, N·m], sensor frame, over `samples` samples (default 500: 0.5 s at 1 kHz). A robot
    /// takes it before it picks the wire up; the simulator lets it be taken at any time. Only
    /// the sensor's own offset, drift and noise are in it: rest() − tare() is the wire's
    /// reading.
    #[pyo3(signature = (samples = TARE_SAMPLES))]
    fn tare<'py>(
        &mut self,
        py: Python<'py>,
        samples: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let average = rest_average(samples)?;
        let rig = &mut self.rig;
        let read: Vec<Option<FtSample>> = (0..samples)
            .map(|_| rig.read_ft_empty_gripper().ok())
            .collect();
        mean(py, &average, &read, "tare")
    }

    /// (M, 3) the motion-capture markers now [m], base clamp frame, in the order of their arc
    /// lengths along the wire (11 by default); NaN rows for markers that dropped out.
    fn markers<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let frame = self
            .rig
            .observe_markers()
            .map_err(|e| sim_error(e, "markers"))?;
        let m = frame.positions.len();
        let array = Array2::from_shape_fn((m, 3), |(i, k)| {
            frame.positions[i].map_or(f64::NAN, |p| p[k])
        });
        Ok(PyArray2::from_owned_array(py, array))
    }

    /// (n, 3) ground truth: the simulated wire's centreline from the base clamp point to the
    /// second clamp point [m], base clamp frame (the simulator's nodes).
    fn centreline<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let points = true_centreline(&self.rig);
        let array = Array2::from_shape_fn((points.len(), 3), |(i, k)| points[i][k]);
        PyArray2::from_owned_array(py, array)
    }

    fn __repr__(&self) -> String {
        format!(
            "Rig(wire={:?}, gravity={}, time={:?})",
            self.wire.spec.name,
            if matches!(self.gravity, Gravity::On) {
                "True"
            } else {
                "False"
            },
            self.rig.time()
        )
    }
}

impl SimulatedRig {
    /// Moves the second gripper to `b` relative to the base (released GIL).
    fn move_to(&mut self, py: Python<'_>, b: Pose) -> PyResult<()> {
        let rig = &mut self.rig;
        py.detach(|| {
            let base = rig.gripper_poses()?.base;
            rig.move_tip(base * b)
        })
        .map_err(|e| sim_error(e, "moving the second gripper"))
    }
}

/// Most F/T samples one rest or tare reads: 10⁶, 1000 s at the simulated sensor's 1 kHz, far
/// beyond any rest (each sample is read and kept until the mean is taken).
pub const MAX_REST_SAMPLES: usize = 1_000_000;

/// The average of a rest of `samples` F/T samples: at least half of them good.
///
/// # Errors
/// `ValueError` for fewer than 4 samples or more than [`MAX_REST_SAMPLES`].
fn rest_average(samples: usize) -> PyResult<RestAverage> {
    if !(4..=MAX_REST_SAMPLES).contains(&samples) {
        return Err(value_error(format!(
            "samples = {samples} is not allowed: from 4 to {MAX_REST_SAMPLES} F/T samples"
        )));
    }
    RestAverage::new(samples / 2).map_err(|e| value_error(format!("samples: {e}")))
}

/// The (6,) mean of the good samples of `read`.
///
/// # Errors
/// `RuntimeError` (naming `what`) when too few samples are good.
fn mean<'py>(
    py: Python<'py>,
    average: &RestAverage,
    read: &[Option<FtSample>],
    what: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let averaged = average
        .average(read.iter().map(Option::as_ref))
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("{what}: {e}")))?;
    Ok(PyArray1::from_owned_array(
        py,
        Array1::from(averaged.mean.as_slice().to_vec()),
    ))
}
