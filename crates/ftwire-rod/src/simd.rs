//! The shape solve's hot loops (its DOP853 step, the frame jets at the grid points, which the
//! Jacobian path's `solve` uses too, and the Hermite interpolation) written with explicit
//! AVX2+FMA operations (x86-64).
//!
//! [`crate::arith`]'s lane type leaves the choice of instructions to LLVM, which splits some
//! 4-lane operations into scalar and 2-lane pieces (and pays for it in shuffles and blends).
//! Here every operation is one AVX instruction on a whole `__m256d`, so the code is what it
//! says. The functions are compiled for AVX2 and FMA and only reached through
//! [`crate::arith::fast_path`]; intrinsics are safe to call inside them, and values cross
//! the boundary by copy through `bytemuck` (`cast`, `cast_ref`) both ways, so no `unsafe` is
//! needed here.
//!
//! The right-hand side is that of the portable path
//! ([`crate::equations::Kirchhoff::shape_rate`]) operation for operation, and the step is the
//! same DOP853 step with the step size folded in differently: the portable step sums
//! `(h a_ij) k_j`, this one has the rate return `h k` (its constants are scaled by `h`) and
//! sums `a_ij (h k_j)` with the tableau's own coefficients, so nothing is rescaled per step
//! size. The jets and the interpolation group their sums differently too. The two paths agree
//! to rounding (a test checks states, jets and shapes to 1e-12).

use std::arch::x86_64::{
    __m256d, _mm256_add_pd, _mm256_blend_pd, _mm256_fmadd_pd, _mm256_fmsub_pd, _mm256_mul_pd,
    _mm256_permute4x64_pd, _mm256_set1_pd,
};

use crate::equations::{FrameArray, FrameJet, ShapeArray, euler_coefficients};
use crate::integrator::{DOP853_A, DOP853_B, with_dop853_terms};

/// Four lanes of `f64` in one AVX register.
#[derive(Clone, Copy)]
struct F4(__m256d);

/// Lane orders for [`F4::permute`] (`_mm256_permute4x64_pd`'s immediates: lane `k` of the
/// result is lane `(imm >> 2k) & 3` of the input).
mod order {
    /// `(a1, a2, a0, a3)`.
    pub const YZX3: i32 = 0b11_00_10_01;
    /// `(a2, a0, a1, a3)`.
    pub const ZXY3: i32 = 0b11_01_00_10;
    /// `(a1, a2, a0, a0)`.
    pub const YZX0: i32 = 0b00_00_10_01;
    /// `(a3, a2, a1, a3)`.
    pub const WZYW: i32 = 0b11_01_10_11;
}

impl F4 {
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn new(v: &[f64; 4]) -> Self {
        // One unaligned 32-byte load (`_mm256_setr_pd` of four loads is compiled to
        // several partial loads and blends).
        Self(bytemuck::cast(*v))
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn splat(x: f64) -> Self {
        Self(_mm256_set1_pd(x))
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn to_array(self) -> [f64; 4] {
        bytemuck::cast(self.0)
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn add(self, b: Self) -> Self {
        Self(_mm256_add_pd(self.0, b.0))
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn mul(self, b: Self) -> Self {
        Self(_mm256_mul_pd(self.0, b.0))
    }

    /// `self · b + c`, one rounding.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn mul_add(self, b: Self, c: Self) -> Self {
        Self(_mm256_fmadd_pd(self.0, b.0, c.0))
    }

    /// `self · b − c`, one rounding.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn mul_sub(self, b: Self, c: Self) -> Self {
        Self(_mm256_fmsub_pd(self.0, b.0, c.0))
    }

    /// The lanes in the order `IMM` (see [`order`]).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn permute<const IMM: i32>(self) -> Self {
        Self(_mm256_permute4x64_pd::<IMM>(self.0))
    }

    /// Lanes 0–2 of `self`, lane 3 of `b`.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn with_lane3_of(self, b: Self) -> Self {
        Self(_mm256_blend_pd::<0b1000>(self.0, b.0))
    }
}

