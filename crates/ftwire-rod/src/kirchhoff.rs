//! The solver's flat integration states and the hot right-hand sides of eq. 1, 3 and 4 on
//! them ([`Kirchhoff`]), with the closed forms (A) and (B) of [`crate::equations`]: the
//! shape-only solves' `q` and `m` ([`ShapeArray`]), the Jacobian solves' `q` and `J`
//! ([`FullArray`]), and the frame jets for the Hermite dense output.
//!
//! # Layout
//!
//! The flat states are laid out for 4-lane arithmetic (`arith::V4`): the frame by rows
//! `(R_i0, R_i1, R_i2, p_i)`, so that row `i` of `R û` is `r_i × u` and `p_i' = R_i0`; `J` by
//! rows, columns 0–3 then columns 4–5.
//!
//! Guarded by `shape_rate_is_eq_1_and_3` and `frame_jet_matches_finite_differences` below,
//! and by the closed-form and finite-difference tests of `tests/model.rs` through the solver.

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

use crate::arith::{MulAdd, Separate, V2, V4};
use crate::equations::{costate_rate, turning_scale};

/// The frame part of the state: `q = (R, p)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FrameState {
    pub r: Matrix3<f64>,
    pub p: Vector3<f64>,
}

/// The flat integration state of the frame, by rows: row `i` of `R`, then `p_i`, for
/// `i = 0, 1, 2` (`y[4i + j] = R_ij`, `y[4i + 3] = p_i`).
///
/// This layout makes eq. 1 three 4-lane operations: row `i` of `R' = R û` is `r_i × u`, and
/// `p_i' = R_i0` is lane 0 of the same row ([`Kirchhoff::shape_rate`]).
pub(crate) type FrameArray = [f64; 12];
/// The flat integration state of the shape-only solves: the frame's 12 numbers
/// ([`FrameArray`]), then `m = (m1, m2, m3, 0)`.
///
/// Here `m` is integrated by eq. 3 alongside the frame instead of being read from the frame
/// by closed form (A): the frame's rates depend on `u = C⁻¹ m` alone, and `m'` on `m` and
/// `n` only, so the step's longest chain of dependent operations is `m`'s short one (the
/// frame rows run beside it), where closed form (A) puts `Rᵀ (m0 − p × n0)` on it for every
/// stage. `n = Rᵀ n0` is a linear combination of the frame rows, read from them at each stage
/// (integrating it too costs a fifth more work in every stage sum and runs no faster).
pub(crate) type ShapeArray = [f64; 16];
/// The flat integration state of frame and Jacobian: the frame's 12 numbers
/// ([`FrameArray`]), then columns 0–3 of the six rows of `J` (4 numbers a row, angular rows
/// first), then columns 4–5 of the six rows (2 numbers a row).
pub(crate) type FullArray = [f64; 48];

/// Where columns 0–3 of row `i` of `J` start: `JL + 4 i`.
const JL: usize = 12;
/// Where columns 4–5 of row `i` of `J` start: `JR + 2 i`.
const JR: usize = 36;

impl FrameState {
    /// The frame of a flat state (its first 12 numbers).
    pub fn from_slice(y: &[f64]) -> Self {
        Self {
            r: Matrix3::from_fn(|i, j| y[4 * i + j]),
            p: Vector3::new(y[3], y[7], y[11]),
        }
    }

    /// The initial flat state `q = I` (and `J = 0`).
    pub fn initial<const D: usize>() -> [f64; D] {
        let mut y = [0.0; D];
        y[0] = 1.0;
        y[5] = 1.0;
        y[10] = 1.0;
        y
    }
}

/// The initial shape state: `q = I`, `m(0) = (a1, a2, a3)`.
pub(crate) fn shape_initial(a: &Vector6<f64>) -> ShapeArray {
    let mut y: ShapeArray = FrameState::initial();
    y[12..15].copy_from_slice(&[a[0], a[1], a[2]]);
    y
}

/// The frame part (first 12 numbers) of a flat state.
#[inline(always)]
pub(crate) fn frame_of(y: &[f64]) -> FrameArray {
    std::array::from_fn(|i| y[i])
}

