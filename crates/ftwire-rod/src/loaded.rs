//! The loaded solver: the full system of [`crate::load`] (`R`, `p`, `m`, `n`, `M`, `J`;
//! 90 numbers) integrated with the crate's fixed-step tableaux on the same grid as the unloaded
//! solver, and the shape-only system (`R`, `p`, `m`, `n`; 18 numbers).
//!
//! Shape nodes between grid points are reached by one step of the 18-number system from the
//! grid point before them (a step no longer than the grid's, so as accurate as the grid
//! points), which gives `μ` there too.
//!
//! Flat layouts (nalgebra's column-major order): `R` in `0..9`, `p` in `9..12`, `m` in
//! `12..15`, `n` in `15..18`; the full state adds `M` in `18..54` and `J` in `54..90`.
//!
//! Guarded by `tests/loaded.rs`: agreement with the unloaded solver as the load vanishes,
//! `J(L)` and `M(L)` against finite differences, the invariants, a rest arc, and an independent
//! Dop853 integration of the same equations.

use ftwire_core::Pose;
use nalgebra::{Matrix3, Matrix3x6, Matrix6, Translation3, UnitQuaternion, Vector3, Vector6};

use crate::arith::Separate;
use crate::integrator::{Integrator, Workspace};
use crate::kirchhoff::determinant6;
use crate::rod::{DEFAULT_NODES, JacobianSolution, Rod, Shape, Solution, rotation_from_columns};
use crate::se3::hat;
use crate::stability::SignTracker;
use crate::{Load, RodError, intersection::self_contact, validate_configuration};

/// The flat shape state: `R`, `p`, `m`, `n`.
pub(crate) type LoadedShapeArray = [f64; 18];
/// The flat full state: the shape state, then `M` and `J`.
pub(crate) type LoadedFullArray = [f64; 90];

/// Where `M` starts in the full state.
const M_AT: usize = 18;
/// Where `J` starts in the full state.
const J_AT: usize = 54;

/// The right-hand sides of the loaded equations for one wire, load and configuration.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Loaded {
    inv_c: Vector3<f64>,
    u0: Vector3<f64>,
    w: Vector3<f64>,
    a: Vector6<f64>,
}

/// The frame, costate and strain of a flat state.
struct Local {
    r: Matrix3<f64>,
    m: Vector3<f64>,
    n: Vector3<f64>,
    u: Vector3<f64>,
}

impl Loaded {
    pub fn new(c: [f64; 3], load: &Load, a: &Vector6<f64>) -> Self {
        Self {
            inv_c: Vector3::new(1.0 / c[0], 1.0 / c[1], 1.0 / c[2]),
            u0: load.natural_curvature,
            w: load.weight_per_length,
            a: *a,
        }
    }

    /// The initial full state: `q = I`, `μ = a`, `M = I`, `J = 0`.
    pub fn full_initial(&self) -> LoadedFullArray {
        let mut y = [0.0; 90];
        y[..18].copy_from_slice(&self.shape_initial());
        for i in 0..6 {
            y[M_AT + 7 * i] = 1.0;
        }
        y
    }

    /// The initial shape state: `q = I`, `μ = a`.
    pub fn shape_initial(&self) -> LoadedShapeArray {
        let mut y = [0.0; 18];
        y[0] = 1.0;
        y[4] = 1.0;
        y[8] = 1.0;
        y[12..18].copy_from_slice(self.a.as_slice());
        y
    }

    #[inline(always)]
    fn local(&self, y: &[f64]) -> Local {
        let r = Matrix3::from_column_slice(&y[0..9]);
        let m = Vector3::new(y[12], y[13], y[14]);
        let n = Vector3::new(y[15], y[16], y[17]);
        let u = self.inv_c.component_mul(&m) + self.u0;
        Local { r, m, n, u }
    }

