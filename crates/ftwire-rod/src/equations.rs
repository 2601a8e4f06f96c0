//! The equations of the Kirchhoff wire (paper §II-A, eq. 1, 3, 4; Bretl & McCarthy 2014).
//!
//! Conventions (DESIGN.md "The model"): `q(t) = (R(t), p(t))` is the wire frame at arc length
//! `t` relative to the base clamp, `q(0) = I`, x axis along the tangent; `μ(t) = (m, n)` is the
//! internal wrench (torque first) in the body frame; `u = (μ1/c1, μ2/c2, μ3/c3)`.
//!
//! # Closed forms used by the solver (derived here, checked by tests)
//!
//! The wrench is constant in the base frame (`n' = 0`, `m' + p' × n = 0` there), so with
//! `a = (m0, n0)`:
//!
//! ```text
//! μ(t) = Ad_{q(t)}ᵀ a = ( Rᵀ (m0 − p × n0),  Rᵀ n0 )                          (A)
//! ```
//!
//! which satisfies eq. 3 identically. Perturbing `a` moves `q` to `q exp(ĵ)` with `j = J δa`,
//! and differentiating (A) gives `M(t) = ∂μ(t)/∂a` algebraically:
//!
//! ```text
//! M(t) = Ad_{q(t)}ᵀ + K(μ(t)) J(t),   K(m, n) = [[m̂, n̂], [n̂, 0]]                (B)
//! ```
//!
//! so the solver integrates only `q` and `J` (eq. 1 and `J' = G M + H J` of eq. 4), 48 states
//! instead of 90, and never `μ` or `M`. Tests check (A) and (B) against an independent
//! integration of the full system (eq. 3 and `M' = F M`) and `J` against finite differences.

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

use crate::arith::MulAdd;
use crate::se3::hat;

/// The right-hand side of the costate ODE, paper eq. 3: `μ'` for stiffnesses `c` \[N·m²\].
///
/// # Example
/// ```
/// use nalgebra::Vector6;
/// // A pure force along the tangent (a straight wire under tension) is an equilibrium.
/// let rate = ftwire_rod::costate_rate([1.0, 2.0, 3.0], &Vector6::new(0.0, 0.0, 0.0, 1.0, 0.0, 0.0));
/// assert_eq!(rate, Vector6::zeros());
/// ```
pub fn costate_rate(c: [f64; 3], mu: &Vector6<f64>) -> Vector6<f64> {
    let u = [mu[0] / c[0], mu[1] / c[1], mu[2] / c[2]];
    Vector6::new(
        u[2] * mu[1] - u[1] * mu[2],
        mu[5] + u[0] * mu[2] - u[2] * mu[0],
        -mu[4] + u[1] * mu[0] - u[0] * mu[1],
        u[2] * mu[4] - u[1] * mu[5],
        u[0] * mu[5] - u[2] * mu[3],
        u[1] * mu[3] - u[0] * mu[4],
    )
}

/// `F(μ) = ∂μ'/∂μ` of paper eq. 4 (DESIGN.md lists it entry by entry).
pub fn f_matrix(c: [f64; 3], mu: &Vector6<f64>) -> Matrix6<f64> {
    let [c1, c2, c3] = c;
    let m = mu;
    let (d32, d13, d21) = (
        1.0 / c3 - 1.0 / c2,
        1.0 / c1 - 1.0 / c3,
        1.0 / c2 - 1.0 / c1,
    );
    Matrix6::from_row_slice(&[
        0.0,
        d32 * m[2],
        d32 * m[1],
        0.0,
        0.0,
        0.0, //
        d13 * m[2],
        0.0,
        d13 * m[0],
        0.0,
        0.0,
        1.0, //
        d21 * m[1],
        d21 * m[0],
        0.0,
        0.0,
        -1.0,
        0.0, //
        0.0,
        -m[5] / c2,
        m[4] / c3,
        0.0,
        m[2] / c3,
        -m[1] / c2, //
        m[5] / c1,
        0.0,
        -m[3] / c3,
        -m[2] / c3,
        0.0,
        m[0] / c1, //
        -m[4] / c1,
        m[3] / c2,
        0.0,
        m[1] / c2,
        -m[0] / c1,
        0.0,
    ])
}

