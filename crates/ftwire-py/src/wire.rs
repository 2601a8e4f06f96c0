//! `ftwire.Wire`: an immutable wire (stiffnesses, length, radius, density, rest strains), and
//! its Kirchhoff model solved for one or many configurations ([`Wire::solve`]).

use std::path::PathBuf;

use ftwire_lab::wire::WireSpec;
use ftwire_rod::rod::{MAX_NODES, MIN_NODES};
use ftwire_rod::{Load, Rod, RodError, Solution as RodSolution, WireParams};
use nalgebra::Vector3;
use numpy::ndarray::{Array, Array1, Array2, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray3};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat};
use rayon::prelude::*;

use crate::input::{self, value_error};

/// The CLI's default radius \[m\] (`ftwire solve --radius`), the default of `Wire(radius=...)`.
pub const DEFAULT_RADIUS: f64 = 0.001;
/// The CLI's default density \[kg/m³\] (nitinol's; `ftwire solve --density`).
pub const DEFAULT_DENSITY: f64 = 6450.0;

/// An elastic wire: the parameters of the Kirchhoff rod model. Immutable.
///
/// Wire(c, length, radius=0.001, density=6450.0, natural_curvature=None, name="wire")
///
/// - c: (c1, c2, c3) [N·m²], torsion, then bending about body y and body z; each finite > 0.
/// - length: length L between the two clamp points [m], finite > 0.
/// - radius: [m], finite > 0 and below length / 2 (self-intersection and weight).
/// - density: [kg/m³], finite > 0 (weight per length density·π·radius², with gravity).
/// - natural_curvature: rest twist and curvatures (κ1, κ2, κ3) [1/m], body frame;
///   None: a straight, untwisted wire.
///
/// Raises ValueError naming the argument for a value out of range.
#[pyclass(module = "ftwire", frozen, eq)]
#[derive(Debug, Clone, PartialEq)]
pub struct Wire {
    pub(crate) spec: WireSpec,
    pub(crate) params: WireParams,
}

impl Wire {
    /// A wire from a spec, checked as the constructor checks its arguments.
    ///
    /// # Errors
    /// `ValueError` naming the field.
    pub fn from_spec(spec: WireSpec) -> PyResult<Self> {
        for (i, c) in spec.c.iter().enumerate() {
            input::positive(*c, &format!("c[{i}]"), "N·m²")?;
        }
        input::positive(spec.length, "length", "m")?;
        input::positive(spec.radius, "radius", "m")?;
        input::positive(spec.density, "density", "kg/m³")?;
        if 2.0 * spec.radius >= spec.length {
            return Err(value_error(format!(
                "radius = {} is not allowed: less than half the length ({} m), a wire, not a disc",
                spec.radius, spec.length
            )));
        }
        if let Some(i) = spec.natural_curvature.iter().position(|k| !k.is_finite()) {
            return Err(value_error(format!(
                "natural_curvature[{i}] = {} is not allowed: a finite curvature [1/m]",
                spec.natural_curvature[i]
            )));
        }
        let params = WireParams::new(spec.c, spec.length, spec.radius)
            .map_err(|e| value_error(format!("invalid wire: {e}")))?;
        Ok(Self { spec, params })
    }

    /// The load of a solve: the weight under `gravity` (if given) and the rest strains.
    fn load(&self, gravity: Option<Vector3<f64>>) -> PyResult<Load> {
        let weight = match gravity {
            Some(g) => Load::from_gravity(self.spec.density, self.spec.radius, g),
            None => Ok(Load::none()),
        };
        weight
            .and_then(|l| l.with_natural_curvature(Vector3::from(self.spec.natural_curvature)))
            .map_err(|e| value_error(format!("gravity: {e}")))
    }

    /// The model of this wire under `gravity` (base clamp frame, m/s²; `None`: weightless).
    pub(crate) fn rod(&self, gravity: Option<Vector3<f64>>) -> PyResult<Rod> {
        Ok(Rod::new(self.params).with_load(self.load(gravity)?))
    }
}

/// The Python error of a failed solve of row `row` (`None`: a single configuration).
pub(crate) fn rod_error(error: &RodError, name: &str, row: Option<usize>) -> PyErr {
    let at = row.map_or_else(|| name.to_owned(), |i| format!("{name}[{i}]"));
    match error {
        RodError::Diverged { .. } => PyRuntimeError::new_err(format!("{at}: no answer: {error}")),
        _ => value_error(format!("{at}: {error}")),
    }
}