/// Row `i` of `J` from a flat full state.
#[inline(always)]
pub(crate) fn jacobian_row(y: &FullArray, i: usize) -> [f64; 6] {
    let (l, r) = (JL + 4 * i, JR + 2 * i);
    [y[l], y[l + 1], y[l + 2], y[l + 3], y[r], y[r + 1]]
}

/// `J` from a flat full state.
pub(crate) fn jacobian_of(y: &FullArray) -> Matrix6<f64> {
    Matrix6::from_fn(|row, col| jacobian_row(y, row)[col])
}

/// `(a × b, a_0)` on the first three lanes of `a` and `b`, given `b` permuted as
/// `b_zxy1 = (b2, b0, b1, 1)` and `b_yzx0 = (b1, b2, b0, 0)`: row `i` of `R û` and
/// `p_i' = R_i0` when `a` is a row `(R_i0, R_i1, R_i2, p_i)` of the frame state and `b = u`.
///
/// (`(a × b)_k = a_{k+1} b_{k+2} − a_{k+2} b_{k+1}`; lane 3 is `a_0 · 1 − a_0 · 0`.)
#[inline(always)]
fn cross_lane0<A: MulAdd>(a: V4, b_zxy1: V4, b_yzx0: V4) -> V4 {
    let a_yzx0 = a.permute([1, 2, 0, 0]);
    let a_zxy0 = a.permute([2, 0, 1, 0]);
    a_yzx0.mul_add::<A>(b_zxy1, a_zxy0.mul(b_yzx0).scale(-1.0))
}

/// `b` permuted for [`cross_lane0`], from `b = (b0, b1, b2, 0)` and `e3 = (0, 0, 0, 1)`:
/// `(b2, b0, b1, 1)` and `(b1, b2, b0, 0)`.
///
/// `e3` and the zero lane 3 of `b` are run-time values (from [`Kirchhoff`]'s fields), so
/// that the compiler keeps all four lanes in one vector operation (with constants in lane 3
/// it splits the lanes into scalar and 2-lane pieces, and the stores that follow defeat
/// store-to-load forwarding).
#[inline(always)]
fn cross_operands(b: V4, e3: V4) -> (V4, V4) {
    (b.permute([2, 0, 1, 3]).add(e3), b.permute([1, 2, 0, 3]))
}

/// What the right-hand sides share: the rows of the frame state, `p`, `μ = (m, n)` by closed
/// form (A), and `u` (lane 3 of `m`, `n` and `u` is unused).
struct Local {
    rows: [V4; 3],
    p: [f64; 3],
    m: V4,
    n: V4,
    u: V4,
}

/// [`Kirchhoff::full_rate`] as an [`crate::integrator::Rhs`], multiply–adding with `A`.
#[derive(Debug)]
pub(crate) struct FullRhs<'a, A> {
    pub model: &'a Kirchhoff,
    pub arith: std::marker::PhantomData<A>,
}

/// [`Kirchhoff::shape_rate`] as an [`crate::integrator::Rhs`], multiply–adding with `A`.
#[derive(Debug)]
pub(crate) struct ShapeRhs<'a, A> {
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
impl<A> Clone for ShapeRhs<'_, A> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<A> Copy for ShapeRhs<'_, A> {}

impl<A: MulAdd> crate::integrator::Rhs<48> for FullRhs<'_, A> {
    #[inline(always)]
    fn rate(&self, y: &FullArray, out: &mut FullArray) {
        self.model.full_rate::<A>(y, out);
    }
}

impl<A: MulAdd> crate::integrator::Rhs<16> for ShapeRhs<'_, A> {
    #[inline(always)]
    fn rate(&self, y: &ShapeArray, out: &mut ShapeArray) {
        self.model.shape_rate::<A>(y, out);
    }
}

/// The frame and its first three derivatives along the wire at one point, as flat frame
/// states ([`FrameArray`] layout), for Hermite dense output: `d[k]` is `q⁽ᵏ⁾`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrameJet {
    pub d: [FrameArray; 4],
}

impl FrameJet {
    /// The frame itself.
    pub fn frame(&self) -> FrameState {
        FrameState::from_slice(&self.d[0])
    }
}

