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
//! `FrameJet`s, jet rows and interpolation code; the loaded jets come from `u' = C⁻¹ m'` and
//! `u'' = C⁻¹ m''` with the loaded `m'`, `n'`). `μ` at the nodes is the loaded closed form
//! `n = Rᵀ N`, `N = a_f − w t`, `m = Rᵀ (a_m − P × w − p × N)` of [`crate::load`], with
//! `P = ∫₀ᵗ p` integrated alongside (3 numbers) and interpolated from `P, p, p', p''`.
//!
//! Flat layouts: `R` in `0..9` (nalgebra's column-major order), `p` in `9..12`, `m` in
//! `12..15`, `n` in `15..18`; the full state adds `P` in `18..21`, then (after three zeros)
//! the nine rows of six numbers of the torque rows of `M`, `a_0..a_2`, the rotational rows of
//! `J` (`J_ω`), `t_0..t_2`, and its translational rows (`J_v`), `b_0..b_2`: columns 0–3 of
//! row `k` in `24 + 4k`, columns 4–5 in `60 + 2k` (and two zeros at the end). The rate of the
//! matrices is a sum of scalar-times-row terms (every `3 × 3` factor has a zero diagonal or
//! is diagonal), as the unloaded solver's rate on the rows of `J`; with every block of four
//! numbers at a multiple of four, the rate writes whole 4-lane blocks where the stage sums
//! read them (a load that spans two smaller stores waits for both to reach the cache).
//!
//! # Speed
//!
//! The rates and the stage sums are generic over the multiply–add ([`crate::arith`]) and run
//! compiled for AVX2 with hardware FMA when the CPU has it, as the unloaded solver's generic
//! loops do; `FTWIRE_NO_SIMD=1` forces the portable build. The two builds differ only in
//! rounding (`fast_and_portable_paths_agree` below checks it).
//!
//! Guarded by `tests/loaded.rs`: agreement with the unloaded solver as the load vanishes,
//! `J(L)` and `M(L)` against finite differences, the invariants, a rest arc, and an independent
//! Dop853 integration of the same equations.

use ftwire_core::Pose;
use nalgebra::{Matrix3, Matrix3x6, Matrix6, Translation3, UnitQuaternion, Vector3, Vector6};

use std::marker::PhantomData;

use crate::arith::{MulAdd, Separate, V2, V4};
use crate::hermite::septic_hermite;
use crate::integrator::{Integrator, Rhs, Workspace};
use crate::kirchhoff::{FrameArray, FrameJet, jet_of_strains};
use crate::rod::rotation_from_columns;
use crate::rod::{DEFAULT_NODES, JacobianSolution, Rod, Shape, Solution};
use crate::se3::hat;
use crate::stability::SignTracker;
use crate::{Load, RodError, intersection::self_contact, validate_configuration};

mod series;

/// The flat shape state: `R`, `p`, `m`, `n`.
pub(crate) type LoadedShapeArray = [f64; 18];
/// The flat full state: the shape state, then the torque rows of `M`, and `J`.
pub(crate) type LoadedFullArray = [f64; FULL];

/// The knots of the full solve: the shape state and `P` (the first 21 numbers).
pub(crate) type LoadedKnotArray = [f64; 21];

/// Numbers in the full state (a multiple of four; see the module docs).
const FULL: usize = 80;
/// Where `P = ∫ p` starts in the full state.
const P_AT: usize = 18;
/// Where the matrices' rows start: columns 0–3 of row `k` (`k` = 0–8: the rows of `M_m`,
/// `J_ω`, `J_v`) at `LEFT + 4 k`.
const LEFT: usize = 24;
/// Columns 4–5 of row `k` at `RIGHT + 2 k`.
const RIGHT: usize = 60;

/// The right-hand sides of the loaded equations for one wire, load and configuration.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Loaded {
    inv_c: Vector3<f64>,
    u0: Vector3<f64>,
    w: Vector3<f64>,
    a: Vector6<f64>,
    /// `(0, 0, 0, 1)`, for the jets (a run-time value, see `kirchhoff`'s `cross_operands`).
    e3: V4,
}