#[pymethods]
impl Wire {
    #[new]
    #[pyo3(signature = (c, length, radius = DEFAULT_RADIUS, density = DEFAULT_DENSITY, natural_curvature = None, name = "wire".to_owned()))]
    fn new(
        c: &Bound<'_, PyAny>,
        length: f64,
        radius: f64,
        density: f64,
        natural_curvature: Option<&Bound<'_, PyAny>>,
        name: String,
    ) -> PyResult<Self> {
        let c = input::fixed::<3>(c, "c", "the stiffnesses (c1, c2, c3) [N·m²]")?;
        let natural_curvature = input::vector3(
            natural_curvature,
            "natural_curvature",
            "the rest strains (κ1, κ2, κ3) [1/m]",
        )?
        .unwrap_or_else(Vector3::zeros);
        Self::from_spec(WireSpec {
            name,
            c,
            length,
            radius,
            density,
            natural_curvature: natural_curvature.into(),
        })
    }

    /// A preset wire of the paper by name: "nitinol-2mm-630", "nitinol-3mm-910",
    /// "nitinol-3mm-820" or "cable-3mm-920". Raises ValueError for another name.
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Self> {
        let spec = WireSpec::preset(name).ok_or_else(|| {
            value_error(format!(
                "name = {name:?} is not a preset; allowed are {}",
                ftwire_lab::wire::PRESETS.join(", ")
            ))
        })?;
        Self::from_spec(spec)
    }

    /// A wire from a wire file (TOML: name, c, length, radius, density, natural_curvature;
    /// schema in docs/config.md). Raises ValueError naming the file, line and key.
    #[staticmethod]
    fn from_toml(path: PathBuf) -> PyResult<Self> {
        let text = ftwire_core::text::read_text(&path)
            .map_err(|e| value_error(format!("path {}: {e}", path.display())))?;
        let spec = WireSpec::from_toml(&text, &path.display().to_string())
            .map_err(|e| value_error(format!("path: {e}")))?;
        Self::from_spec(spec)
    }

    /// The name, for reports.
    #[getter]
    fn name(&self) -> &str {
        &self.spec.name
    }

    /// (c1, c2, c3) [N·m²]: torsion, bending about body y, bending about body z.
    #[getter]
    fn c(&self) -> (f64, f64, f64) {
        let [c1, c2, c3] = self.spec.c;
        (c1, c2, c3)
    }

    /// Length L between the clamp points [m].
    #[getter]
    fn length(&self) -> f64 {
        self.spec.length
    }

    /// Radius [m].
    #[getter]
    fn radius(&self) -> f64 {
        self.spec.radius
    }

    /// Density [kg/m³].
    #[getter]
    fn density(&self) -> f64 {
        self.spec.density
    }

    /// Rest twist and curvatures (κ1, κ2, κ3) [1/m], body frame.
    #[getter]
    fn natural_curvature(&self) -> (f64, f64, f64) {
        let [k1, k2, k3] = self.spec.natural_curvature;
        (k1, k2, k3)
    }

    fn __repr__(&self) -> String {
        let s = &self.spec;
        format!(
            "Wire(c=({:?}, {:?}, {:?}), length={:?}, radius={:?}, density={:?}, natural_curvature=({:?}, {:?}, {:?}), name={:?})",
            s.c[0],
            s.c[1],
            s.c[2],
            s.length,
            s.radius,
            s.density,
            s.natural_curvature[0],
            s.natural_curvature[1],
            s.natural_curvature[2],
            s.name
        )
    }