    /// `R' = R û`, `p' = R e1`, `m' = m × u + n × e1`, `n' = n × u − Rᵀ w` into `out[0..18]`.
    #[inline(always)]
    fn shape_part(&self, l: &Local, out: &mut [f64]) {
        let dr = l.r * hat(&l.u);
        out[0..9].copy_from_slice(dr.as_slice());
        out[9..12].copy_from_slice(l.r.column(0).as_slice());
        let dm = l.m.cross(&l.u) + Vector3::new(0.0, l.n.z, -l.n.y);
        let dn = l.n.cross(&l.u) - l.r.tr_mul(&self.w);
        out[12..15].copy_from_slice(dm.as_slice());
        out[15..18].copy_from_slice(dn.as_slice());
    }

    /// The shape system's rate.
    #[inline(always)]
    pub fn shape_rate(&self, y: &LoadedShapeArray, out: &mut LoadedShapeArray) {
        let l = self.local(y);
        self.shape_part(&l, out);
    }

    /// The full system's rate: the shape part, `M' = F M + E J` and `J' = G M + H J` (see
    /// [`crate::load`]), written by blocks of three rows.
    #[inline(always)]
    pub fn full_rate(&self, y: &LoadedFullArray, out: &mut LoadedFullArray) {
        let l = self.local(y);
        self.shape_part(&l, out);
        let mm = Matrix6::from_column_slice(&y[M_AT..J_AT]);
        let jj = Matrix6::from_column_slice(&y[J_AT..90]);
        let (m_top, m_bot): (Matrix3x6<f64>, Matrix3x6<f64>) =
            (mm.fixed_rows::<3>(0).into(), mm.fixed_rows::<3>(3).into());
        let (j_top, j_bot): (Matrix3x6<f64>, Matrix3x6<f64>) =
            (jj.fixed_rows::<3>(0).into(), jj.fixed_rows::<3>(3).into());
        let inv_c = Matrix3::from_diagonal(&self.inv_c);
        let uh = hat(&l.u);
        let e1h = hat(&Vector3::x());
        let cm = inv_c * m_top;
        let dm_top = hat(&l.m) * cm - uh * m_top - e1h * m_bot;
        let dm_bot = hat(&l.n) * cm - uh * m_bot - hat(&l.r.tr_mul(&self.w)) * j_top;
        let dj_top = cm - uh * j_top;
        let dj_bot = -(e1h * j_top) - uh * j_bot;
        let mut dmm = Matrix6::zeros();
        dmm.fixed_rows_mut::<3>(0).copy_from(&dm_top);
        dmm.fixed_rows_mut::<3>(3).copy_from(&dm_bot);
        let mut djj = Matrix6::zeros();
        djj.fixed_rows_mut::<3>(0).copy_from(&dj_top);
        djj.fixed_rows_mut::<3>(3).copy_from(&dj_bot);
        out[M_AT..J_AT].copy_from_slice(dmm.as_slice());
        out[J_AT..90].copy_from_slice(djj.as_slice());
    }

    /// Integrates the full system over the grid of `steps` steps of `h`, tracking `det J`;
    /// pushes the shape part at `t = 0` and at every grid point into `knots` if given, and stops
    /// at the first sign change if `early_exit`.
    pub fn integrate_full(
        &self,
        integrator: &Integrator,
        h: f64,
        steps: usize,
        mut knots: Option<&mut Vec<LoadedShapeArray>>,
        record_det: bool,
        early_exit: bool,
    ) -> (LoadedFullArray, SignTracker) {
        let mut tracker = SignTracker::new(h, steps, record_det);
        let mut y = self.full_initial();
        if let Some(k) = knots.as_deref_mut() {
            k.push(shape_of(&y));
        }
        let f = |y: &LoadedFullArray, out: &mut LoadedFullArray| self.full_rate(y, out);
        let mut work = Workspace::new();
        for (step, grid_point) in integrator.grid(h, steps) {
            integrator.step_in_place::<Separate, 90>(&mut y, step, f, &mut work);
            if let Some(index) = grid_point {
                if let Some(k) = knots.as_deref_mut() {
                    k.push(shape_of(&y));
                }
                let stable = tracker.push(index as f64 * h, determinant6(jacobian_rows(&y)));
                if !stable && early_exit {
                    break;
                }
            }
        }
        (y, tracker)
    }