/// The frame, costate and strain of a flat state.
struct Local {
    r: Matrix3<f64>,
    m: Vector3<f64>,
    n: Vector3<f64>,
    u: Vector3<f64>,
}

/// The loaded rates as an [`Rhs`] on `D` numbers ([`Loaded::full_rate`] for `D = FULL`,
/// [`Loaded::shape_rate`] for `D = 18`), multiply–adding with `A` (a struct, not a closure, so
/// that the rate is compiled into the AVX2+FMA loops; see [`Rhs`]).
struct Rate<'a, A, const D: usize> {
    model: &'a Loaded,
    arith: PhantomData<A>,
}

// Manual impls: derives would require `A: Copy`.
impl<A, const D: usize> Clone for Rate<'_, A, D> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<A, const D: usize> Copy for Rate<'_, A, D> {}

impl<A: MulAdd> Rhs<FULL> for Rate<'_, A, FULL> {
    #[inline(always)]
    fn rate(&self, y: &LoadedFullArray, out: &mut LoadedFullArray) {
        self.model.full_rate::<A>(y, out);
    }
}

impl<A: MulAdd> Rhs<18> for Rate<'_, A, 18> {
    #[inline(always)]
    fn rate(&self, y: &LoadedShapeArray, out: &mut LoadedShapeArray) {
        self.model.shape_rate::<A>(y, out);
    }
}

impl Loaded {
    pub fn new(c: [f64; 3], load: &Load, a: &Vector6<f64>) -> Self {
        Self {
            inv_c: Vector3::new(1.0 / c[0], 1.0 / c[1], 1.0 / c[2]),
            u0: load.natural_curvature,
            w: load.weight_per_length,
            a: *a,
            e3: V4([0.0, 0.0, 0.0, 1.0]),
        }
    }