/// The shape state in registers: the frame rows `(R_i0, R_i1, R_i2, p_i)`, then `m` (lane 3
/// zero), as in [`ShapeArray`].
type State = [F4; 4];

/// The constants of the right-hand side for one configuration.
#[derive(Clone, Copy)]
struct Constants {
    /// `(1/c1, 1/c2, 1/c3, 0)`.
    inv_c: F4,
    /// `(1/c3, 1/c1, 1/c2, 0)`: `C⁻¹` in the lane order of [`order::ZXY3`].
    inv_c_zxy: F4,
    /// `(1/c2, 1/c3, 1/c1, 0)`: `C⁻¹` in the lane order of [`order::YZX3`].
    inv_c_yzx: F4,
    /// Euler's coefficients of `m × C⁻¹ m` (`equations::euler_coefficients`).
    euler: F4,
    /// `n0`, each component in every lane.
    n0: [F4; 3],
    /// `(0, 0, 0, 1)`.
    e3: F4,
    /// `(0, 1, −1, 0)`.
    e1_signs: F4,
}

/// `n = Rᵀ n0 = Σ_i n0_i r_i` from the frame rows, in lanes 0–2 (lane 3 is `n0 · p`).
#[inline]
#[target_feature(enable = "avx2,fma")]
fn n_of_rows(k: &Constants, y: &State) -> F4 {
    y[2].mul_add(k.n0[2], y[1].mul_add(k.n0[1], y[0].mul(k.n0[0])))
}

/// Eq. 1 and the top of eq. 3 on the shape state, as
/// [`crate::equations::Kirchhoff::shape_rate`].
#[inline]
#[target_feature(enable = "avx2,fma")]
fn rate(k: &Constants, y: &State) -> State {
    let [r0, r1, r2, m] = *y;
    let (m_yzx, m_zxy) = (
        m.permute::<{ order::YZX3 }>(),
        m.permute::<{ order::ZXY3 }>(),
    );
    // u = C⁻¹ m in the two lane orders of the cross products, from m's permutes (lane 3 of
    // u_zxy1 is 0 · (1/c2) + 1).
    let u_zxy1 = m_zxy.mul_add(k.inv_c_zxy, k.e3);
    let u_yzx = m_yzx.mul(k.inv_c_yzx);
    // Row i of R' = R û is r_i × u; lane 3 gets R_i0 · 1 − p_i · 0 = p_i'.
    let row = |r: F4| cross_lane0(r, u_zxy1, u_yzx);
    // n × e1 = (0, n3, −n2) (the signs clear the lanes that hold n0 · p).
    let n_e1 = n_of_rows(k, y).permute::<{ order::WZYW }>().mul(k.e1_signs);
    [
        row(r0),
        row(r1),
        row(r2),
        m_yzx.mul(m_zxy).mul_add(k.euler, n_e1),
    ]
}

/// `(a × b, a_0)` for `b` given as `b_zxy1 = (b2, b0, b1, 1)` and `b_yzx = (b1, b2, b0, 0)`
/// (as [`crate::equations`]' `cross_lane0`): on a frame row, lane 3 is `R_i0`, which is `p_i'`.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn cross_lane0(a: F4, b_zxy1: F4, b_yzx: F4) -> F4 {
    a.permute::<{ order::YZX0 }>()
        .mul_sub(b_zxy1, a.permute::<{ order::ZXY3 }>().mul(b_yzx))
}

/// `a × b` for `b = (b0, b1, b2, 0)` given as `b_zxy = (b2, b0, b1, 0)` and
/// `b_yzx = (b1, b2, b0, 0)`; lane 3 is zero.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn cross(a: F4, b_zxy: F4, b_yzx: F4) -> F4 {
    a.permute::<{ order::YZX3 }>()
        .mul_sub(b_zxy, a.permute::<{ order::ZXY3 }>().mul(b_yzx))
}