/// `(1/c3 − 1/c2, 1/c1 − 1/c3, 1/c2 − 1/c1, 0)` from `inv_c = (1/c1, 1/c2, 1/c3)`: the
/// coefficients of Euler's form of `m × C⁻¹ m`.
pub(crate) fn euler_coefficients(inv_c: [f64; 3]) -> [f64; 4] {
    let [i1, i2, i3] = inv_c;
    [i3 - i2, i1 - i3, i2 - i1, 0.0]
}

/// The right-hand sides for one configuration `a` and stiffnesses `c`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Kirchhoff {
    c: [f64; 3],
    inv_c: Vector3<f64>,
    m0: Vector3<f64>,
    n0: Vector3<f64>,
    /// `(1/c1, 1/c2, 1/c3, 0)`.
    inv_c4: V4,
    /// `(0, 0, 0, 1)` (see [`cross_operands`]).
    e3: V4,
    /// `(0, 1, −1, 0)`: `n × e1` is `n` permuted, times this.
    e1_signs: V4,
}

impl Kirchhoff {
    pub fn new(c: [f64; 3], a: &Vector6<f64>) -> Self {
        Self {
            c,
            inv_c: Vector3::new(1.0 / c[0], 1.0 / c[1], 1.0 / c[2]),
            m0: Vector3::new(a[0], a[1], a[2]),
            n0: Vector3::new(a[3], a[4], a[5]),
            inv_c4: V4([1.0 / c[0], 1.0 / c[1], 1.0 / c[2], 0.0]),
            e3: V4([0.0, 0.0, 0.0, 1.0]),
            e1_signs: V4([0.0, 1.0, -1.0, 0.0]),
        }
    }

    /// `(1/c1, 1/c2, 1/c3)`.
    pub fn inv_c(&self) -> [f64; 3] {
        [self.inv_c.x, self.inv_c.y, self.inv_c.z]
    }

    /// `m0`, the torque part of `a`.
    pub fn m0(&self) -> [f64; 3] {
        [self.m0.x, self.m0.y, self.m0.z]
    }

    /// `n0`, the force part of `a`.
    pub fn n0(&self) -> [f64; 3] {
        [self.n0.x, self.n0.y, self.n0.z]
    }

