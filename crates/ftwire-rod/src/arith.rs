//! Multiply–add, fused or not, and the run-time CPU dispatch of the hot loops.
//!
//! The integration loops ([`crate::integrator`]'s stage sums, [`crate::kirchhoff`]'
//! right-hand sides) are sums of products. They are written once, generic over [`MulAdd`], and
//! compiled twice (the DOP853 steps of the shape and Jacobian solves, the jets and the Hermite
//! interpolation also have a third, hand-written AVX2 copy in the `simd` module, checked
//! against these):
//!
//! - with [`Separate`] (`a·b + c`, two roundings) for any x86-64 or other CPU;
//! - with [`Fused`] (`fma(a, b, c)`, one rounding) inside a function compiled for AVX2 and FMA,
//!   chosen at run time when the CPU has both ([`fast_path`]).
//!
//! The two differ only in rounding (a few ulps per operation); the results of one machine are
//! reproducible run to run. Set `FTWIRE_NO_SIMD=1` to force the portable path (for example to
//! compare machines bit for bit).
//!
//! `f64::mul_add` without hardware FMA is a slow library call, so [`Fused`] is only ever
//! instantiated inside the AVX2+FMA functions.

use std::sync::OnceLock;

/// `a·b + c`, fused or not.
pub(crate) trait MulAdd {
    /// `a·b + c`.
    fn mul_add(a: f64, b: f64, c: f64) -> f64;
}

/// `a·b + c` with two roundings: portable.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Separate;

/// `a·b + c` with one rounding (a hardware FMA): only inside `#[target_feature(enable = "fma")]`
/// code.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Fused;

impl MulAdd for Separate {
    #[inline(always)]
    fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
}

impl MulAdd for Fused {
    #[inline(always)]
    fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
}

/// Four lanes of `f64`, for code written once over 4-wide vectors: LLVM compiles the
/// lane-wise operations to single AVX instructions inside the AVX2+FMA functions, and to
/// pairs of SSE2 instructions elsewhere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct V4(pub [f64; 4]);

impl V4 {
    /// Lanes `i..i + 4` of `y`.
    #[inline(always)]
    pub fn load(y: &[f64], i: usize) -> Self {
        Self([y[i], y[i + 1], y[i + 2], y[i + 3]])
    }

    /// Writes the lanes to `y[i..i + 4]`.
    #[inline(always)]
    pub fn store(self, y: &mut [f64], i: usize) {
        y[i..i + 4].copy_from_slice(&self.0);
    }

    /// Lane-wise `self + b`.
    #[inline(always)]
    pub fn add(self, b: Self) -> Self {
        Self(std::array::from_fn(|i| self.0[i] + b.0[i]))
    }

    /// Lane-wise `self · b`.
    #[inline(always)]
    pub fn mul(self, b: Self) -> Self {
        Self(std::array::from_fn(|i| self.0[i] * b.0[i]))
    }

    /// Lane-wise `self · s`.
    #[inline(always)]
    pub fn scale(self, s: f64) -> Self {
        Self(std::array::from_fn(|i| self.0[i] * s))
    }

    /// Lane-wise `self · b + c`, multiply–added by `A`.
    #[inline(always)]
    pub fn mul_add<A: MulAdd>(self, b: Self, c: Self) -> Self {
        Self(std::array::from_fn(|i| {
            A::mul_add(self.0[i], b.0[i], c.0[i])
        }))
    }

    /// Lane-wise `s · self + c`, multiply–added by `A`.
    #[inline(always)]
    pub fn scale_add<A: MulAdd>(self, s: f64, c: Self) -> Self {
        Self(std::array::from_fn(|i| A::mul_add(s, self.0[i], c.0[i])))
    }

    /// The lanes in the order `idx` (lane `k` of the result is lane `idx[k]` of `self`).
    #[inline(always)]
    pub fn permute(self, idx: [usize; 4]) -> Self {
        Self(idx.map(|k| self.0[k]))
    }
}

/// Two lanes of `f64`, as [`V4`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct V2(pub [f64; 2]);

impl V2 {
    /// Lanes `i..i + 2` of `y`.
    #[inline(always)]
    pub fn load(y: &[f64], i: usize) -> Self {
        Self([y[i], y[i + 1]])
    }

    /// Lane-wise `self · s`.
    #[inline(always)]
    pub fn scale(self, s: f64) -> Self {
        Self([self.0[0] * s, self.0[1] * s])
    }

    /// Lane-wise `s · self + c`, multiply–added by `A`.
    #[inline(always)]
    pub fn scale_add<A: MulAdd>(self, s: f64, c: Self) -> Self {
        Self([
            A::mul_add(s, self.0[0], c.0[0]),
            A::mul_add(s, self.0[1], c.0[1]),
        ])
    }
}

/// Whether the AVX2+FMA versions of the hot loops may run: the CPU has AVX2 and FMA, and
/// `FTWIRE_NO_SIMD` is not set (checked once per process).
pub(crate) fn fast_path() -> bool {
    static FAST: OnceLock<bool> = OnceLock::new();
    *FAST.get_or_init(|| {
        let disabled = std::env::var_os("FTWIRE_NO_SIMD").is_some_and(|v| !v.is_empty());
        !disabled && cpu_has_avx2_fma()
    })
}

#[cfg(target_arch = "x86_64")]
fn cpu_has_avx2_fma() -> bool {
    std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
}

#[cfg(not(target_arch = "x86_64"))]
fn cpu_has_avx2_fma() -> bool {
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_multiply_add() {
        assert_eq!(Separate::mul_add(2.0, 3.0, 1.0), 7.0);
        assert_eq!(Fused::mul_add(2.0, 3.0, 1.0), 7.0);
        // One rounding: (1 + ε)(1 − ε) − 1 = −ε² exactly, which two roundings lose.
        let e = f64::EPSILON;
        assert_eq!(Fused::mul_add(1.0 + e, 1.0 - e, -1.0), -e * e);
        assert_eq!(Separate::mul_add(1.0 + e, 1.0 - e, -1.0), 0.0);
    }
}