/// The frame jet `q, q', q'', q'''` at a shape state, as
/// [`crate::equations::Kirchhoff::shape_jet`]: with `u' = C⁻¹ m'` and
/// `u'' = C⁻¹ (m' × u + m × u' + n' × e1)`, row `i` of `R⁽ᵏ⁾` is `w_k = w_{k−1} × u + …`
/// (`w_1 = r_i × u`, `w_2 = w_1 × u + r_i × u'`, `w_3 = w_2 × u + 2 w_1 × u' + r_i × u''`),
/// lane 3 (`p_i⁽ᵏ⁾ = (R⁽ᵏ⁻¹⁾)_i0`) carried by the `× u` term.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn jet(k: &Constants, y: &State) -> FrameJet {
    let [d_r0, d_r1, d_r2, dm] = rate(k, y);
    let m = y[3];
    let n = n_of_rows(k, y).with_lane3_of(F4::splat(0.0));
    let u = m.mul(k.inv_c);
    let du = dm.mul(k.inv_c);
    let du_zxy = du.permute::<{ order::ZXY3 }>();
    let du_yzx = du.permute::<{ order::YZX3 }>();
    let u_zxy = u.permute::<{ order::ZXY3 }>();
    let u_yzx = u.permute::<{ order::YZX3 }>();
    let u_zxy1 = u_zxy.with_lane3_of(k.e3);
    let dn = cross(n, u_zxy, u_yzx);
    let dn_e1 = dn.permute::<{ order::WZYW }>().mul(k.e1_signs);
    let ddm = cross(dm, u_zxy, u_yzx)
        .add(cross(m, du_zxy, du_yzx))
        .add(dn_e1);
    let ddu = ddm.mul(k.inv_c);
    let ddu_zxy = ddu.permute::<{ order::ZXY3 }>();
    let ddu_yzx = ddu.permute::<{ order::YZX3 }>();
    // × u with lane 3 set to lane 0 of the left operand.
    let times_u = |a: F4| cross_lane0(a, u_zxy1, u_yzx);
    let mut d = [[[0.0; 4]; 3]; 4];
    for (i, (r, w1)) in y[..3].iter().zip([d_r0, d_r1, d_r2]).enumerate() {
        let w2 = times_u(w1).add(cross(*r, du_zxy, du_yzx));
        let w1du = cross(w1, du_zxy, du_yzx);
        let w3 = times_u(w2)
            .add(w1du.add(w1du))
            .add(cross(*r, ddu_zxy, ddu_yzx));
        for (d, w) in d.iter_mut().zip([*r, w1, w2, w3]) {
            d[i] = w.to_array();
        }
    }
    FrameJet {
        d: bytemuck::cast(d),
    }
}

/// [`jet`] at a frame with its `m`, for the Jacobian path's knots (where `m` comes from
/// closed form (A)), for stiffnesses `1 / inv_c` and the base force `n0`.
#[target_feature(enable = "avx2,fma")]
pub(crate) fn frame_jet(
    inv_c: [f64; 3],
    n0: [f64; 3],
    frame: &FrameArray,
    m: [f64; 3],
) -> FrameJet {
    let rows: &[[f64; 4]; 3] = bytemuck::cast_ref(frame);
    let [r0, r1, r2] = rows.map(|r| F4::new(&r));
    let state = [r0, r1, r2, F4::new(&[m[0], m[1], m[2], 0.0])];
    jet(&constants(inv_c, n0), &state)
}