    /// `n = Rᵀ n0 = Σ_i n0_i r_i` from the frame rows, in lanes 0–2 (lane 3 is `n0 · p`).
    #[inline(always)]
    fn n_of_rows<A: MulAdd>(&self, rows: &[V4; 3]) -> V4 {
        let [r0, r1, r2] = *rows;
        let n0 = &self.n0;
        r2.scale_add::<A>(n0.z, r1.scale_add::<A>(n0.y, r0.scale(n0.x)))
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

    /// `μ = (Rᵀ (m0 − p × n0), Rᵀ n0)` and `u` from the frame rows: `Rᵀ v = Σ_i v_i r_i`.
    #[inline(always)]
    fn local<A: MulAdd>(&self, y: &[f64]) -> Local {
        let rows = [V4::load(y, 0), V4::load(y, 4), V4::load(y, 8)];
        let [r0, r1, r2] = rows;
        let p = [y[3], y[7], y[11]];
        let (m0, n0) = (&self.m0, &self.n0);
        // Rᵀ(p × n0) = Σ_j p_j w_j with w_j linear in the rows (constant coefficients), so
        // the only step that waits on p is one multiply–add per j.
        let w0 = r2.scale_add::<A>(n0.y, r1.scale(-n0.z));
        let w1 = r0.scale_add::<A>(n0.z, r2.scale(-n0.x));
        let w2 = r1.scale_add::<A>(n0.x, r0.scale(-n0.y));
        let rm0 = r2.scale_add::<A>(m0.z, r1.scale_add::<A>(m0.y, r0.scale(m0.x)));
        let n = self.n_of_rows::<A>(&rows);
        let pw = w2.scale_add::<A>(p[2], w1.scale_add::<A>(p[1], w0.scale(p[0])));
        let m = rm0.add(pw.scale(-1.0));
        let u = m.mul(self.inv_c4);
        Local { rows, p, m, n, u }
    }

    /// Eq. 1 for the frame rows from the local quantities, into `out[0..12]`.
    #[inline(always)]
    fn frame_part<A: MulAdd>(&self, l: &Local, out: &mut [f64]) {
        let (u_zxy1, u_yzx0) = cross_operands(l.u, self.e3);
        for (i, row) in l.rows.iter().enumerate() {
            cross_lane0::<A>(*row, u_zxy1, u_yzx0).store(out, 4 * i);
        }
    }

    /// Eq. 1: `R' = R û`, `p' = R e1`, on the flat frame state, with `μ` by closed form (A)
    /// (the reference in tests; the solver integrates [`Kirchhoff::shape_rate`] or
    /// [`Kirchhoff::full_rate`]).
    #[cfg(test)]
    pub fn frame_rate<A: MulAdd>(&self, y: &FrameArray, out: &mut FrameArray) {
        let l = self.local::<A>(y);
        self.frame_part::<A>(&l, out);
    }

    /// Eq. 1 and the top of eq. 3 on the flat shape state ([`ShapeArray`]): `R' = R û`,
    /// `p' = R e1`, `m' = m × u + n × e1` with `n = Rᵀ n0`.
    ///
    /// `u = C⁻¹ m` is formed in the two lane orders the cross products take from `m`'s own
    /// permutes (times `C⁻¹` permuted), and `m × u` as Euler's `(c⁻¹₃ − c⁻¹₂) m2 m3, …`
    /// (exactly zero about the axis of a round wire, where `m1` is conserved): fewer permutes
    /// and a shorter chain than `u`'s permutes and a general cross product.
    #[inline(always)]
    pub fn shape_rate<A: MulAdd>(&self, y: &ShapeArray, out: &mut ShapeArray) {
        let rows = [V4::load(y, 0), V4::load(y, 4), V4::load(y, 8)];
        let m = V4::load(y, 12);
        let (zxy, yzx) = ([2, 0, 1, 3], [1, 2, 0, 3]);
        // C⁻¹ in the two lane orders, and Euler's coefficients (loop invariants; the AVX2
        // kernel of `simd` computes them once per solve).
        let (inv_c_zxy, inv_c_yzx) = (self.inv_c4.permute(zxy), self.inv_c4.permute(yzx));
        let euler = inv_c_zxy.add(inv_c_yzx.scale(-1.0));
        let (m_yzx, m_zxy) = (m.permute(yzx), m.permute(zxy));
        // Lane 3 of m is zero, so lane 3 of u_zxy1 is 1 (see `cross_operands`).
        let u_zxy1 = m_zxy.mul_add::<A>(inv_c_zxy, self.e3);
        let u_yzx0 = m_yzx.mul(inv_c_yzx);
        for (i, r) in rows.iter().enumerate() {
            cross_lane0::<A>(*r, u_zxy1, u_yzx0).store(out, 4 * i);
        }
        // (n × e1) = (0, n3, −n2): n permuted, times (0, 1, −1, 0) (which also clears the
        // lane that holds n0 · p).
        let n_e1 = self
            .n_of_rows::<A>(&rows)
            .permute([3, 2, 1, 3])
            .mul(self.e1_signs);
        m_yzx.mul(m_zxy).mul_add::<A>(euler, n_e1).store(out, 12);
    }

    /// Eq. 1 and `J' = G M + H J` (eq. 4) with `M` from closed form (B), on the flat full
    /// state: `J'_top = C⁻¹ ([Rᵀ, −Rᵀ p̂] + m̂ J_top + n̂ J_bot) − û J_top` and
    /// `J'_bot = −ê1 J_top − û J_bot`.
    ///
    /// Written on the rows of `J` (columns 0–3 and 4–5 of each row contiguous): with
    /// `P = C⁻¹ m̂ − û` and `Q = C⁻¹ n̂` (both with zero diagonal), row `i` of `J'_top` is
    /// `c_i⁻¹ (Rᵀ e_i, p × R e_i) + Σ_k P_ik J_top,k + Σ_k Q_ik J_bot,k`, so the whole update
    /// is scalar-times-row sums that vectorise (`Rᵀ p̂` row `i` is `−(R e_i × p)ᵀ`).
    #[inline(always)]
    pub fn full_rate<A: MulAdd>(&self, y: &FullArray, out: &mut FullArray) {
        let l = self.local::<A>(y);
        self.frame_part::<A>(&l, out);
        let ic = [self.inv_c.x, self.inv_c.y, self.inv_c.z];
        let ([m0, m1, m2, _], [n0, n1, n2, _], [u0, u1, u2, _]) = (l.m.0, l.n.0, l.u.0);
        let [r0, r1, r2] = l.rows;
        let p = l.p;
        // Lane i of s_k is (p × R e_i)_k: s_0 = p1 r_2 − p2 r_1 and cyclically.
        let s0 = r2.scale_add::<A>(p[1], r1.scale(-p[2]));
        let s1 = r0.scale_add::<A>(p[2], r2.scale(-p[0]));
        let s2 = r1.scale_add::<A>(p[0], r0.scale(-p[1]));
        // Row i of C⁻¹ [Rᵀ, −Rᵀ p̂]: c_i⁻¹ (R_0i, R_1i, R_2i, s_0i | s_1i, s_2i).
        let base_l = |i: usize| V4([r0.0[i], r1.0[i], r2.0[i], s0.0[i]]).scale(ic[i]);
        let base_r = |i: usize| V2([s1.0[i], s2.0[i]]).scale(ic[i]);
        let tl: [V4; 6] = std::array::from_fn(|i| V4::load(y, JL + 4 * i));
        let tr: [V2; 6] = std::array::from_fn(|i| V2::load(y, JR + 2 * i));
        // Row i of J'_top: base_i + Σ_k P_ik t_k + Σ_k Q_ik b_k over the off-diagonal entries
        // of P and Q (rows 0–2 of J are t, rows 3–5 are b).
        let coefficients = [
            [
                (u2 - ic[0] * m2, 1),
                (ic[0] * m1 - u1, 2),
                (-ic[0] * n2, 4),
                (ic[0] * n1, 5),
            ],
            [
                (ic[1] * m2 - u2, 0),
                (u0 - ic[1] * m0, 2),
                (ic[1] * n2, 3),
                (-ic[1] * n0, 5),
            ],
            [
                (u1 - ic[2] * m1, 0),
                (ic[2] * m0 - u0, 1),
                (-ic[2] * n1, 3),
                (ic[2] * n0, 4),
            ],
        ];
        // Columns 4–5 of the six output rows, stored in pairs of rows at the end, meant as one
        // 4-lane store per pair, as the stage sums read them. LLVM still splits some pairs,
        // but this form costs the fewest instructions of those tried (`docs/integrator.md`).
        let mut right = [V2([0.0; 2]); 6];
        for (i, terms) in coefficients.iter().enumerate() {
            let (mut vl, mut vr) = (base_l(i), base_r(i));
            for &(s, k) in terms {
                vl = tl[k].scale_add::<A>(s, vl);
                vr = tr[k].scale_add::<A>(s, vr);
            }
            vl.store(out, JL + 4 * i);
            right[i] = vr;
        }
        // J'_bot = −ê1 J_top − û J_bot: −ê1 v = (0, v_z, −v_y); −û v = v × u (rows 3–5 are
        // b_0..b_2): b_0' = u2 b_1 − u1 b_2, b_1' = t_2 + u0 b_2 − u2 b_0,
        // b_2' = −t_1 + u1 b_0 − u0 b_1.
        let bottom = [
            (tl[4].scale(u2), tr[4].scale(u2), [(-u1, 5)]),
            (tl[2], tr[2], [(u0, 5)]),
            (tl[1].scale(-1.0), tr[1].scale(-1.0), [(u1, 3)]),
        ];
        let last = [(0.0, 0), (-u2, 3), (-u0, 4)];
        for (i, ((mut vl, mut vr, [(s, k)]), (s2, k2))) in bottom.into_iter().zip(last).enumerate()
        {
            vl = tl[k].scale_add::<A>(s, vl);
            vr = tr[k].scale_add::<A>(s, vr);
            if i > 0 {
                vl = tl[k2].scale_add::<A>(s2, vl);
                vr = tr[k2].scale_add::<A>(s2, vr);
            }
            vl.store(out, JL + 4 * (3 + i));
            right[3 + i] = vr;
        }
        for pair in 0..3 {
            let (a, b) = (right[2 * pair].0, right[2 * pair + 1].0);
            V4([a[0], a[1], b[0], b[1]]).store(out, JR + 4 * pair);
        }
    }

    /// `q, q', q'', q'''` at one point, on the frame rows `r` (`r û = r × u`):
    /// `R' = R û`, `R'' = R (û² + û')`, `R''' = R (û³ + 2 û û' + û' û + û'')`, so with
    /// `W1 = r × u` and `W2 = W1 × u + r × u'` the rows are `W1`, `W2` and
    /// `W2 × u + 2 W1 × u' + r × u''`; `p⁽ᵏ⁺¹⁾ = R⁽ᵏ⁾ e1` is lane 0 of the row before. `u'` is
    /// from eq. 3 and `u''` from `μ'' = F(μ) μ'` (eq. 4's `F`).
    #[inline(always)]
    pub fn frame_jet(&self, y: &FrameArray) -> FrameJet {
        let l = self.local::<Separate>(y);
        self.jet_of(y, &l.rows, l.m, l.n)
    }

    /// [`Kirchhoff::frame_jet`] from a shape state, with its integrated `m`.
    #[inline(always)]
    pub fn shape_jet(&self, y: &ShapeArray) -> FrameJet {
        let rows = [V4::load(y, 0), V4::load(y, 4), V4::load(y, 8)];
        let [n1, n2, n3, _] = self.n_of_rows::<Separate>(&rows).0;
        self.jet_of(&frame_of(y), &rows, V4::load(y, 12), V4([n1, n2, n3, 0.0]))
    }

    /// The frame jet at frame `y` (rows `rows`) with `μ = (m, n)`: the portable paths' jets,
    /// and the fast paths' for methods other than DOP853 (inlined, so compiled for AVX2 and
    /// FMA there; DOP853's fast paths use the `simd` module's jet).
    #[inline(always)]
    fn jet_of(&self, y: &FrameArray, rows: &[V4; 3], m: V4, n: V4) -> FrameJet {
        let mu = Vector6::new(m.0[0], m.0[1], m.0[2], n.0[0], n.0[1], n.0[2]);
        let u = m.mul(self.inv_c4);
        let dmu = costate_rate(self.c, &mu);
        // The top rows of F(μ) μ' (see `f_matrix`): only u'' is needed.
        let [d32, d13, d21, _] = euler_coefficients(self.inv_c());
        let (m, v) = (&mu, &dmu);
        let ddm = [
            d32 * (m[2] * v[1] + m[1] * v[2]),
            d13 * (m[2] * v[0] + m[0] * v[2]) + v[5],
            d21 * (m[1] * v[0] + m[0] * v[1]) - v[4],
        ];
        let du = V4([v[0], v[1], v[2], 0.0]).mul(self.inv_c4);
        let ddu = V4([ddm[0], ddm[1], ddm[2], 0.0]).mul(self.inv_c4);
        jet_of_strains(y, rows, [u, du, ddu], self.e3)
    }
}

/// The frame jet at frame `y` (rows `rows`) from the strain `u` and its derivatives `u'`,
/// `u''` (lane 3 zero), as in [`Kirchhoff::frame_jet`]: the rows `W1 = r × u`,
/// `W2 = W1 × u + r × u'` and `W2 × u + 2 W1 × u' + r × u''`; `e3 = (0, 0, 0, 1)` as a
/// run-time value (see [`cross_operands`]). Shared with the loaded solver, whose `u`, `u'`,
/// `u''` come from the loaded equations.
#[inline(always)]
pub(crate) fn jet_of_strains(
    y: &FrameArray,
    rows: &[V4; 3],
    [u, du, ddu]: [V4; 3],
    e3: V4,
) -> FrameJet {
    let (u_a, u_b) = cross_operands(u, e3);
    let (du_a, du_b) = cross_operands(du, e3);
    let (ddu_a, ddu_b) = cross_operands(ddu, e3);
    // `cross_lane0` puts lane 0 of its first argument into lane 3, which is p⁽ᵏ⁺¹⁾ for
    // the W × u terms; the added terms must not add to lane 3, so theirs is cleared.
    let no_lane3 = |v: V4| V4([v.0[0], v.0[1], v.0[2], 0.0]);
    let mut jet = FrameJet { d: [*y; 4] };
    for (i, r) in rows.iter().enumerate() {
        let w1 = cross_lane0::<Separate>(*r, u_a, u_b);
        let w2 = cross_lane0::<Separate>(w1, u_a, u_b)
            .add(no_lane3(cross_lane0::<Separate>(*r, du_a, du_b)));
        let w1du = no_lane3(cross_lane0::<Separate>(w1, du_a, du_b));
        let w3 = cross_lane0::<Separate>(w2, u_a, u_b)
            .add(w1du.add(w1du))
            .add(no_lane3(cross_lane0::<Separate>(*r, ddu_a, ddu_b)));
        w1.store(&mut jet.d[1], 4 * i);
        w2.store(&mut jet.d[2], 4 * i);
        w3.store(&mut jet.d[3], 4 * i);
    }
    jet
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arith::Separate;
    use crate::se3::hat;

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
        let jet = |y: &FrameArray| model.frame_jet(y);
        let (j0, jp, jm) = (
            jet(&y),
            jet(&integ.step(&y, eps, f)),
            jet(&integ.step(&y, -eps, f)),
        );
        // max |(a − b) / 2ε − exact| over R and p (the flat layout holds both).
        let error = |a: &FrameArray, b: &FrameArray, exact: &FrameArray| {
            (0..12)
                .map(|i| ((a[i] - b[i]) / (2.0 * eps) - exact[i]).abs())
                .fold(0.0, f64::max)
        };
        for k in 0..3 {
            let e = error(&jp.d[k], &jm.d[k], &j0.d[k + 1]);
            assert!(e < 1e-6, "derivative {}: {e:e}", k + 1);
        }
        // The jet's frame is the state, and its derivative is eq. 1's rate.
        let mut rate = [0.0; 12];
        model.frame_rate::<Separate>(&y, &mut rate);
        assert_eq!(j0.d[0], y);
        let gap = (0..12)
            .map(|i| (rate[i] - j0.d[1][i]).abs())
            .fold(0.0, f64::max);
        assert!(gap <= 1e-14, "{gap:e}");
    }