    /// The initial full state: `q = I`, `μ = a`, `M_m = [I, 0]`, `J = 0`.
    pub fn full_initial(&self) -> LoadedFullArray {
        let mut y = [0.0; FULL];
        y[..18].copy_from_slice(&self.shape_initial());
        for i in 0..3 {
            y[LEFT + 4 * i + i] = 1.0;
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

    /// `R' = R û`, `p' = R e1`, `m' = m × u + n × e1`, `n' = n × u − Rᵀ w` (and `u`),
    /// multiply–added by `A`: column `j` of `R û` is `R (u × e_j)`, a sum of two columns of
    /// `R`.
    #[inline(always)]
    fn shape_part<A: MulAdd>(&self, y: &[f64]) -> ([f64; 18], [f64; 3]) {
        let ic = [self.inv_c.x, self.inv_c.y, self.inv_c.z];
        let (m, n) = ([y[12], y[13], y[14]], [y[15], y[16], y[17]]);
        let u: [f64; 3] = std::array::from_fn(|i| A::mul_add(ic[i], m[i], self.u0[i]));
        let col = |j: usize| [y[3 * j], y[3 * j + 1], y[3 * j + 2]];
        let (c0, c1, c2) = (col(0), col(1), col(2));
        let mut out = [0.0; 18];
        for i in 0..3 {
            out[i] = A::mul_add(u[2], c1[i], -(u[1] * c2[i]));
            out[3 + i] = A::mul_add(u[0], c2[i], -(u[2] * c0[i]));
            out[6 + i] = A::mul_add(u[1], c0[i], -(u[0] * c1[i]));
            out[9 + i] = c0[i];
        }
        let w = [self.w.x, self.w.y, self.w.z];
        let rtw = |c: [f64; 3]| A::mul_add(c[2], w[2], A::mul_add(c[1], w[1], c[0] * w[0]));
        // m × u + (0, n2, −n1); n × u − Rᵀ w.
        out[12] = A::mul_add(m[1], u[2], -(m[2] * u[1]));
        out[13] = A::mul_add(m[2], u[0], -(m[0] * u[2])) + n[2];
        out[14] = A::mul_add(m[0], u[1], -(m[1] * u[0])) - n[1];
        out[15] = A::mul_add(n[1], u[2], -(n[2] * u[1])) - rtw(c0);
        out[16] = A::mul_add(n[2], u[0], -(n[0] * u[2])) - rtw(c1);
        out[17] = A::mul_add(n[0], u[1], -(n[1] * u[0])) - rtw(c2);
        (out, u)
    }

    /// The shape system's rate.
    #[inline(always)]
    pub fn shape_rate<A: MulAdd>(&self, y: &LoadedShapeArray, out: &mut LoadedShapeArray) {
        *out = self.shape_part::<A>(y).0;
    }

    /// The full system's rate: the shape part, `M_m' = (m̂ C⁻¹ − û) M_m − ê1 M_n` with the
    /// closed form `M_n = [0, Rᵀ] + n̂ J_ω`, and `J' = G M + H J`, i.e. `J_ω' = C⁻¹ M_m − û J_ω`,
    /// `J_v' = −ê1 J_ω − û J_v` (see [`crate::load`] and the module docs), on the rows
    /// `a_i` of `M_m`, `t_i` of `J_ω` and `b_i` of `J_v`. With `K = m̂ C⁻¹ − û` (zero
    /// diagonal), and `ê1 X` being `X`'s rows `(0, −x_2, x_1)`, `M_n`'s rows 1 and 2
    /// `(0, R_·1) + n2 t_0 − n0 t_2` and `(0, R_·2) − n1 t_0 + n0 t_1`:
    ///
    /// ```text
    /// a_0' = K01 a_1 + K02 a_2
    /// a_1' = K10 a_0 + K12 a_2 + (0, R_·2) − n1 t_0 + n0 t_1
    /// a_2' = K20 a_0 + K21 a_1 − (0, R_·1) − n2 t_0 + n0 t_2
    /// t_i' = c_i⁻¹ a_i + (t × u)_i          (−û t = t × u, over the rows)
    /// b_0' = u2 b_1 − u1 b_2,  b_1' = t_2 + u0 b_2 − u2 b_0,  b_2' = −t_1 + u1 b_0 − u0 b_1
    /// ```
    #[inline(always)]
    pub fn full_rate<A: MulAdd>(&self, y: &LoadedFullArray, out: &mut LoadedFullArray) {
        let (d, u) = self.shape_part::<A>(y);
        for i in 0..4 {
            V4::load(&d, 4 * i).store(out, 4 * i);
        }
        V4([d[16], d[17], y[9], y[10]]).store(out, 16);
        V4([y[11], 0.0, 0.0, 0.0]).store(out, 20);
        let ic = [self.inv_c.x, self.inv_c.y, self.inv_c.z];
        let (m, n) = ([y[12], y[13], y[14]], [y[15], y[16], y[17]]);
        // Row k (0–8: a, t, b) as its columns 0–3 and 4–5.
        let row = |k: usize| (V4::load(y, LEFT + 4 * k), V2::load(y, RIGHT + 2 * k));
        let rows: [(V4, V2); 9] = std::array::from_fn(row);
        let (a, t, b) = (&rows[0..3], &rows[3..6], &rows[6..9]);
        let axpy = |s: f64, x: &(V4, V2), acc: (V4, V2)| {
            (x.0.scale_add::<A>(s, acc.0), x.1.scale_add::<A>(s, acc.1))
        };
        let times = |s: f64, x: &(V4, V2)| (x.0.scale(s), x.1.scale(s));
        let mut right = [V2([0.0; 2]); 10];
        let mut store = |k: usize, v: (V4, V2)| {
            v.0.store(out, LEFT + 4 * k);
            right[k] = v.1;
        };
        // K = m̂ C⁻¹ − û, off the diagonal.
        let k01 = A::mul_add(-m[2], ic[1], u[2]);
        let k02 = A::mul_add(m[1], ic[2], -u[1]);
        let k10 = A::mul_add(m[2], ic[0], -u[2]);
        let k12 = A::mul_add(-m[0], ic[2], u[0]);
        let k20 = A::mul_add(-m[1], ic[0], u[1]);
        let k21 = A::mul_add(m[0], ic[1], -u[0]);
        store(0, axpy(k02, &a[2], times(k01, &a[1])));
        let base1 = (V4([0.0, 0.0, 0.0, y[6]]), V2([y[7], y[8]]));
        let a1 = axpy(k12, &a[2], axpy(k10, &a[0], base1));
        store(1, axpy(n[0], &t[1], axpy(-n[1], &t[0], a1)));
        let base2 = (V4([0.0, 0.0, 0.0, -y[3]]), V2([-y[4], -y[5]]));
        let a2 = axpy(k21, &a[1], axpy(k20, &a[0], base2));
        store(2, axpy(n[0], &t[2], axpy(-n[2], &t[0], a2)));
        // t × u over the rows: (u2 t_1 − u1 t_2, u0 t_2 − u2 t_0, u1 t_0 − u0 t_1).
        let cross = |x: &[(V4, V2)], i: usize| {
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            axpy(-u[i1], &x[i2], times(u[i2], &x[i1]))
        };
        for i in 0..3 {
            store(3 + i, axpy(ic[i], &a[i], cross(t, i)));
        }
        store(6, cross(b, 0));
        store(7, axpy(1.0, &t[2], cross(b, 1)));
        store(8, axpy(-1.0, &t[1], cross(b, 2)));
        for (pair, r) in right.chunks_exact(2).enumerate() {
            let (x, y) = (r[0].0, r[1].0);
            V4([x[0], x[1], y[0], y[1]]).store(out, RIGHT + 4 * pair);
        }
    }

    /// Integrates the full system over the grid of `steps` steps of `h`, tracking `det J`;
    /// pushes the shape part at `t = 0` and at every grid point into `knots` if given, and stops
    /// at the first sign change if `early_exit`. AVX2+FMA when the CPU has it.
    pub fn integrate_full(
        &self,
        integrator: &Integrator,
        h: f64,
        steps: usize,
        knots: Option<&mut Vec<LoadedKnotArray>>,
        record_det: bool,
        early_exit: bool,
    ) -> (LoadedFullArray, SignTracker<FULL>) {
        #[cfg(target_arch = "x86_64")]
        if crate::arith::fast_path() {
            // SAFETY: `fast_path` has checked that this CPU supports AVX2 and FMA, the only
            // requirement of the `#[target_feature]` function.
            #[allow(unsafe_code)]
            return unsafe {
                self.integrate_full_fma(integrator, h, steps, knots, record_det, early_exit)
            };
        }
        self.integrate_full_with::<Separate>(integrator, h, steps, knots, record_det, early_exit)
    }

    /// [`Loaded::integrate_full`] compiled for AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn integrate_full_fma(
        &self,
        integrator: &Integrator,
        h: f64,
        steps: usize,
        knots: Option<&mut Vec<LoadedKnotArray>>,
        record_det: bool,
        early_exit: bool,
    ) -> (LoadedFullArray, SignTracker<FULL>) {
        self.integrate_full_with::<crate::arith::Fused>(
            integrator, h, steps, knots, record_det, early_exit,
        )
    }

    #[inline(always)]
    fn integrate_full_with<A: MulAdd>(
        &self,
        integrator: &Integrator,
        h: f64,
        steps: usize,
        mut knots: Option<&mut Vec<LoadedKnotArray>>,
        record_det: bool,
        early_exit: bool,
    ) -> (LoadedFullArray, SignTracker<FULL>) {
        let mut tracker = SignTracker::new(h, steps, record_det);
        let mut y = self.full_initial();
        if let Some(k) = knots.as_deref_mut() {
            k.push(knot_of(&y));
        }
        let f = Rate::<A, FULL> {
            model: self,
            arith: PhantomData,
        };
        let mut work = Workspace::new();
        for (step, grid_point) in integrator.grid(h, steps) {
            integrator.step_in_place::<A, FULL>(&mut y, step, f, &mut work);
            if let Some(index) = grid_point {
                if let Some(k) = knots.as_deref_mut() {
                    k.push(knot_of(&y));
                }
                let stable = tracker.push(index, &y, self);
                if !stable && early_exit {
                    break;
                }
            }
        }
        (y, tracker)
    }

    /// Integrates the shape system over the grid, pushing the state at `t = 0` and at every
    /// grid point into `knots`. AVX2+FMA when the CPU has it.
    pub fn integrate_shape(
        &self,
        integrator: &Integrator,
        h: f64,
        steps: usize,
        knots: &mut Vec<LoadedShapeArray>,
    ) {
        #[cfg(target_arch = "x86_64")]
        if crate::arith::fast_path() {
            // SAFETY: as in `integrate_full`.
            #[allow(unsafe_code)]
            return unsafe { self.integrate_shape_fma(integrator, h, steps, knots) };
        }
        self.integrate_shape_with::<Separate>(integrator, h, steps, knots);
    }

    /// [`Loaded::integrate_shape`] compiled for AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn integrate_shape_fma(
        &self,
        integrator: &Integrator,
        h: f64,
        steps: usize,
        knots: &mut Vec<LoadedShapeArray>,
    ) {
        self.integrate_shape_with::<crate::arith::Fused>(integrator, h, steps, knots);
    }