/// `G = [[diag(1/c1, 1/c2, 1/c3), 0], [0, 0]]` of paper eq. 4.
pub fn g_matrix(c: [f64; 3]) -> Matrix6<f64> {
    let mut g = Matrix6::zeros();
    for (i, ci) in c.iter().enumerate() {
        g[(i, i)] = 1.0 / ci;
    }
    g
}

/// `H(μ) = −ad_ξ` of paper eq. 4 for the body twist `ξ = (u, e1)`.
pub fn h_matrix(c: [f64; 3], mu: &Vector6<f64>) -> Matrix6<f64> {
    let xi = Vector6::new(mu[0] / c[0], mu[1] / c[1], mu[2] / c[2], 1.0, 0.0, 0.0);
    -crate::se3::ad(&xi)
}

/// `M(t) = ∂μ(t)/∂a` from the frame, costate and Jacobian at `t`, by the closed form (B) of
/// this module: `M = Ad_qᵀ + [[m̂, n̂], [n̂, 0]] J`.
pub fn m_matrix(q: &ftwire_core::Pose, mu: &Vector6<f64>, j: &Matrix6<f64>) -> Matrix6<f64> {
    let mut k = Matrix6::zeros();
    let mh = hat(&mu.fixed_rows::<3>(0).into_owned());
    let nh = hat(&mu.fixed_rows::<3>(3).into_owned());
    k.fixed_view_mut::<3, 3>(0, 0).copy_from(&mh);
    k.fixed_view_mut::<3, 3>(0, 3).copy_from(&nh);
    k.fixed_view_mut::<3, 3>(3, 0).copy_from(&nh);
    crate::se3::adjoint(q).transpose() + k * j
}

/// An a-priori bound `σ` \[1/m\] on how fast the solution turns: the larger of the
/// curvature bound and the load wavenumber,
///
/// ```text
/// |u(t)| ≤ √(2 (H + |n|) / c_min),   H = ½ Σ μi²/ci + μ4 (conserved),   and   √(|n| / c_min),
/// ```
///
/// both constant along the wire (`½ Σ μi²/ci = H − μ4 ≤ H + |n|`). The adaptive integrator
/// takes steps in proportion to `σ L`.
///
/// # Example
/// ```
/// use nalgebra::Vector6;
/// // Pure bending: the bound is the exact curvature τ / c3.
/// let s = ftwire_rod::equations::turning_scale([1.0, 1.0, 0.5], &Vector6::new(0.0, 0.0, 2.0, 0.0, 0.0, 0.0));
/// assert!((s - 4.0).abs() < 1e-12);
/// ```
pub fn turning_scale(c: [f64; 3], a: &Vector6<f64>) -> f64 {
    let c_min = c[0].min(c[1]).min(c[2]);
    let h = 0.5 * (a[0] * a[0] / c[0] + a[1] * a[1] / c[1] + a[2] * a[2] / c[2]) + a[3];
    let n = (a[3] * a[3] + a[4] * a[4] + a[5] * a[5]).sqrt();
    let curvature = (2.0 * (h + n).max(0.0) / c_min).sqrt();
    curvature.max((n / c_min).sqrt())
}

/// The frame part of the state: `q = (R, p)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FrameState {
    pub r: Matrix3<f64>,
    pub p: Vector3<f64>,
}

/// The flat integration state of the frame: `R` column-major (9), then `p` (3).
pub(crate) type FrameArray = [f64; 12];
/// The flat integration state of frame and Jacobian: the frame's 12 numbers, then the six rows
/// of `J` (angular rows first), each row's 6 numbers contiguous.
pub(crate) type FullArray = [f64; 48];

const JT: usize = 12;
const JB: usize = 30;

impl FrameState {
    /// The frame of a flat state (its first 12 numbers).
    pub fn from_slice(y: &[f64]) -> Self {
        Self {
            r: Matrix3::from_column_slice(&y[0..9]),
            p: Vector3::new(y[9], y[10], y[11]),
        }
    }