    /// The shape state's rate is eq. 1 and the top of eq. 3 with `n = Rᵀ n0`, written with
    /// nalgebra, on a round wire (where Euler's form has a zero coefficient) and an anisotropic
    /// one, at a turned frame and an arbitrary `m`.
    #[test]
    fn shape_rate_is_eq_1_and_3() {
        let a = Vector6::new(0.3, -0.7, 1.2, -2.0, 1.5, 0.4);
        for c in [[1.3, 1.0, 0.6], [0.214, 0.278, 0.278]] {
            let model = Kirchhoff::new(c, &a);
            let integ = crate::Integrator::new(crate::Method::Rk8, 1).expect("valid");
            let f = |s: &FrameArray, o: &mut FrameArray| model.frame_rate::<Separate>(s, o);
            let mut frame: FrameArray = FrameState::initial();
            for _ in 0..300 {
                frame = integ.step(&frame, 1e-3, f);
            }
            let q = FrameState::from_slice(&frame);
            let m = Vector3::new(0.4, -1.1, 0.25);
            let mut y: ShapeArray = [0.0; 16];
            y[..12].copy_from_slice(&frame);
            y[12..15].copy_from_slice(m.as_slice());
            let mut out = [0.0; 16];
            model.shape_rate::<Separate>(&y, &mut out);
            let n = q.r.tr_mul(&model.n0);
            let mu = Vector6::new(m.x, m.y, m.z, n.x, n.y, n.z);
            let dmu = costate_rate(c, &mu);
            let u = Vector3::new(m.x / c[0], m.y / c[1], m.z / c[2]);
            let dr = q.r * hat(&u);
            let dp = q.r.column(0);
            for i in 0..3 {
                for j in 0..3 {
                    assert!(
                        (out[4 * i + j] - dr[(i, j)]).abs() <= 1e-14,
                        "R' ({i}, {j})"
                    );
                }
                assert!((out[4 * i + 3] - dp[i]).abs() <= 1e-14, "p' {i}");
                assert!(
                    (out[12 + i] - dmu[i]).abs() <= 1e-13,
                    "m' {i}: {out:?} vs {dmu}"
                );
            }
            assert_eq!(out[15], 0.0, "lane 3 of m' stays zero");
        }
    }
}
