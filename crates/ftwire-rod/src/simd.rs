//! The solver's hot loops written with explicit AVX2+FMA operations (x86-64): the shape
//! solve's DOP853 step, the frame jets at the grid points, the Hermite interpolation, and the
//! Jacobian path's DOP853 step (frame and `J`, 48 numbers).
//!
//! [`crate::arith`]'s lane type leaves the choice of instructions to LLVM, which splits some
//! 4-lane operations into scalar and 2-lane pieces (and pays for it in shuffles and blends).
//! Here every operation is one AVX instruction on a whole `__m256d` (or `__m128d`), so the
//! code is what it says. The functions are compiled for AVX2 and FMA and only reached
//! through [`crate::arith::fast_path`]; intrinsics are safe to call inside them, and values
//! cross the boundary by copy through `bytemuck` (`cast`, `cast_ref`) both ways, so no
//! `unsafe` is needed here.
//!
//! The right-hand sides are those of the portable paths
//! ([`crate::kirchhoff::Kirchhoff::shape_rate`] operation for operation;
//! [`crate::kirchhoff::Kirchhoff::full_rate`] with its sums grouped for the CPU, see
//! [`full_rate`]), and the steps are the same DOP853 step with the step size folded in
//! differently: the portable step sums `(h a_ij) k_j`, these have the rate return `h k` (its
//! constants are scaled by `h`) and sum `a_ij (h k_j)` with the tableau's own coefficients, so
//! nothing is rescaled per step size. The jets and the interpolation group their sums
//! differently too. The two paths agree to rounding (a test checks states, `J`, jets and
//! shapes to 1e-12).

use std::arch::x86_64::{
    __m128d, __m256d, _mm_add_pd, _mm_fmadd_pd, _mm_fmsub_pd, _mm_fnmadd_pd, _mm_mul_pd,
    _mm_set1_pd, _mm256_add_pd, _mm256_blend_pd, _mm256_castpd256_pd128, _mm256_extractf128_pd,
    _mm256_fmadd_pd, _mm256_fmsub_pd, _mm256_fnmadd_pd, _mm256_mul_pd, _mm256_permute2f128_pd,
    _mm256_permute4x64_pd, _mm256_set_m128d, _mm256_set1_pd, _mm256_unpackhi_pd,
    _mm256_unpacklo_pd,
};

use crate::kirchhoff::{FrameArray, FrameJet, FullArray, ShapeArray, euler_coefficients};
use crate::tableau::{DOP853_A, DOP853_B, with_dop853_terms};

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

    /// `c − self · b`, one rounding.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn neg_mul_add(self, b: Self, c: Self) -> Self {
        Self(_mm256_fnmadd_pd(self.0, b.0, c.0))
    }

    /// The lanes in the order `IMM` (see [`order`]).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn permute<const IMM: i32>(self) -> Self {
        Self(_mm256_permute4x64_pd::<IMM>(self.0))
    }

    /// `(a0, b0, a2, b2)` for `self = a`.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn unpack_lo(self, b: Self) -> Self {
        Self(_mm256_unpacklo_pd(self.0, b.0))
    }

    /// `(a1, b1, a3, b3)` for `self = a`.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn unpack_hi(self, b: Self) -> Self {
        Self(_mm256_unpackhi_pd(self.0, b.0))
    }

    /// Two 128-bit halves of `self` and `b`, chosen by `IMM` (`_mm256_permute2f128_pd`'s
    /// immediate: `0x20` joins the low halves, `0x31` the high ones).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn join<const IMM: i32>(self, b: Self) -> Self {
        Self(_mm256_permute2f128_pd::<IMM>(self.0, b.0))
    }

    /// Lanes 0–1.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn low(self) -> F2 {
        F2(_mm256_castpd256_pd128(self.0))
    }

    /// Lanes 2–3.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn high(self) -> F2 {
        F2(_mm256_extractf128_pd::<1>(self.0))
    }

    /// `(lo, hi)` as four lanes.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn from_halves(lo: F2, hi: F2) -> Self {
        Self(_mm256_set_m128d(hi.0, lo.0))
    }

    /// Lanes 0–2 of `self`, lane 3 of `b`.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn with_lane3_of(self, b: Self) -> Self {
        Self(_mm256_blend_pd::<0b1000>(self.0, b.0))
    }
}