    /// The initial flat state `q = I` (and `J = 0`).
    pub fn initial<const D: usize>() -> [f64; D] {
        let mut y = [0.0; D];
        y[0] = 1.0;
        y[4] = 1.0;
        y[8] = 1.0;
        y
    }
}

/// `J` from a flat full state.
pub(crate) fn jacobian_of(y: &FullArray) -> Matrix6<f64> {
    Matrix6::from_fn(|row, col| {
        if row < 3 {
            y[JT + 6 * row + col]
        } else {
            y[JB + 6 * (row - 3) + col]
        }
    })
}

/// `det J` from a flat full state, by Gaussian elimination with partial pivoting on the rows
/// of `J` (as nalgebra's LU, without building a `Matrix6`).
pub(crate) fn jacobian_determinant(y: &FullArray) -> f64 {
    let mut a = [[0.0; 6]; 6];
    for (r, row) in a.iter_mut().enumerate() {
        row.copy_from_slice(&y[JT + 6 * r..JT + 6 * r + 6]);
    }
    determinant6(a)
}

/// The determinant of a 6×6 matrix given by rows (Gaussian elimination, partial pivoting).
pub(crate) fn determinant6(mut a: [[f64; 6]; 6]) -> f64 {
    let mut det = 1.0;
    for c in 0..6 {
        let mut p = c;
        for r in c + 1..6 {
            if a[r][c].abs() > a[p][c].abs() {
                p = r;
            }
        }
        if p != c {
            a.swap(p, c);
            det = -det;
        }
        let pivot = a[c][c];
        det *= pivot;
        if pivot == 0.0 {
            return det;
        }
        let (top, rest) = a.split_at_mut(c + 1);
        let prow = &top[c];
        for row in rest.iter_mut() {
            let factor = row[c] / pivot;
            for k in c + 1..6 {
                row[k] -= factor * prow[k];
            }
        }
    }
    det
}

#[inline(always)]
fn v3(y: &[f64], i: usize) -> [f64; 3] {
    [y[i], y[i + 1], y[i + 2]]
}

#[inline(always)]
fn dot<A: MulAdd>(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    A::mul_add(a[2], b[2], A::mul_add(a[1], b[1], a[0] * b[0]))
}

#[inline(always)]
fn cross<A: MulAdd>(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        A::mul_add(a[1], b[2], -(a[2] * b[1])),
        A::mul_add(a[2], b[0], -(a[0] * b[2])),
        A::mul_add(a[0], b[1], -(a[1] * b[0])),
    ]
}

/// What the right-hand sides share: the columns of `R`, `p`, `μ = (m, n)` by closed form (A),
/// and `u`.
struct Local {
    c: [[f64; 3]; 3],
    p: [f64; 3],
    m: [f64; 3],
    n: [f64; 3],
    u: [f64; 3],
}

/// [`Kirchhoff::full_rate`] as an [`crate::integrator::Rhs`], multiply–adding with `A`.
#[derive(Debug)]
pub(crate) struct FullRhs<'a, A> {
    pub model: &'a Kirchhoff,
    pub arith: std::marker::PhantomData<A>,
}

/// [`Kirchhoff::frame_rate`] as an [`crate::integrator::Rhs`], multiply–adding with `A`.
#[derive(Debug)]
pub(crate) struct FrameRhs<'a, A> {
    pub model: &'a Kirchhoff,
    pub arith: std::marker::PhantomData<A>,
}

// Manual impls: derives would require `A: Copy`.
impl<A> Clone for FullRhs<'_, A> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<A> Copy for FullRhs<'_, A> {}
impl<A> Clone for FrameRhs<'_, A> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<A> Copy for FrameRhs<'_, A> {}

impl<A: MulAdd> crate::integrator::Rhs<48> for FullRhs<'_, A> {
    #[inline(always)]
    fn rate(&self, y: &FullArray, out: &mut FullArray) {
        self.model.full_rate::<A>(y, out);
    }
}

impl<A: MulAdd> crate::integrator::Rhs<12> for FrameRhs<'_, A> {
    #[inline(always)]
    fn rate(&self, y: &FrameArray, out: &mut FrameArray) {
        self.model.frame_rate::<A>(y, out);
    }
}