    #[inline(always)]
    fn integrate_shape_with<A: MulAdd>(
        &self,
        integrator: &Integrator,
        h: f64,
        steps: usize,
        knots: &mut Vec<LoadedShapeArray>,
    ) {
        let mut y = self.shape_initial();
        knots.push(y);
        let f = Rate::<A, 18> {
            model: self,
            arith: PhantomData,
        };
        let mut work = Workspace::new();
        for (step, grid_point) in integrator.grid(h, steps) {
            integrator.step_in_place::<A, 18>(&mut y, step, f, &mut work);
            if grid_point.is_some() {
                knots.push(y);
            }
        }
    }

    /// `q, q', q'', q'''` at a state (its first 18 numbers), as flat frame states by rows
    /// (`FrameJet`, the unloaded solver's layout): `R' = R û`, `R'' = R (û² + û')`,
    /// `R''' = R (û³ + 2 û û' + û' û + û'')`, `p⁽ᵏ⁺¹⁾ = R⁽ᵏ⁾ e1`, with `u' = C⁻¹ m'` and
    /// `u'' = C⁻¹ (m' × u + m × u' + n' × e1)` from the loaded `m'`, `n'`; the rows by the
    /// unloaded solver's `kirchhoff::jet_of_strains`.
    pub fn jet(&self, y: &[f64]) -> FrameJet {
        let l = self.local(y);
        let times_e1 = |v: &Vector3<f64>| Vector3::new(0.0, v.z, -v.y);
        let dm = l.m.cross(&l.u) + times_e1(&l.n);
        let dn = l.n.cross(&l.u) - l.r.tr_mul(&self.w);
        let du = self.inv_c.component_mul(&dm);
        let ddm = dm.cross(&l.u) + l.m.cross(&du) + times_e1(&dn);
        let ddu = self.inv_c.component_mul(&ddm);
        let lanes = |v: Vector3<f64>| V4([v.x, v.y, v.z, 0.0]);
        let frame: FrameArray = std::array::from_fn(|k| {
            let (i, j) = (k / 4, k % 4);
            y[3 * j + i]
        });
        let rows = [0, 1, 2].map(|i| V4::load(&frame, 4 * i));
        let strains = [lanes(l.u), lanes(du), lanes(ddu)];
        jet_of_strains(&frame, &rows, strains, self.e3)
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
    let rows = matrix_rows(y);
    let block = |k: usize| Matrix3x6::from_fn(|i, j| rows[k + i][j]);
    let mut m = Matrix6::zeros();
    m.fixed_rows_mut::<3>(0).copy_from(&block(0));
    m.fixed_rows_mut::<3>(3).copy_from(&(hat(&n) * block(3)));
    let mut force_block = m.fixed_view_mut::<3, 3>(3, 3);
    force_block += r.transpose();
    m
}

/// `J` of a full state.
pub(crate) fn jacobian_of(y: &LoadedFullArray) -> Matrix6<f64> {
    let rows = jacobian_rows(y);
    Matrix6::from_fn(|i, j| rows[i][j])
}

/// The nine rows of `M_m`, `J_ω` and `J_v` of a full state.
fn matrix_rows(y: &LoadedFullArray) -> [[f64; 6]; 9] {
    std::array::from_fn(|k| {
        std::array::from_fn(|c| {
            if c < 4 {
                y[LEFT + 4 * k + c]
            } else {
                y[RIGHT + 2 * k + c - 4]
            }
        })
    })
}

/// The rows of `J` of a full state.
fn jacobian_rows(y: &LoadedFullArray) -> [[f64; 6]; 6] {
    let rows = matrix_rows(y);
    std::array::from_fn(|r| rows[3 + r])
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
        tracker: SignTracker<FULL>,
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
        // intervals as the frames (the walk of `rod::shape::from_knots_with`).
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

#[cfg(test)]
mod tests {
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::WireParams;
    use crate::sampling::Sampler;

    /// The largest `|x − y|` over two states, relative to the largest entry of `y` (at least 1).
    fn relative_difference(x: &[f64], y: &[f64]) -> f64 {
        let scale = y.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        x.iter()
            .zip(y)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs() / scale))
    }