    /// Solves the Kirchhoff model for configurations `a`.
    ///
    /// - a: (6,) or (N, 6), the wrench on the base gripper (τ1, τ2, τ3 [N·m], f1, f2, f3 [N]),
    ///   torque first, in the base clamp frame.
    /// - points: shape nodes from t = 0 to t = L, both ends included (2 to 1 000 000).
    /// - gravity: (3,) [m/s²] in the base clamp frame: the loaded model with the wire's weight;
    ///   None: weightless (the paper's model).
    ///
    /// Returns a Solution whose arrays have a leading axis N for a (N, 6) input and none for
    /// a (6,) input. A batch runs in parallel over its rows with the GIL released.
    ///
    /// Raises ValueError naming the argument (and the row) for a bad shape, a value that is
    /// not finite or a configuration outside A; RuntimeError when the integration diverges.
    #[pyo3(signature = (a, points = 100, gravity = None))]
    fn solve(
        &self,
        py: Python<'_>,
        a: &Bound<'_, PyAny>,
        points: usize,
        gravity: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Solution> {
        if !(MIN_NODES..=MAX_NODES).contains(&points) {
            return Err(value_error(format!(
                "points = {points} is not allowed: {MIN_NODES} to {MAX_NODES} shape nodes"
            )));
        }
        let gravity = input::vector3(
            gravity,
            "gravity",
            "the gravity vector [m/s²], base clamp frame",
        )?;
        let rod = self.rod(gravity)?;
        let rows = input::rows(
            a,
            "a",
            6,
            "configurations (τ1, τ2, τ3, f1, f2, f3) [N·m, N]",
        )?;
        // Per row: the points, Γ (16), J (36) and three scalars.
        input::check_output(
            &format!("a ({} rows) and points = {points}", rows.values.len() / 6),
            (rows.values.len() as u128 / 6) * (3 * points as u128 + 55),
        )?;
        let configurations = input::vectors6(&rows);
        if !rows.batched {
            let solution = rod
                .solve(&configurations[0], points)
                .map_err(|e| rod_error(&e, "a", None))?;
            return Ok(Solution::single(py, &solution));
        }
        let batch = py
            .detach(|| Batch::solve(&rod, &configurations, points))
            .map_err(|(row, e)| rod_error(&e, "a", Some(row)))?;
        Ok(batch.into_solution(py))
    }
}

/// The model's answer for one configuration or a batch: arrays of float64 (C-contiguous).
#[pyclass(module = "ftwire", frozen, get_all)]
pub struct Solution {
    /// (N, points, 3) [m]: the centreline's nodes from t = 0 to t = L, base clamp frame.
    shape: Py<PyAny>,
    /// (N, 4, 4): Γ(a), the second gripper's clamp pose in the base clamp frame (homogeneous
    /// matrix, translation in m).
    tip_pose: Py<PyAny>,
    /// (N, 6, 6): J(L), δb ≈ J δa, rows the tip's body twist (δω [rad], δv [m]), columns δa.
    jacobian: Py<PyAny>,
    /// (N,) bool: whether the configuration is stable.
    stable: Py<PyAny>,
    /// (N,) bool: whether non-adjacent parts of the wire are closer than its diameter.
    self_intersecting: Py<PyAny>,
    /// (N,): the stability test's smallest |det J(t)| along the wire.
    det_j_min: Py<PyAny>,
}

impl Solution {
    fn single(py: Python<'_>, s: &RodSolution) -> Self {
        let mut row = Row::zeros(s.shape.len());
        row.fill(s);
        let n = s.shape.len();
        // The lengths are those written; the shapes cannot disagree.
        let any2 = |v: Vec<f64>, shape: (usize, usize)| -> Py<PyAny> {
            Array2::from_shape_vec(shape, v)
                .map_or_else(|_| py.None(), |a| a.into_pyarray(py).into_any().unbind())
        };
        Self {
            shape: any2(row.shape, (n, 3)),
            tip_pose: any2(row.tip.to_vec(), (4, 4)),
            jacobian: any2(row.jacobian.to_vec(), (6, 6)),
            stable: PyBool::new(py, row.stable).to_owned().into_any().unbind(),
            self_intersecting: PyBool::new(py, row.self_intersecting)
                .to_owned()
                .into_any()
                .unbind(),
            det_j_min: PyFloat::new(py, row.det_j_min).into_any().unbind(),
        }
    }
}

#[pymethods]
impl Solution {
    fn __repr__(&self, py: Python<'_>) -> String {
        let shape = self
            .shape
            .bind(py)
            .getattr("shape")
            .map_or_else(|_| "?".to_owned(), |s| s.to_string());
        format!("Solution(shape: {shape})")
    }
}

/// The flat, row-major arrays of a batch's answers.
struct Batch {
    n: usize,
    points: usize,
    shape: Vec<f64>,
    tip: Vec<f64>,
    jacobian: Vec<f64>,
    stable: Vec<bool>,
    self_intersecting: Vec<bool>,
    det_j_min: Vec<f64>,
}

impl Batch {
    /// Every configuration solved in parallel, each answer written in its place; the first
    /// failing row (lowest index) and its error otherwise, whatever the thread count.
    fn solve(
        rod: &Rod,
        configurations: &[nalgebra::Vector6<f64>],
        points: usize,
    ) -> Result<Self, (usize, RodError)> {
        let n = configurations.len();
        let mut batch = Self {
            n,
            points,
            shape: vec![0.0; n * points * 3],
            tip: vec![0.0; n * 16],
            jacobian: vec![0.0; n * 36],
            stable: vec![false; n],
            self_intersecting: vec![false; n],
            det_j_min: vec![0.0; n],
        };
        let mut errors: Vec<Option<RodError>> = vec![None; n];
        (
            batch.shape.par_chunks_mut(points * 3),
            batch.tip.par_chunks_mut(16),
            batch.jacobian.par_chunks_mut(36),
            batch.stable.par_iter_mut(),
            batch.self_intersecting.par_iter_mut(),
            batch.det_j_min.par_iter_mut(),
            errors.par_iter_mut(),
            configurations.par_iter(),
        )
            .into_par_iter()
            .for_each(
                |(shape, tip, jacobian, stable, intersecting, det, error, a)| match rod
                    .solve(a, points)
                {
                    Ok(s) => {
                        write_shape(&s, shape);
                        write_tip(&s, tip);
                        write_jacobian(&s, jacobian);
                        *stable = s.jacobian.stability.stable;
                        *intersecting = s.self_intersecting;
                        *det = s.jacobian.stability.det_j_min;
                    }
                    Err(e) => *error = Some(e),
                },
            );
        match errors
            .into_iter()
            .enumerate()
            .find_map(|(i, e)| e.map(|e| (i, e)))
        {
            Some(failure) => Err(failure),
            None => Ok(batch),
        }
    }