/// Frame derivatives up to second order at one point, for Hermite dense output.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrameJet {
    pub frame: FrameState,
    pub d1: FrameState,
    pub d2: FrameState,
    pub d3: FrameState,
}

/// The right-hand sides for one configuration `a` and stiffnesses `c`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Kirchhoff {
    c: [f64; 3],
    inv_c: Vector3<f64>,
    m0: Vector3<f64>,
    n0: Vector3<f64>,
}

impl Kirchhoff {
    pub fn new(c: [f64; 3], a: &Vector6<f64>) -> Self {
        Self {
            c,
            inv_c: Vector3::new(1.0 / c[0], 1.0 / c[1], 1.0 / c[2]),
            m0: Vector3::new(a[0], a[1], a[2]),
            n0: Vector3::new(a[3], a[4], a[5]),
        }
    }

    /// [`turning_scale`] of this configuration.
    pub fn turning_scale(&self) -> f64 {
        let a = Vector6::new(
            self.m0.x, self.m0.y, self.m0.z, self.n0.x, self.n0.y, self.n0.z,
        );
        turning_scale(self.c, &a)
    }

    /// `μ = Ad_qᵀ a` (closed form (A)), as `(m, n)`.
    #[inline(always)]
    pub fn costate(&self, q: &FrameState) -> (Vector3<f64>, Vector3<f64>) {
        let mw = self.m0 - q.p.cross(&self.n0);
        (q.r.tr_mul(&mw), q.r.tr_mul(&self.n0))
    }

    /// `μ` as a 6-vector.
    #[inline]
    pub fn costate6(&self, q: &FrameState) -> Vector6<f64> {
        let (m, n) = self.costate(q);
        Vector6::new(m.x, m.y, m.z, n.x, n.y, n.z)
    }

    #[inline(always)]
    fn local<A: MulAdd>(&self, y: &[f64]) -> Local {
        let c = [v3(y, 0), v3(y, 3), v3(y, 6)];
        let p = v3(y, 9);
        let n0 = [self.n0.x, self.n0.y, self.n0.z];
        let pn = cross::<A>(&p, &n0);
        let mw = [self.m0.x - pn[0], self.m0.y - pn[1], self.m0.z - pn[2]];
        let m = [
            dot::<A>(&c[0], &mw),
            dot::<A>(&c[1], &mw),
            dot::<A>(&c[2], &mw),
        ];
        let n = [
            dot::<A>(&c[0], &n0),
            dot::<A>(&c[1], &n0),
            dot::<A>(&c[2], &n0),
        ];
        let u = [
            m[0] * self.inv_c.x,
            m[1] * self.inv_c.y,
            m[2] * self.inv_c.z,
        ];
        Local { c, p, m, n, u }
    }

    /// Eq. 1 for `R` and `p` from the local quantities, into `out[0..12]`.
    #[inline(always)]
    fn frame_part<A: MulAdd>(l: &Local, out: &mut [f64]) {
        let [c0, c1, c2] = &l.c;
        let u = &l.u;
        for i in 0..3 {
            // R û: columns u_z c1 − u_y c2, −u_z c0 + u_x c2, u_y c0 − u_x c1.
            out[i] = A::mul_add(u[2], c1[i], -(u[1] * c2[i]));
            out[3 + i] = A::mul_add(u[0], c2[i], -(u[2] * c0[i]));
            out[6 + i] = A::mul_add(u[1], c0[i], -(u[0] * c1[i]));
            out[9 + i] = c0[i];
        }
    }

    /// Eq. 1: `R' = R û`, `p' = R e1`, on the flat frame state.
    #[inline(always)]
    pub fn frame_rate<A: MulAdd>(&self, y: &FrameArray, out: &mut FrameArray) {
        let l = self.local::<A>(y);
        Self::frame_part::<A>(&l, out);
    }