    /// The dispatched loops (AVX2+FMA on a CPU that has them) and the portable ones agree to
    /// rounding, as the unloaded solver's (`rod::tests::fast_and_portable_paths_agree`):
    /// the full state (frame, `μ`, `∫p`, `M_m`, `J`), every knot, and the stability record,
    /// and the shape system's knots, within 1e-12 of the largest entry, under random weights
    /// and rest strains on a round and an anisotropic wire. (On a CPU without AVX2 and FMA,
    /// or with `FTWIRE_NO_SIMD` set, both sides are the portable loops, and the test says
    /// so.)
    #[test]
    fn fast_and_portable_paths_agree() {
        if !crate::arith::fast_path() {
            eprintln!("fast_and_portable_paths_agree: no AVX2+FMA path here, both sides portable");
        }
        let wires = [
            WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid"),
            WireParams::new([1.3, 1.0, 0.6], 1.0, 0.001).expect("valid"),
        ];
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let sampler = Sampler::default();
        let mut worst = 0.0f64;
        for wire in wires.into_iter().flat_map(|w| std::iter::repeat_n(w, 40)) {
            let gravity = Vector3::from_fn(|_, _| rng.random_range(-9.81..9.81));
            let kappa = Vector3::from_fn(|_, _| rng.random_range(-2.0..2.0));
            let load = Load::from_gravity(6450.0, wire.radius(), gravity)
                .expect("valid")
                .with_natural_curvature(kappa)
                .expect("finite");
            let rod = Rod::new(wire).with_load(load);
            let a = sampler.sample_a(&rod, &mut rng);
            let (model, h, steps) = rod.loaded_model(&a).expect("in A");
            let integrator = rod.integrator();
            let (mut k_fast, mut k_plain) = (Vec::new(), Vec::new());
            let (y_fast, t_fast) =
                model.integrate_full(integrator, h, steps, Some(&mut k_fast), true, false);
            let (y_plain, t_plain) = model.integrate_full_with::<Separate>(
                integrator,
                h,
                steps,
                Some(&mut k_plain),
                true,
                false,
            );
            let mut difference = relative_difference(&y_fast, &y_plain);
            assert_eq!(k_fast.len(), k_plain.len());
            for (f, p) in k_fast.iter().zip(&k_plain) {
                difference = difference.max(relative_difference(f, p));
            }
            let (s_fast, s_plain) = (t_fast.finish(), t_plain.finish());
            assert_eq!(s_fast.stable, s_plain.stable, "a = {a}");
            assert_eq!(s_fast.det_j.len(), s_plain.det_j.len());
            let (mut kf, mut kp) = (Vec::new(), Vec::new());
            model.integrate_shape(integrator, h, steps, &mut kf);
            model.integrate_shape_with::<Separate>(integrator, h, steps, &mut kp);
            assert_eq!(kf.len(), kp.len());
            for (f, p) in kf.iter().zip(&kp) {
                difference = difference.max(relative_difference(f, p));
            }
            assert!(difference <= 1e-12, "a = {a}, {load:?}: {difference:e}");
            worst = worst.max(difference);
        }
        eprintln!("loaded fast vs portable: worst {worst:.1e} of the largest entry");
    }
}