/// The constants of the right-hand side for stiffnesses `c = 1 / inv_c` and the base force
/// `n0`.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn constants(inv_c: [f64; 3], n0: [f64; 3]) -> Constants {
    Constants {
        inv_c: F4::new(&[inv_c[0], inv_c[1], inv_c[2], 0.0]),
        inv_c_zxy: F4::new(&[inv_c[2], inv_c[0], inv_c[1], 0.0]),
        inv_c_yzx: F4::new(&[inv_c[1], inv_c[2], inv_c[0], 0.0]),
        euler: F4::new(&euler_coefficients(inv_c)),
        n0: [F4::splat(n0[0]), F4::splat(n0[1]), F4::splat(n0[2])],
        e3: F4::new(&[0.0, 0.0, 0.0, 1.0]),
        e1_signs: F4::new(&[0.0, 1.0, -1.0, 0.0]),
    }
}

impl Constants {
    /// The constants that make [`rate`] return `h` times the rate: the terms of `u` (and
    /// lane 3, which carries `p'`), Euler's coefficients and the `n × e1` signs, times `h`.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn times(&self, h: f64) -> Self {
        let h4 = F4::splat(h);
        Self {
            inv_c_zxy: self.inv_c_zxy.mul(h4),
            inv_c_yzx: self.inv_c_yzx.mul(h4),
            euler: self.euler.mul(h4),
            e3: self.e3.mul(h4),
            e1_signs: self.e1_signs.mul(h4),
            ..*self
        }
    }
}

/// The written-out DOP853 stages over the nonzero coefficients (the lists of
/// [`with_dop853_terms`]).
macro_rules! stages {
    ($c:ident, $y:ident, $k:ident; $($i:literal: [$($j:literal),*]);*) => {
        $(
            {
                #[allow(unused_mut)]
                let mut sum = *$y;
                $(
                    let a = F4::splat(DOP853_A[$i][$j]);
                    for (v, kj) in sum.iter_mut().zip(&$k[$j]) {
                        *v = a.mul_add(*kj, *v);
                    }
                )*
                $k[$i] = rate($c, &sum);
            }
        )*
    };
}

/// One DOP853 step in place, with `c` the constants [`Constants::times`] the step size (so
/// that `k` holds `h f(Y_i)`, and the stage sums use the tableau's own coefficients).
#[inline]
#[target_feature(enable = "avx2,fma")]
fn step(c: &Constants, y: &mut State, k: &mut [State; 12]) {
    with_dop853_terms!(stages!(c, y, k));
    for j in [0, 5, 6, 7, 8, 9, 10, 11] {
        let b = F4::splat(DOP853_B[j]);
        for (v, kj) in y.iter_mut().zip(&k[j]) {
            *v = b.mul_add(*kj, *v);
        }
    }
}

/// Integrates the shape state `y` over `grid` (step sizes, and the grid point each step ends
/// on, as [`crate::Integrator::grid`]), pushing the frame jets at the start and at each grid
/// point into `knots`; returns the final state.
#[target_feature(enable = "avx2,fma")]
pub(crate) fn integrate_shape(
    inv_c: [f64; 3],
    n0: [f64; 3],
    y: &ShapeArray,
    grid: impl Iterator<Item = (f64, Option<usize>)>,
    knots: &mut Vec<FrameJet>,
) -> ShapeArray {
    let c = constants(inv_c, n0);
    let rows: &[[f64; 4]; 4] = bytemuck::cast_ref(y);
    let mut state: State = rows.map(|r| F4::new(&r));
    let mut k = [state; 12];
    let (mut step_size, mut scaled) = (f64::NAN, c);
    knots.push(jet(&c, &state));
    for (h, grid_point) in grid {
        if h.to_bits() != step_size.to_bits() {
            (step_size, scaled) = (h, c.times(h));
        }
        step(&scaled, &mut state, &mut k);
        if grid_point.is_some() {
            knots.push(jet(&c, &state));
        }
    }
    bytemuck::cast(state.map(|v| v.0))
}