/// Two lanes of `f64` in an SSE register.
#[derive(Clone, Copy)]
struct F2(__m128d);

impl F2 {
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn new(v: [f64; 2]) -> Self {
        Self(bytemuck::cast(v))
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn splat(x: f64) -> Self {
        Self(_mm_set1_pd(x))
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn add(self, b: Self) -> Self {
        Self(_mm_add_pd(self.0, b.0))
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn mul(self, b: Self) -> Self {
        Self(_mm_mul_pd(self.0, b.0))
    }

    /// `self · b + c`, one rounding.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn mul_add(self, b: Self, c: Self) -> Self {
        Self(_mm_fmadd_pd(self.0, b.0, c.0))
    }

    /// `self · b − c`, one rounding.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn mul_sub(self, b: Self, c: Self) -> Self {
        Self(_mm_fmsub_pd(self.0, b.0, c.0))
    }

    /// `c − self · b`, one rounding.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn neg_mul_add(self, b: Self, c: Self) -> Self {
        Self(_mm_fnmadd_pd(self.0, b.0, c.0))
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
    /// Euler's coefficients of `m × C⁻¹ m` (`kirchhoff::euler_coefficients`).
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
/// [`crate::kirchhoff::Kirchhoff::shape_rate`].
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
/// (as `kirchhoff`'s `cross_lane0`): on a frame row, lane 3 is `R_i0`, which is `p_i'`.
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
/// [`crate::kirchhoff::Kirchhoff::shape_jet`]: with `u' = C⁻¹ m'` and
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

/// The Jacobian path's flat state ([`FullArray`]) as 12 rows of four lanes, 32-byte aligned:
/// the frame rows `(R_i0, R_i1, R_i2, p_i)`, columns 0–3 of the six rows of `J`, then columns
/// 4–5 of the rows of `J` in pairs of rows.
#[derive(Clone, Copy)]
#[repr(C, align(32))]
struct Block([[f64; 4]; 12]);

/// Where the rows of `J` start in a [`Block`]: columns 0–3 of row `i` are row `JL + i`,
/// columns 4–5 of rows `2p` and `2p + 1` are row `JR + p`.
const JL: usize = 3;
const JR: usize = 9;

/// The constants of the Jacobian path's right-hand side for one configuration. All but `m0`
/// and `n0` are scaled by the step size in [`FullConstants::times`].
#[derive(Clone, Copy)]
struct FullConstants {
    /// `m0` and `n0`, each component in every lane.
    m0: [F4; 3],
    n0: [F4; 3],
    /// `(0, 0, 0, 1)`: lane 3 of a frame row's rate is `p_i' = R_i0`.
    e3: F4,
    /// `C⁻¹` in the lane orders of [`order::ZXY3`] and [`order::YZX3`] (lane 3 zero).
    inv_c_zxy: F4,
    inv_c_yzx: F4,
    /// `C⁻¹` (lane 3 zero).
    inv_c: F4,
    /// `inv_c_zxy − inv_c` and `inv_c − inv_c_yzx`: with `m` permuted, the coefficients of
    /// `J_top` in `J'_top` (see [`full_rate`]).
    d_zxy: F4,
    d_yzx: F4,
    /// `1/c_i` in every lane, `i = 0, 1, 2`.
    inv_c_splat: [F4; 3],
    /// `1` in every lane, scaled by the step size (the `ê1` terms of `J'_bot`).
    one: F4,
}

impl FullConstants {
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn new(inv_c: [f64; 3], m0: [f64; 3], n0: [f64; 3]) -> Self {
        let [i0, i1, i2] = inv_c;
        Self {
            m0: m0.map(|x| F4::splat(x)),
            n0: n0.map(|x| F4::splat(x)),
            e3: F4::new(&[0.0, 0.0, 0.0, 1.0]),
            inv_c_zxy: F4::new(&[i2, i0, i1, 0.0]),
            inv_c_yzx: F4::new(&[i1, i2, i0, 0.0]),
            inv_c: F4::new(&[i0, i1, i2, 0.0]),
            d_zxy: F4::new(&[i2 - i0, i0 - i1, i1 - i2, 0.0]),
            d_yzx: F4::new(&[i0 - i1, i1 - i2, i2 - i0, 0.0]),
            inv_c_splat: inv_c.map(|x| F4::splat(x)),
            one: F4::splat(1.0),
        }
    }

    /// The constants that make [`full_rate`] return `h` times the rate (every term of the
    /// rate is linear in exactly one of them).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn times(&self, h: f64) -> Self {
        let h4 = F4::splat(h);
        Self {
            e3: self.e3.mul(h4),
            inv_c_zxy: self.inv_c_zxy.mul(h4),
            inv_c_yzx: self.inv_c_yzx.mul(h4),
            inv_c: self.inv_c.mul(h4),
            d_zxy: self.d_zxy.mul(h4),
            d_yzx: self.d_yzx.mul(h4),
            inv_c_splat: self.inv_c_splat.map(|x| x.mul(h4)),
            one: self.one.mul(h4),
            ..*self
        }
    }
}

/// Eq. 1 and `J' = G M + H J` (eq. 4) on the Jacobian path's state `y` into `out`, as
/// [`crate::kirchhoff::Kirchhoff::full_rate`], on the rows of `J`: with `μ = (m, n)` by closed
/// form (A), row `i` of `J'_top` is `c_i⁻¹ (R_0i, R_1i, R_2i, s_0i | s_1i, s_2i)` plus four
/// rows of `J` times coefficients (the entries of `C⁻¹ m̂ − û` and `C⁻¹ n̂`), and the rows of
/// `J'_bot` are rows of `J` times components of `u`.
///
/// Written for the costs of the AVX2 machines this runs on (a lane-crossing permute is slow
/// and scarce, an in-lane shuffle cheap, a broadcast from memory a load; the measured numbers
/// are in `docs/integrator.md`). The coefficients
/// are formed four at a time, stored in `scratch` and broadcast from memory, not permuted out
/// of registers one by one; the rows of `[Rᵀ, −Rᵀ p̂]` come from one 4×4 transpose of in-lane
/// unpacks; `m = Rᵀ m0 − Rᵀ (p × n0)` reuses the `s_k` (`Rᵀ (p × n0) = −Σ_k n0_k s_k`) and is
/// summed as a tree, because the chain from a stage's frame through `m` to the frame's rate
/// is the one the next stage waits on. (Storing `J` by columns instead, as pairs of cross
/// products, takes about 50 permutes a stage, which costs more than the generic loop saves.)
#[inline]
#[target_feature(enable = "avx2,fma")]
fn full_rate(k: &FullConstants, y: &Block, out: &mut Block, scratch: &mut [[f64; 4]; 5]) {
    let y = &y.0;
    let [r0, r1, r2] = [0, 1, 2].map(|i| F4::new(&y[i]));
    let entry = |i: usize, j: usize| F4::splat(y[i][j]);
    let [p0, p1, p2] = [0, 1, 2].map(|i| entry(i, 3));
    // Lane i of s_k is (p × R e_i)_k.
    let s0 = r2.mul_sub(p1, r1.mul(p2));
    let s1 = r0.mul_sub(p2, r2.mul(p0));
    let s2 = r1.mul_sub(p0, r0.mul(p1));
    let n = r2.mul_add(k.n0[2], r1.mul_add(k.n0[1], r0.mul(k.n0[0])));
    // m = Σ_j (m0_j r_j + n0_j s_j), summed as a tree: m is on the chain from one stage to
    // the next.
    let term = |j: usize, r: F4, s: F4| s.mul_add(k.n0[j], r.mul(k.m0[j]));
    let m = term(0, r0, s0).add(term(1, r1, s1)).add(term(2, r2, s2));
    // Lane 3 of m and n is not used: every coefficient below has a zero lane 3.
    let (m_zxy, m_yzx) = (
        m.permute::<{ order::ZXY3 }>(),
        m.permute::<{ order::YZX3 }>(),
    );
    let (n_zxy, n_yzx) = (
        n.permute::<{ order::ZXY3 }>(),
        n.permute::<{ order::YZX3 }>(),
    );
    // Eq. 1: row i of R û is r_i × u, lane 3 R_i0 (= p_i'); the rows' permutes are off
    // the chain through m.
    let u_zxy1 = m_zxy.mul_add(k.inv_c_zxy, k.e3);
    let u_yzx = m_yzx.mul(k.inv_c_yzx);
    for (o, r) in out.0[..3].iter_mut().zip([r0, r1, r2]) {
        *o = cross_lane0(r, u_zxy1, u_yzx).to_array();
    }
    // The coefficients, lane i for row i of J'_top: of t_(i+1), t_(i+2), −b_(i+1), b_(i+2)
    // (rows 0–2 of J are t, rows 3–5 are b), then u.
    *scratch = [
        m_zxy.mul(k.d_zxy),
        m_yzx.mul(k.d_yzx),
        n_zxy.mul(k.inv_c),
        n_yzx.mul(k.inv_c),
        m.mul(k.inv_c),
    ]
    .map(|v| v.to_array());
    let scratch = std::hint::black_box(&*scratch);
    let coefficient = |c: usize, i: usize| F4::splat(scratch[c][i]);
    // Columns 0–3 of row i of [Rᵀ, −Rᵀ p̂] (column i of the rows r0, r1, r2, s0), and
    // columns 4–5 (lanes 0–1 or 2–3 of the unpacked s1, s2).
    let (lo01, hi01) = (r0.unpack_lo(r1), r0.unpack_hi(r1));
    let (lo2s, hi2s) = (r2.unpack_lo(s0), r2.unpack_hi(s0));
    let base_left = [
        lo01.join::<0x20>(lo2s),
        hi01.join::<0x20>(hi2s),
        lo01.join::<0x31>(lo2s),
    ];
    let (lo_s, hi_s) = (s1.unpack_lo(s2), s1.unpack_hi(s2));
    let base_right = [lo_s.low(), hi_s.low(), lo_s.high()];
    let left = |row: usize| F4::new(&y[JL + row]);
    let right = |row: usize| {
        let [a, b, c, d] = y[JR + row / 2];
        F2::new(if row.is_multiple_of(2) {
            [a, b]
        } else {
            [c, d]
        })
    };
    let mut top = [F2::splat(0.0); 3];
    for (i, top) in top.iter_mut().enumerate() {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        let [ca, cb, cc, cd] = [0, 1, 2, 3].map(|c| coefficient(c, i));
        let scale = k.inv_c_splat[i];
        let l = ca.mul_add(left(i1), base_left[i].mul(scale));
        let l = cb.mul_add(left(i2), l);
        let l2 = cd.mul_sub(left(3 + i2), cc.mul(left(3 + i1)));
        let r = ca.low().mul_add(right(i1), base_right[i].mul(scale.low()));
        let r = cb.low().mul_add(right(i2), r);
        let r2 = cd.low().mul_sub(right(3 + i2), cc.low().mul(right(3 + i1)));
        out.0[JL + i] = l.add(l2).to_array();
        *top = r.add(r2);
    }
    // J'_bot = −ê1 J_top − û J_bot: b_0' = u2 b_1 − u1 b_2, b_1' = t_2 + u0 b_2 − u2 b_0,
    // b_2' = −t_1 + u1 b_0 − u0 b_1.
    let [u0, u1, u2] = [0, 1, 2].map(|i| coefficient(4, i));
    let h = k.one;
    out.0[JL + 3] = u1.neg_mul_add(left(5), u2.mul(left(4))).to_array();
    out.0[JL + 4] = u2
        .neg_mul_add(left(3), u0.mul_add(left(5), h.mul(left(2))))
        .to_array();
    out.0[JL + 5] = u0
        .neg_mul_add(left(4), u1.mul_sub(left(3), h.mul(left(1))))
        .to_array();
    let b0 = u1.low().neg_mul_add(right(5), u2.low().mul(right(4)));
    let b1 = u2
        .low()
        .neg_mul_add(right(3), u0.low().mul_add(right(5), h.low().mul(right(2))));
    let b2 = u0
        .low()
        .neg_mul_add(right(4), u1.low().mul_sub(right(3), h.low().mul(right(1))));
    out.0[JR] = F4::from_halves(top[0], top[1]).to_array();
    out.0[JR + 1] = F4::from_halves(top[2], b0).to_array();
    out.0[JR + 2] = F4::from_halves(b1, b2).to_array();
}

/// [`full_rate`], compiled once: each written-out stage of [`full_step`] calls it with its
/// sum in memory, from where the rate broadcasts the entries it needs. (Inlined into each
/// stage, it is twelve copies of the code and runs no faster.)
#[inline(never)]
#[target_feature(enable = "avx2,fma")]
fn full_rate_at(k: &FullConstants, y: &Block, out: &mut Block, scratch: &mut [[f64; 4]; 5]) {
    full_rate(k, y, out, scratch);
}

/// The written-out DOP853 stages of the Jacobian path: stage `i`'s sum `y + Σ_j a_ij k_j`,
/// then its rate.
macro_rules! full_stages {
    ($c:ident, $y:ident, $k:ident, $scratch:ident; $($i:literal: [$($j:literal),*]);*) => {
        $(
            {
                #[allow(unused_mut)]
                let mut s = $y.0.map(|v| F4::new(&v));
                $(
                    let a = F4::splat(DOP853_A[$i][$j]);
                    for (v, kj) in s.iter_mut().zip(&$k[$j].0) {
                        *v = a.mul_add(F4::new(kj), *v);
                    }
                )*
                let sum = Block(s.map(|v| v.to_array()));
                full_rate_at($c, &sum, &mut $k[$i], $scratch);
            }
        )*
    };
}

/// One DOP853 step of the Jacobian path in place, with `c` the constants
/// [`FullConstants::times`] the step size.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn full_step(c: &FullConstants, y: &mut Block, k: &mut [Block; 12], scratch: &mut [[f64; 4]; 5]) {
    with_dop853_terms!(full_stages!(c, y, k, scratch));
    let mut s = y.0.map(|v| F4::new(&v));
    for j in [0, 5, 6, 7, 8, 9, 10, 11] {
        let b = F4::splat(DOP853_B[j]);
        for (v, kj) in s.iter_mut().zip(&k[j].0) {
            *v = b.mul_add(F4::new(kj), *v);
        }
    }
    y.0 = s.map(|v| v.to_array());
}

