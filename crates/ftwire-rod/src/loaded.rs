//! The loaded solver: the system of [`crate::load`] (`R`, `p`, `m`, `n`, the torque rows of
//! `M`, and `J`; 72 numbers) integrated with the crate's fixed-step tableaux on the same grid as
//! the unloaded solver, and the shape-only system (`R`, `p`, `m`, `n`; 18 numbers).
//!
//! The force rows of `M` keep their closed form under load, `M_n = [0, Rᵀ] + n̂ J_ω`
//! (`δn = n̂ ω + Rᵀ δa_f`, see [`crate::load`]), so only the torque rows `M_m` are integrated:
//! `M_m' = (m̂ C⁻¹ − û) M_m − ê1 M_n` (the force rows' rate, with its `E J` term, is then not
//! needed). This takes 18 numbers and most of the products off every stage.
//!
//! Shape nodes between grid points are interpolated as in the unloaded solver: septic Hermite
//! dense output of the frame from its jets `q, q', q'', q'''` at the grid points (the same
//! `FrameJet`s and interpolation code; the loaded jets come from `u' = C⁻¹ m'` and
//! `u'' = C⁻¹ m''` with the loaded `m'`, `n'`). `μ` at the nodes is the loaded closed form
//! `n = Rᵀ N`, `N = a_f − w t`, `m = Rᵀ (a_m − P × w − p × N)` of [`crate::load`], with
//! `P = ∫₀ᵗ p` integrated alongside (3 numbers) and interpolated from `P, p, p', p''`.
//!
//! Flat layouts (nalgebra's column-major order): `R` in `0..9`, `p` in `9..12`, `m` in
//! `12..15`, `n` in `15..18`; the full state adds `P` in `18..21`, `M_m` (3 × 6) in `21..39`, and
//! `J` as its rotational rows `J_ω` (3 × 6) in `39..57` and translational rows `J_v` in `57..75`
//! (each block contiguous, so that the rate reads and writes them without reassembling `J`).
//!
//! Guarded by `tests/loaded.rs`: agreement with the unloaded solver as the load vanishes,
//! `J(L)` and `M(L)` against finite differences, the invariants, a rest arc, and an independent
//! Dop853 integration of the same equations.

use ftwire_core::Pose;
use nalgebra::{Matrix3, Matrix3x6, Matrix6, Translation3, UnitQuaternion, Vector3, Vector6};

use crate::arith::Separate;
use crate::hermite::septic_hermite;
use crate::integrator::{Integrator, Workspace};
use crate::kirchhoff::{FrameArray, FrameJet, determinant6};
use crate::rod::{DEFAULT_NODES, JacobianSolution, Rod, Shape, Solution, rotation_from_columns};
use crate::se3::hat;
use crate::stability::SignTracker;
use crate::{Load, RodError, intersection::self_contact, validate_configuration};

/// The flat shape state: `R`, `p`, `m`, `n`.
pub(crate) type LoadedShapeArray = [f64; 18];
/// The flat full state: the shape state, then the torque rows of `M`, and `J`.
pub(crate) type LoadedFullArray = [f64; FULL];

/// The knots of the full solve: the shape state and `P` (the first 21 numbers).
pub(crate) type LoadedKnotArray = [f64; 21];