/// The septic Hermite basis of [`crate::integrator::septic_hermite`] in monomial form:
/// `HERMITE[k]` holds the coefficients of `θᵏ` in the eight weights (a test checks it against
/// `septic_hermite` at nine points, which determine a polynomial of degree 7).
const HERMITE: [[f64; 8]; 8] = {
    const S: f64 = 1.0 / 6.0;
    const T: f64 = 2.0 / 3.0;
    [
        [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, S, 0.0, 0.0, 0.0, 0.0],
        [-35.0, -20.0, -5.0, -T, 35.0, -15.0, 2.5, -S],
        [84.0, 45.0, 10.0, 1.0, -84.0, 39.0, -7.0, 0.5],
        [-70.0, -36.0, -7.5, -T, 70.0, -34.0, 6.5, -0.5],
        [20.0, 10.0, 2.0, S, -20.0, 10.0, -2.0, S],
    ]
};

/// The frame between two knots at `θ ∈ (0, 1)` of a step `h`: septic Hermite interpolation
/// of the flat frame (the weights by Estrin's scheme in 4 lanes, each knot's four terms summed
/// apart), as the rows `(R_i0, R_i1, R_i2, p_i)` of the flat frame state.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(crate) fn interpolate_frame(k0: &FrameJet, k1: &FrameJet, h: f64, theta: f64) -> [[f64; 4]; 3] {
    let t = F4::splat(theta);
    let halves = |c: &[f64; 8]| -> [F4; 2] {
        let [lo, hi]: &[[f64; 4]; 2] = bytemuck::cast_ref(c);
        [F4::new(lo), F4::new(hi)]
    };
    // Estrin's scheme: (c0 + c1 t) + (c2 + c3 t) t² + ((c4 + c5 t) + (c6 + c7 t) t²) t⁴, a
    // chain of three multiply–adds where Horner's rule has seven.
    let t2 = t.mul(t);
    let t4 = t2.mul(t2);
    let pair = |k: usize| -> [F4; 2] {
        let ([a_lo, a_hi], [b_lo, b_hi]) = (halves(&HERMITE[k]), halves(&HERMITE[k + 1]));
        [b_lo.mul_add(t, a_lo), b_hi.mul_add(t, a_hi)]
    };
    let ([p0l, p0h], [p2l, p2h], [p4l, p4h], [p6l, p6h]) = (pair(0), pair(2), pair(4), pair(6));
    let (q0l, q0h) = (p2l.mul_add(t2, p0l), p2h.mul_add(t2, p0h));
    let (q4l, q4h) = (p6l.mul_add(t2, p4l), p6h.mul_add(t2, p4h));
    let (lo, hi) = (q4l.mul_add(t4, q0l), q4h.mul_add(t4, q0h));
    let powers = F4::new(&[1.0, h, h * h, h * h * h]);
    let w = [lo.mul(powers).to_array(), hi.mul(powers).to_array()];
    let mut acc = [[F4::splat(0.0); 3]; 2];
    for ((acc, knot), w) in acc.iter_mut().zip([k0, k1]).zip(&w) {
        for (d, &wi) in knot.d.iter().zip(w) {
            let wi = F4::splat(wi);
            let rows: &[[f64; 4]; 3] = bytemuck::cast_ref(d);
            for (a, row) in acc.iter_mut().zip(rows) {
                *a = wi.mul_add(F4::new(row), *a);
            }
        }
    }
    [0, 1, 2].map(|i| acc[0][i].add(acc[1][i]).to_array())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::septic_hermite;

    #[test]
    fn monomial_hermite_is_the_basis() {
        for theta in (0..=8).map(|k| f64::from(k) / 8.0) {
            let w = septic_hermite(theta);
            for (i, w) in w.iter().enumerate() {
                let mono: f64 = HERMITE
                    .iter()
                    .enumerate()
                    .map(|(k, c)| c[i] * theta.powi(k as i32))
                    .sum();
                assert!(
                    (mono - w).abs() < 1e-13,
                    "θ = {theta}, weight {i}: {mono} vs {w}"
                );
            }
        }
    }
}