/// Integrates the frame and `J` from `q = I`, `J = 0` over `grid` (step sizes, and the grid
/// point each step ends on, as [`crate::Integrator::grid`]), for stiffnesses `1 / inv_c` and
/// `a = (m0, n0)`. At each grid point calls `at_point(index, state)`, and stops after the
/// first call that returns `false`. Returns the last state.
#[target_feature(enable = "avx2,fma")]
pub(crate) fn integrate_full(
    inv_c: [f64; 3],
    m0: [f64; 3],
    n0: [f64; 3],
    grid: impl Iterator<Item = (f64, Option<usize>)>,
    mut at_point: impl FnMut(usize, &FullArray) -> bool,
) -> FullArray {
    let c = FullConstants::new(inv_c, m0, n0);
    let mut y = Block([[0.0; 4]; 12]);
    for (i, row) in y.0[..3].iter_mut().enumerate() {
        row[i] = 1.0;
    }
    let mut k = [y; 12];
    let mut scratch = [[0.0; 4]; 5];
    let (mut step_size, mut scaled) = (f64::NAN, c);
    for (h, grid_point) in grid {
        if h.to_bits() != step_size.to_bits() {
            (step_size, scaled) = (h, c.times(h));
        }
        full_step(&scaled, &mut y, &mut k, &mut scratch);
        if let Some(index) = grid_point
            && !at_point(index, bytemuck::cast_ref(&y.0))
        {
            break;
        }
    }
    bytemuck::cast(y.0)
}

/// The septic Hermite basis of [`crate::hermite::septic_hermite`] in monomial form:
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
    // The weights go through memory, so that each is broadcast by a load: from a register,
    // each broadcast is a lane-crossing permute, the scarce resource on this CPU family (see
    // `full_rate`).
    let w = [lo.mul(powers).to_array(), hi.mul(powers).to_array()];
    let w = std::hint::black_box(&w);
    let mut acc = [[F4::splat(0.0); 3]; 2];
    for ((acc, knot), w) in acc.iter_mut().zip([k0, k1]).zip(w) {
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
    use crate::hermite::septic_hermite;

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