    /// Integrates the shape system over the grid, pushing the state at `t = 0` and at every
    /// grid point into `knots`.
    pub fn integrate_shape(
        &self,
        integrator: &Integrator,
        h: f64,
        steps: usize,
        knots: &mut Vec<LoadedShapeArray>,
    ) {
        let mut y = self.shape_initial();
        knots.push(y);
        let f = |y: &LoadedShapeArray, out: &mut LoadedShapeArray| self.shape_rate(y, out);
        let mut work = Workspace::new();
        for (step, grid_point) in integrator.grid(h, steps) {
            integrator.step_in_place::<Separate, 18>(&mut y, step, f, &mut work);
            if grid_point.is_some() {
                knots.push(y);
            }
        }
    }

    /// The shape states at `nodes` nodes uniform in `[0, L]`, `L = h · (knots.len() − 1)`: the
    /// knot itself on a grid point, else one step of the shape system from the knot before.
    pub fn nodes(
        &self,
        integrator: &Integrator,
        knots: &[LoadedShapeArray],
        h: f64,
        nodes: usize,
    ) -> Vec<LoadedShapeArray> {
        let steps = knots.len().saturating_sub(1).max(1);
        let last = nodes.saturating_sub(1).max(1) as f64;
        let f = |y: &LoadedShapeArray, out: &mut LoadedShapeArray| self.shape_rate(y, out);
        let mut work = Workspace::new();
        let mut k = 0;
        (0..nodes)
            .map(|i| {
                let x = i as f64 * steps as f64 / last;
                while k + 1 < steps && x >= (k + 1) as f64 {
                    k += 1;
                }
                let theta = (x - k as f64).clamp(0.0, 1.0);
                let at = if theta == 1.0 { k + 1 } else { k };
                let mut y = knots
                    .get(at)
                    .copied()
                    .unwrap_or_else(|| self.shape_initial());
                if theta > 0.0 && theta < 1.0 {
                    integrator.step_in_place::<Separate, 18>(&mut y, theta * h, f, &mut work);
                }
                y
            })
            .collect()
    }
}

/// The shape part (first 18 numbers) of a full state.
pub(crate) fn shape_of(y: &LoadedFullArray) -> LoadedShapeArray {
    std::array::from_fn(|i| y[i])
}

/// `R` and `p` of a flat state.
pub(crate) fn frame_of(y: &[f64]) -> (Matrix3<f64>, Vector3<f64>) {
    (
        Matrix3::from_column_slice(&y[0..9]),
        Vector3::new(y[9], y[10], y[11]),
    )
}

/// `μ = (m, n)` of a flat state.
pub(crate) fn costate_of(y: &[f64]) -> Vector6<f64> {
    Vector6::from_column_slice(&y[12..18])
}

/// `M` of a full state.
pub(crate) fn m_of(y: &LoadedFullArray) -> Matrix6<f64> {
    Matrix6::from_column_slice(&y[M_AT..J_AT])
}

/// `J` of a full state.
pub(crate) fn jacobian_of(y: &LoadedFullArray) -> Matrix6<f64> {
    Matrix6::from_column_slice(&y[J_AT..90])
}

/// The rows of `J` of a full state.
fn jacobian_rows(y: &LoadedFullArray) -> [[f64; 6]; 6] {
    std::array::from_fn(|r| std::array::from_fn(|c| y[J_AT + 6 * c + r]))
}

/// The loaded solves behind [`Rod`]'s methods when its load is not [`Load::none`].
impl Rod {
    /// The model of `a` under this rod's load, its grid step and step count.
    fn loaded_model(&self, a: &Vector6<f64>) -> Result<(Loaded, f64, usize), RodError> {
        validate_configuration(a)?;
        self.load().validate()?;
        let (c, length) = (self.wire().c(), self.wire().length());
        let sigma = self.load().turning_scale(c, a, length);
        let steps = self.integrator().steps_for(sigma * length);
        Ok((Loaded::new(c, self.load(), a), length / steps as f64, steps))
    }

    /// [`Rod::steps_for_configuration`] under load.
    pub(crate) fn loaded_steps(&self, a: &Vector6<f64>) -> Result<usize, RodError> {
        Ok(self.loaded_model(a)?.2)
    }