    /// Eq. 1 and `J' = G M + H J` (eq. 4) with `M` from closed form (B), on the flat full
    /// state: `J'_top = C⁻¹ ([Rᵀ, −Rᵀ p̂] + m̂ J_top + n̂ J_bot) − û J_top` and
    /// `J'_bot = −ê1 J_top − û J_bot`.
    ///
    /// Written on the rows of `J` (6 numbers each, contiguous): with `P = C⁻¹ m̂ − û` and
    /// `Q = C⁻¹ n̂` (both with zero diagonal), row `i` of `J'_top` is
    /// `c_i⁻¹ (Rᵀ e_i, p × R e_i) + Σ_k P_ik J_top,k + Σ_k Q_ik J_bot,k`, so the whole update
    /// is scalar-times-row sums that vectorise (`Rᵀ p̂` row `i` is `−(R e_i × p)ᵀ`).
    #[inline(always)]
    pub fn full_rate<A: MulAdd>(&self, y: &FullArray, out: &mut FullArray) {
        let l = self.local::<A>(y);
        Self::frame_part::<A>(&l, out);
        let ic = [self.inv_c.x, self.inv_c.y, self.inv_c.z];
        let (m, n, u) = (&l.m, &l.n, &l.u);
        let row = |r: usize| -> [f64; 6] {
            let mut v = [0.0; 6];
            v.copy_from_slice(&y[JT + 6 * r..JT + 6 * r + 6]);
            v
        };
        let (t0, t1, t2) = (row(0), row(1), row(2));
        let (b0, b1, b2) = (row(3), row(4), row(5));
        // `ic_i (Rᵀ e_i, p × R e_i)`: row i of C⁻¹ [Rᵀ, −Rᵀ p̂].
        let base = |i: usize| -> [f64; 6] {
            let ci = &l.c[i];
            let pc = cross::<A>(&l.p, ci);
            [
                ic[i] * ci[0],
                ic[i] * ci[1],
                ic[i] * ci[2],
                ic[i] * pc[0],
                ic[i] * pc[1],
                ic[i] * pc[2],
            ]
        };
        // Row i of J'_top: base_i + Σ_k P_ik t_k + Σ_k Q_ik b_k with the off-diagonal entries
        // of P = C⁻¹ m̂ − û and Q = C⁻¹ n̂ (both have zero diagonals).
        let combine = |base: [f64; 6], x: [(f64, &[f64; 6]); 4]| -> [f64; 6] {
            let mut v = base;
            for (s, r) in x {
                for col in 0..6 {
                    v[col] = A::mul_add(s, r[col], v[col]);
                }
            }
            v
        };
        let o0 = combine(
            base(0),
            [
                (u[2] - ic[0] * m[2], &t1),
                (ic[0] * m[1] - u[1], &t2),
                (-ic[0] * n[2], &b1),
                (ic[0] * n[1], &b2),
            ],
        );
        let o1 = combine(
            base(1),
            [
                (ic[1] * m[2] - u[2], &t0),
                (u[0] - ic[1] * m[0], &t2),
                (ic[1] * n[2], &b0),
                (-ic[1] * n[0], &b2),
            ],
        );
        let o2 = combine(
            base(2),
            [
                (u[1] - ic[2] * m[1], &t0),
                (ic[2] * m[0] - u[0], &t1),
                (-ic[2] * n[1], &b0),
                (ic[2] * n[0], &b1),
            ],
        );
        // J'_bot = −ê1 J_top − û J_bot: −ê1 v = (0, v_z, −v_y); −û v = v × u.
        let mut o3 = [0.0; 6];
        let mut o4 = [0.0; 6];
        let mut o5 = [0.0; 6];
        for col in 0..6 {
            o3[col] = A::mul_add(u[2], b1[col], -(u[1] * b2[col]));
            o4[col] = A::mul_add(u[0], b2[col], A::mul_add(-u[2], b0[col], t2[col]));
            o5[col] = A::mul_add(-u[0], b1[col], A::mul_add(u[1], b0[col], -t1[col]));
        }
        for (r, o) in [o0, o1, o2, o3, o4, o5].iter().enumerate() {
            out[JT + 6 * r..JT + 6 * r + 6].copy_from_slice(o);
        }
    }