/// Numbers in the full state.
const FULL: usize = 75;
/// Where `P = ∫ p` starts in the full state.
const P_AT: usize = 18;
/// Where the torque rows of `M` start in the full state.
const M_AT: usize = 21;
/// Where `J` (its rows `J_ω`) starts in the full state.
const J_AT: usize = 39;
/// Where the rows `J_v` of `J` start in the full state.
const JV_AT: usize = 57;

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

    /// The initial full state: `q = I`, `μ = a`, `M_m = [I, 0]`, `J = 0`.
    pub fn full_initial(&self) -> LoadedFullArray {
        let mut y = [0.0; FULL];
        y[..18].copy_from_slice(&self.shape_initial());
        for i in 0..3 {
            y[M_AT + 4 * i] = 1.0;
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

    /// The full system's rate: the shape part, `M_m' = (m̂ C⁻¹ − û) M_m − ê1 M_n` with the
    /// closed form `M_n = [0, Rᵀ] + n̂ J_ω`, and `J' = G M + H J`, i.e. `J_ω' = C⁻¹ M_m − û J_ω`,
    /// `J_v' = −ê1 J_ω − û J_v` (see [`crate::load`] and the module docs), by blocks of three
    /// rows. (`ê1 X` is `X`'s rows `(0, −x_2, x_1)`: no product needed.)
    #[inline(always)]
    pub fn full_rate(&self, y: &LoadedFullArray, out: &mut LoadedFullArray) {
        let l = self.local(y);
        self.shape_part(&l, out);
        out[P_AT..M_AT].copy_from_slice(&y[9..12]);
        let m_top = Matrix3x6::from_column_slice(&y[M_AT..J_AT]);
        let j_top = Matrix3x6::from_column_slice(&y[J_AT..JV_AT]);
        let j_bot = Matrix3x6::from_column_slice(&y[JV_AT..FULL]);
        let uh = hat(&l.u);
        let mut m_bot = hat(&l.n) * j_top;
        m_bot
            .fixed_columns_mut::<3>(3)
            .iter_mut()
            .zip(l.r.transpose().iter())
            .for_each(|(v, r)| *v += r);
        let a = hat(&l.m) * Matrix3::from_diagonal(&self.inv_c) - uh;
        let mut dm_top = a * m_top;
        minus_e1_hat_add(&m_bot, &mut dm_top);
        let mut dj_top = -(uh * j_top);
        for (i, mut row) in dj_top.row_iter_mut().enumerate() {
            row += m_top.row(i) * self.inv_c[i];
        }
        let mut dj_bot = -(uh * j_bot);
        minus_e1_hat_add(&j_top, &mut dj_bot);
        out[M_AT..J_AT].copy_from_slice(dm_top.as_slice());
        out[J_AT..JV_AT].copy_from_slice(dj_top.as_slice());
        out[JV_AT..FULL].copy_from_slice(dj_bot.as_slice());
    }

    /// Integrates the full system over the grid of `steps` steps of `h`, tracking `det J`;
    /// pushes the shape part at `t = 0` and at every grid point into `knots` if given, and stops
    /// at the first sign change if `early_exit`.
    pub fn integrate_full(
        &self,
        integrator: &Integrator,
        h: f64,
        steps: usize,
        mut knots: Option<&mut Vec<LoadedKnotArray>>,
        record_det: bool,
        early_exit: bool,
    ) -> (LoadedFullArray, SignTracker) {
        let mut tracker = SignTracker::new(h, steps, record_det);
        let mut y = self.full_initial();
        if let Some(k) = knots.as_deref_mut() {
            k.push(knot_of(&y));
        }
        let f = |y: &LoadedFullArray, out: &mut LoadedFullArray| self.full_rate(y, out);
        let mut work = Workspace::new();
        for (step, grid_point) in integrator.grid(h, steps) {
            integrator.step_in_place::<Separate, FULL>(&mut y, step, f, &mut work);
            if let Some(index) = grid_point {
                if let Some(k) = knots.as_deref_mut() {
                    k.push(knot_of(&y));
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

    /// `q, q', q'', q'''` at a state (its first 18 numbers), as flat frame states by rows
    /// (`FrameJet`, the unloaded solver's layout): `R' = R û`, `R'' = R (û² + û')`,
    /// `R''' = R (û³ + 2 û û' + û' û + û'')`, `p⁽ᵏ⁺¹⁾ = R⁽ᵏ⁾ e1`, with `u' = C⁻¹ m'` and
    /// `u'' = C⁻¹ (m' × u + m × u' + n' × e1)` from the loaded `m'`, `n'`.
    pub fn jet(&self, y: &[f64]) -> FrameJet {
        let l = self.local(y);
        let times_e1 = |v: &Vector3<f64>| Vector3::new(0.0, v.z, -v.y);
        let dm = l.m.cross(&l.u) + times_e1(&l.n);
        let dn = l.n.cross(&l.u) - l.r.tr_mul(&self.w);
        let du = self.inv_c.component_mul(&dm);
        let ddm = dm.cross(&l.u) + l.m.cross(&du) + times_e1(&dn);
        let ddu = self.inv_c.component_mul(&ddm);
        let (uh, duh, dduh) = (hat(&l.u), hat(&du), hat(&ddu));
        let r1 = l.r * uh;
        let r2 = l.r * (uh * uh + duh);
        let r3 = l.r * (uh * uh * uh + 2.0 * uh * duh + duh * uh + dduh);
        let rows = |r: &Matrix3<f64>, p: Vector3<f64>| -> FrameArray {
            std::array::from_fn(|k| {
                let (i, j) = (k / 4, k % 4);
                if j < 3 { r[(i, j)] } else { p[i] }
            })
        };
        let p = Vector3::new(y[9], y[10], y[11]);
        FrameJet {
            d: [
                rows(&l.r, p),
                rows(&r1, l.r.column(0).into()),
                rows(&r2, r1.column(0).into()),
                rows(&r3, r2.column(0).into()),
            ],
        }
    }

    /// `μ(t)` at a node from its frame `(r, p)` and `P(t) = ∫₀ᵗ p`: `n = Rᵀ N`,
    /// `m = Rᵀ (a_m − P × w − p × N)`, `N = a_f − w t`.
    pub fn costate_at(
        &self,
        t: f64,
        r: &Matrix3<f64>,
        p: &Vector3<f64>,
        big_p: &Vector3<f64>,
    ) -> Vector6<f64> {
        let a_m = Vector3::new(self.a[0], self.a[1], self.a[2]);
        let big_n = Vector3::new(self.a[3], self.a[4], self.a[5]) - self.w * t;
        let m = r.tr_mul(&(a_m - big_p.cross(&self.w) - p.cross(&big_n)));
        let n = r.tr_mul(&big_n);
        Vector6::new(m.x, m.y, m.z, n.x, n.y, n.z)
    }
}

/// `P = ∫₀ᵗ p` at fraction `theta` of the step `h` from knot `k0` to knot `k1` (with their jets
/// `j0`, `j1`): septic Hermite from `P, P' = p, P'' = p', P''' = p''` at both ends.
pub(crate) fn interpolate_integral(
    (k0, j0): (&LoadedKnotArray, &FrameJet),
    (k1, j1): (&LoadedKnotArray, &FrameJet),
    h: f64,
    theta: f64,
) -> Vector3<f64> {
    let w = septic_hermite(theta);
    let scale = [1.0, h, h * h, h * h * h];
    let mut out = Vector3::zeros();
    for (side, (k, j)) in [(k0, j0), (k1, j1)].into_iter().enumerate() {
        for order in 0..4 {
            let c = w[4 * side + order] * scale[order];
            for (i, o) in out.iter_mut().enumerate() {
                let v = if order == 0 {
                    k[P_AT + i]
                } else {
                    j.d[order - 1][4 * i + 3]
                };
                *o += c * v;
            }
        }
    }
    out
}

/// The knot part (first 21 numbers: shape state and `P`) of a full state.
pub(crate) fn knot_of(y: &LoadedFullArray) -> LoadedKnotArray {
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

/// `M` of a full state: its torque rows, and the force rows by closed form
/// `M_n = [0, Rᵀ] + n̂ J_ω`.
pub(crate) fn m_of(y: &LoadedFullArray) -> Matrix6<f64> {
    let (r, _) = frame_of(y);
    let n = Vector3::new(y[15], y[16], y[17]);
    let j_top = Matrix3x6::from_column_slice(&y[J_AT..JV_AT]);
    let mut m = Matrix6::zeros();
    m.fixed_rows_mut::<3>(0)
        .copy_from(&Matrix3x6::from_column_slice(&y[M_AT..J_AT]));
    m.fixed_rows_mut::<3>(3).copy_from(&(hat(&n) * j_top));
    let mut force_block = m.fixed_view_mut::<3, 3>(3, 3);
    force_block += r.transpose();
    m
}

/// `J` of a full state.
pub(crate) fn jacobian_of(y: &LoadedFullArray) -> Matrix6<f64> {
    let mut j = Matrix6::zeros();
    j.fixed_rows_mut::<3>(0)
        .copy_from(&Matrix3x6::from_column_slice(&y[J_AT..JV_AT]));
    j.fixed_rows_mut::<3>(3)
        .copy_from(&Matrix3x6::from_column_slice(&y[JV_AT..FULL]));
    j
}

/// `out −= ê1 x` row-wise on 3 × 6 blocks: `ê1 x = (0, −x_2, x_1)` (rows), so row 1 of `out`
/// gains `x_2` and row 2 loses `x_1`.
#[inline(always)]
fn minus_e1_hat_add(x: &Matrix3x6<f64>, out: &mut Matrix3x6<f64>) {
    for c in 0..6 {
        out[(1, c)] += x[(2, c)];
        out[(2, c)] -= x[(1, c)];
    }
}

/// The rows of `J` of a full state (each 3 × 6 block column-major).
fn jacobian_rows(y: &LoadedFullArray) -> [[f64; 6]; 6] {
    std::array::from_fn(|r| {
        let (at, i) = if r < 3 { (J_AT, r) } else { (JV_AT, r - 3) };
        std::array::from_fn(|c| y[at + 3 * c + i])
    })
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
        let jets: Vec<FrameJet> = knots.iter().map(|k| model.jet(k)).collect();
        let shape = self.shape_from_knots(&jets, nodes);
        let radius = self.wire().radius();
        let self_intersecting = if nodes >= DEFAULT_NODES {
            self_contact(&shape.positions, shape.spacing(), radius).is_some()
        } else {
            let dense = self.shape_from_knots(&jets, DEFAULT_NODES);
            self_contact(&dense.positions, dense.spacing(), radius).is_some()
        };
        // μ at the nodes by the loaded closed form, with P = ∫p interpolated in the same knot
        // intervals as the frames (the walk of `Rod::shape_from_knots_with`).
        let last = nodes.saturating_sub(1).max(1) as f64;
        let mut k = 0;
        let costate = (0..nodes)
            .map(|i| {
                let x = i as f64 * steps as f64 / last;
                while k + 1 < steps && x >= (k + 1) as f64 {
                    k += 1;
                }
                let theta = (x - k as f64).clamp(0.0, 1.0);
                let big_p = match (knots.get(k), knots.get(k + 1), jets.get(k), jets.get(k + 1)) {
                    (Some(k0), Some(k1), Some(j0), Some(j1)) => {
                        interpolate_integral((k0, j0), (k1, j1), h, theta)
                    }
                    _ => Vector3::zeros(),
                };
                let (t, r, p) = (
                    shape.arc_length[i],
                    shape.rotations[i].matrix(),
                    &shape.positions[i],
                );
                model.costate_at(t, r, p, &big_p)
            })
            .collect();
        Ok(Solution {
            shape,
            costate,
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
        let jets: Vec<FrameJet> = knots.iter().map(|k| model.jet(k)).collect();
        Ok(self.shape_from_knots(&jets, nodes))
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