    fn into_solution(self, py: Python<'_>) -> Solution {
        let (n, p) = (self.n, self.points);
        let any3 = |v: Vec<f64>, shape: (usize, usize, usize)| -> Py<PyAny> {
            Array3::from_shape_vec(shape, v).map_or_else(
                |_| py.None(),
                |a| PyArray3::from_owned_array(py, a).into_any().unbind(),
            )
        };
        Solution {
            shape: any3(self.shape, (n, p, 3)),
            tip_pose: any3(self.tip, (n, 4, 4)),
            jacobian: any3(self.jacobian, (n, 6, 6)),
            stable: PyArray1::from_owned_array(py, Array1::from(self.stable))
                .into_any()
                .unbind(),
            self_intersecting: PyArray1::from_owned_array(py, Array::from(self.self_intersecting))
                .into_any()
                .unbind(),
            det_j_min: PyArray1::from_owned_array(py, Array1::from(self.det_j_min))
                .into_any()
                .unbind(),
        }
    }
}

/// One answer's values (for a single solve).
struct Row {
    shape: Vec<f64>,
    tip: [f64; 16],
    jacobian: [f64; 36],
    stable: bool,
    self_intersecting: bool,
    det_j_min: f64,
}

impl Row {
    fn zeros(points: usize) -> Self {
        Self {
            shape: vec![0.0; points * 3],
            tip: [0.0; 16],
            jacobian: [0.0; 36],
            stable: false,
            self_intersecting: false,
            det_j_min: 0.0,
        }
    }

    fn fill(&mut self, s: &RodSolution) {
        write_shape(s, &mut self.shape);
        write_tip(s, &mut self.tip);
        write_jacobian(s, &mut self.jacobian);
        self.stable = s.jacobian.stability.stable;
        self.self_intersecting = s.self_intersecting;
        self.det_j_min = s.jacobian.stability.det_j_min;
    }
}

/// The nodes' positions, row-major (points, 3).
fn write_shape(s: &RodSolution, out: &mut [f64]) {
    for (p, o) in s.shape.positions.iter().zip(out.chunks_exact_mut(3)) {
        o.copy_from_slice(&[p.x, p.y, p.z]);
    }
}

/// Γ(a) as a row-major homogeneous 4 × 4 matrix (the CLI's rotation matrix and position).
fn write_tip(s: &RodSolution, out: &mut [f64]) {
    let pose = &s.jacobian.tip;
    let r = pose.rotation.to_rotation_matrix();
    let t = pose.translation.vector;
    for i in 0..3 {
        for k in 0..3 {
            out[4 * i + k] = r[(i, k)];
        }
        out[4 * i + 3] = t[i];
    }
    out[12..16].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
}

/// J(L), row-major.
fn write_jacobian(s: &RodSolution, out: &mut [f64]) {
    let j = &s.jacobian.jacobian;
    for i in 0..6 {
        for k in 0..6 {
            out[6 * i + k] = j[(i, k)];
        }
    }
}