    /// `q, q', q'', q'''` at one point: `R'' = R (û² + û')`, `p'' = R û e1`,
    /// `R''' = R (û³ + 2 û û' + û' û + û'')`, `p''' = R (û² + û') e1`, with `u'` from eq. 3 and
    /// `u''` from `μ'' = F(μ) μ'` (eq. 4's `F`).
    #[inline(always)]
    pub fn frame_jet(&self, q: &FrameState) -> FrameJet {
        let mu = self.costate6(q);
        let dmu = costate_rate(self.c, &mu);
        // The top rows of F(μ) μ' (see `f_matrix`): only u'' is needed.
        let [c1, c2, c3] = self.c;
        let (d32, d13, d21) = (
            1.0 / c3 - 1.0 / c2,
            1.0 / c1 - 1.0 / c3,
            1.0 / c2 - 1.0 / c1,
        );
        let (m, v) = (&mu, &dmu);
        let ddm = Vector3::new(
            d32 * (m[2] * v[1] + m[1] * v[2]),
            d13 * (m[2] * v[0] + m[0] * v[2]) + v[5],
            d21 * (m[1] * v[0] + m[0] * v[1]) - v[4],
        );
        let u = mu.fixed_rows::<3>(0).component_mul(&self.inv_c);
        let du = dmu.fixed_rows::<3>(0).component_mul(&self.inv_c);
        let ddu = ddm.component_mul(&self.inv_c);
        let uh = hat(&u);
        let duh = hat(&du);
        let uu = uh * uh;
        let second = uu + duh;
        let uduh = uh * duh;
        let third = uu * uh + uduh + uduh + duh * uh + hat(&ddu);
        FrameJet {
            frame: *q,
            d1: FrameState {
                r: q.r * uh,
                p: q.r.column(0).into_owned(),
            },
            d2: FrameState {
                r: q.r * second,
                p: q.r * Vector3::new(0.0, u.z, -u.y),
            },
            d3: FrameState {
                r: q.r * third,
                p: q.r * second.column(0),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arith::Separate;

    /// The jet's second and third derivatives are the central differences of the lower ones
    /// along the solution.
    #[test]
    fn frame_jet_matches_finite_differences() {
        let model = Kirchhoff::new(
            [1.3, 1.0, 0.6],
            &Vector6::new(0.3, -0.7, 1.2, -2.0, 1.5, 0.4),
        );
        let integ = crate::Integrator::new(crate::Method::Rk8, 1).expect("valid");
        let f = |s: &FrameArray, o: &mut FrameArray| model.frame_rate::<Separate>(s, o);
        let mut y: FrameArray = FrameState::initial();
        for _ in 0..300 {
            y = integ.step(&y, 1e-3, f);
        }
        let eps = 1e-4;
        let jet = |y: &FrameArray| model.frame_jet(&FrameState::from_slice(y));
        let (j0, jp, jm) = (
            jet(&y),
            jet(&integ.step(&y, eps, f)),
            jet(&integ.step(&y, -eps, f)),
        );
        // max |(a − b) / 2ε − exact| over R and p.
        let error = |a: FrameState, b: FrameState, exact: FrameState| {
            let r = (a.r - b.r) / (2.0 * eps) - exact.r;
            let p = (a.p - b.p) / (2.0 * eps) - exact.p;
            r.amax().max(p.amax())
        };
        assert!(error(jp.d1, jm.d1, j0.d2) < 1e-6, "q''");
        assert!(error(jp.d2, jm.d2, j0.d3) < 1e-6, "q'''");
    }

    /// The elimination determinant agrees with nalgebra's LU on random and singular matrices,
    /// and `jacobian_determinant` reads `J` as `jacobian_of` does.
    #[test]
    fn determinant_matches_nalgebra() {
        let mut x = 0.123_f64;
        let mut next = || {
            x = (x * 997.0 + 0.618).fract();
            2.0 * x - 1.0
        };
        for trial in 0..50 {
            let mut y: FullArray = [0.0; 48];
            for v in y.iter_mut() {
                *v = next();
            }
            if trial % 10 == 0 {
                // Two equal rows: singular.
                let (a, b) = y.split_at_mut(JT + 6);
                b[..6].copy_from_slice(&a[JT..JT + 6]);
            }
            let j = jacobian_of(&y);
            let expected = j.determinant();
            let got = jacobian_determinant(&y);
            assert!(
                (got - expected).abs() <= 1e-12 * (1.0 + expected.abs()),
                "{got} vs {expected}"
            );
        }
    }
}