    /// The shape from the node states.
    fn loaded_shape_of(&self, states: &[LoadedShapeArray]) -> Shape {
        let length = self.wire().length();
        let last = states.len().saturating_sub(1).max(1) as f64;
        let (positions, rotations) = states
            .iter()
            .map(|y| {
                let (r, p) = frame_of(y);
                (p, rotation_from_columns(&r))
            })
            .unzip();
        Shape {
            arc_length: (0..states.len())
                .map(|i| length * i as f64 / last)
                .collect(),
            positions,
            rotations,
        }
    }

    fn loaded_jacobian_solution(
        &self,
        a: &Vector6<f64>,
        steps: usize,
        y: &LoadedFullArray,
        tracker: SignTracker,
    ) -> Result<JacobianSolution, RodError> {
        if !y.iter().all(|v| v.is_finite()) {
            return Err(RodError::Diverged {
                a: (*a).into(),
                steps,
            });
        }
        let (r, p) = frame_of(y);
        let rotation = rotation_from_columns(&r);
        Ok(JacobianSolution {
            tip: Pose::from_parts(
                Translation3::from(p),
                UnitQuaternion::from_rotation_matrix(&rotation),
            ),
            jacobian: jacobian_of(y),
            m: m_of(y),
            costate_tip: costate_of(y),
            stability: tracker.finish(),
        })
    }

    /// [`Rod::solve`] under load (nodes already checked).
    pub(crate) fn loaded_solve(
        &self,
        a: &Vector6<f64>,
        nodes: usize,
    ) -> Result<Solution, RodError> {
        let (model, h, steps) = self.loaded_model(a)?;
        let mut knots = Vec::with_capacity(steps + 1);
        let (y, tracker) =
            model.integrate_full(self.integrator(), h, steps, Some(&mut knots), true, false);
        let jacobian = self.loaded_jacobian_solution(a, steps, &y, tracker)?;
        let states = model.nodes(self.integrator(), &knots, h, nodes);
        let shape = self.loaded_shape_of(&states);
        let radius = self.wire().radius();
        let self_intersecting = if nodes >= DEFAULT_NODES {
            self_contact(&shape.positions, shape.spacing(), radius).is_some()
        } else {
            let dense = model.nodes(self.integrator(), &knots, h, DEFAULT_NODES);
            let dense = self.loaded_shape_of(&dense);
            self_contact(&dense.positions, dense.spacing(), radius).is_some()
        };
        Ok(Solution {
            shape,
            costate: states.iter().map(|y| costate_of(y)).collect(),
            jacobian,
            self_intersecting,
        })
    }

    /// [`Rod::shape`] under load (nodes already checked).
    pub(crate) fn loaded_shape(&self, a: &Vector6<f64>, nodes: usize) -> Result<Shape, RodError> {
        let (model, h, steps) = self.loaded_model(a)?;
        let mut knots = Vec::with_capacity(steps + 1);
        model.integrate_shape(self.integrator(), h, steps, &mut knots);
        if !knots.iter().flatten().all(|v| v.is_finite()) {
            return Err(RodError::Diverged {
                a: (*a).into(),
                steps,
            });
        }
        let states = model.nodes(self.integrator(), &knots, h, nodes);
        Ok(self.loaded_shape_of(&states))
    }

    /// [`Rod::jacobian`] under load.
    pub(crate) fn loaded_jacobian(&self, a: &Vector6<f64>) -> Result<JacobianSolution, RodError> {
        let (model, h, steps) = self.loaded_model(a)?;
        let (y, tracker) = model.integrate_full(self.integrator(), h, steps, None, true, false);
        self.loaded_jacobian_solution(a, steps, &y, tracker)
    }

    /// [`Rod::is_stable`] under load (early exit).
    pub(crate) fn loaded_is_stable(&self, a: &Vector6<f64>) -> Result<bool, RodError> {
        let (model, h, steps) = self.loaded_model(a)?;
        let (_, tracker) = model.integrate_full(self.integrator(), h, steps, None, false, true);
        Ok(tracker.finish().stable)
    }
}
