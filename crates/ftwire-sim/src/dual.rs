//! Second-order forward-mode automatic differentiation for the rod's stencil energies.
//!
//! A [`Dual2<N>`] carries a value, its gradient and its Hessian with respect to `N` seed
//! variables. Each stencil energy of the discrete elastic rod (Bergou et al. 2008, eq. 2–4 for
//! bending and twisting; Bergou et al. 2010, §4 for the reference twist) is written once,
//! generic over [`Scalar`], and evaluated either with `f64` (energy only, for line searches) or
//! with `Dual2<N>` (energy, exact gradient and exact Hessian, for Newton's method). This keeps the
//! reference-twist terms consistent between energy, gradient and Hessian by construction.
//!
//! **Why hand-written, not `num-dual`.** `num-dual` 0.15 offers the same thing
//! (`Dual2SVec64<11>`: value, gradient and Hessian in 11 variables, on the same nalgebra), adds
//! only itself to the build, and agrees with this module to rounding. It is not used because:
//! - the Hessian is the hot path of every Newton iteration, and this module updates only the
//!   upper triangle of the symmetric Hessian, on plain fixed-size arrays, where `num-dual`
//!   updates the full matrix behind an `Option` per derivative, so it does less work per
//!   stencil (the measurement, with its date and machine, is in `benches/README.md`);
//! - the stencils need only [`Scalar`]: arithmetic, `sqrt`, `sin`, `cos` and `atan2`; being
//!   generic over `num-dual`'s `DualNum` (the whole `num-traits` float surface) would tie every
//!   stencil to a much larger trait for no new capability.
//!
//! The derivative tests of `energy` (against central finite differences) guard both the
//! numbers and the stencils.

use std::ops::{Add, Div, Mul, Neg, Sub};

use nalgebra::{SMatrix, SVector};

/// The number type the stencil energies are written in: `f64`, or a [`Dual2`].
pub trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
{
    /// A constant (zero derivatives).
    fn cst(value: f64) -> Self;
    /// The value, without derivatives.
    fn re(&self) -> f64;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Sine.
    fn sin(self) -> Self;
    /// Cosine.
    fn cos(self) -> Self;
    /// Four-quadrant arctangent of `self / x`.
    fn atan2(self, x: Self) -> Self;
}

impl Scalar for f64 {
    fn cst(value: f64) -> Self {
        value
    }
    fn re(&self) -> f64 {
        *self
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    fn sin(self) -> Self {
        f64::sin(self)
    }
    fn cos(self) -> Self {
        f64::cos(self)
    }
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
}

/// A number with its gradient and Hessian with respect to `N` variables.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dual2<const N: usize> {
    /// Value.
    pub v: f64,
    /// Gradient.
    pub g: SVector<f64, N>,
    /// Hessian; only its upper triangle is meaningful (read it with [`Dual2::hess`]).
    pub h: SMatrix<f64, N, N>,
}

impl<const N: usize> Dual2<N> {
    /// The `i`-th seed variable with value `v`.
    pub fn var(v: f64, i: usize) -> Self {
        let mut g = SVector::zeros();
        g[i] = 1.0;
        Self {
            v,
            g,
            h: SMatrix::zeros(),
        }
    }

    /// Applies a scalar function with value `f0` and derivatives `f1`, `f2` at `self.v`.
    ///
    /// Only the upper triangle of the Hessian is kept up to date (see [`Dual2::hess`]).
    #[inline]
    fn chain(self, f0: f64, f1: f64, f2: f64) -> Self {
        let mut h = SMatrix::<f64, N, N>::zeros();
        for j in 0..N {
            let gj = f2 * self.g[j];
            for i in 0..=j {
                h[(i, j)] = f1 * self.h[(i, j)] + gj * self.g[i];
            }
        }
        Self {
            v: f0,
            g: self.g * f1,
            h,
        }
    }

    /// The Hessian entry `(i, j)`. Products and functions update only the upper triangle,
    /// so entries are read from there.
    #[inline]
    pub fn hess(&self, i: usize, j: usize) -> f64 {
        if i <= j {
            self.h[(i, j)]
        } else {
            self.h[(j, i)]
        }
    }

    fn recip(self) -> Self {
        let r = 1.0 / self.v;
        self.chain(r, -r * r, 2.0 * r * r * r)
    }
}

impl<const N: usize> Scalar for Dual2<N> {
    fn cst(value: f64) -> Self {
        Self {
            v: value,
            g: SVector::zeros(),
            h: SMatrix::zeros(),
        }
    }
    fn re(&self) -> f64 {
        self.v
    }
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * self.v))
    }
    fn sin(self) -> Self {
        let (s, c) = self.v.sin_cos();
        self.chain(s, c, -s)
    }
    fn cos(self) -> Self {
        let (s, c) = self.v.sin_cos();
        self.chain(c, -s, -c)
    }
    fn atan2(self, x: Self) -> Self {
        // Rotate (x, y) by −a0 so that the point lies on the positive x axis, then
        // atan2(y, x) = a0 + atan(y'/x') with y' = 0 at the evaluation point.
        let a0 = self.v.atan2(x.v);
        let (s, c) = a0.sin_cos();
        let xr = x * c + self * s;
        let yr = self * c - x * s;
        let u = yr / xr;
        let d = 1.0 + u.v * u.v;
        u.chain(a0 + u.v.atan(), 1.0 / d, -2.0 * u.v / (d * d))
    }
}

impl<const N: usize> Add for Dual2<N> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self {
            v: self.v + o.v,
            g: self.g + o.g,
            h: self.h + o.h,
        }
    }
}

impl<const N: usize> Sub for Dual2<N> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self {
            v: self.v - o.v,
            g: self.g - o.g,
            h: self.h - o.h,
        }
    }
}

impl<const N: usize> Mul for Dual2<N> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let mut h = SMatrix::<f64, N, N>::zeros();
        for j in 0..N {
            let (aj, bj) = (self.g[j], o.g[j]);
            for i in 0..=j {
                h[(i, j)] =
                    self.v * o.h[(i, j)] + o.v * self.h[(i, j)] + self.g[i] * bj + o.g[i] * aj;
            }
        }
        Self {
            v: self.v * o.v,
            g: o.g * self.v + self.g * o.v,
            h,
        }
    }
}

impl<const N: usize> Div for Dual2<N> {
    type Output = Self;
    #[inline]
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, o: Self) -> Self {
        self * o.recip()
    }
}

impl<const N: usize> Neg for Dual2<N> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self {
            v: -self.v,
            g: -self.g,
            h: -self.h,
        }
    }
}

impl<const N: usize> Add<f64> for Dual2<N> {
    type Output = Self;
    #[inline]
    fn add(self, o: f64) -> Self {
        Self {
            v: self.v + o,
            ..self
        }
    }
}

impl<const N: usize> Sub<f64> for Dual2<N> {
    type Output = Self;
    #[inline]
    fn sub(self, o: f64) -> Self {
        Self {
            v: self.v - o,
            ..self
        }
    }
}

impl<const N: usize> Mul<f64> for Dual2<N> {
    type Output = Self;
    #[inline]
    fn mul(self, o: f64) -> Self {
        Self {
            v: self.v * o,
            g: self.g * o,
            h: self.h * o,
        }
    }
}

/// A number with its gradient with respect to `N` variables (first-order forward mode), for
/// gradient-only evaluations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dual1<const N: usize> {
    /// Value.
    pub v: f64,
    /// Gradient.
    pub g: SVector<f64, N>,
}

impl<const N: usize> Dual1<N> {
    /// The `i`-th seed variable with value `v`.
    pub fn var(v: f64, i: usize) -> Self {
        let mut g = SVector::zeros();
        g[i] = 1.0;
        Self { v, g }
    }

    #[inline]
    fn chain(self, f0: f64, f1: f64) -> Self {
        Self {
            v: f0,
            g: self.g * f1,
        }
    }
}

impl<const N: usize> Scalar for Dual1<N> {
    fn cst(value: f64) -> Self {
        Self {
            v: value,
            g: SVector::zeros(),
        }
    }
    fn re(&self) -> f64 {
        self.v
    }
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s)
    }
    fn sin(self) -> Self {
        let (s, c) = self.v.sin_cos();
        self.chain(s, c)
    }
    fn cos(self) -> Self {
        let (s, c) = self.v.sin_cos();
        self.chain(c, -s)
    }
    fn atan2(self, x: Self) -> Self {
        let r2 = x.v * x.v + self.v * self.v;
        Self {
            v: self.v.atan2(x.v),
            g: (self.g * x.v - x.g * self.v) / r2,
        }
    }
}

impl<const N: usize> Add for Dual1<N> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self {
            v: self.v + o.v,
            g: self.g + o.g,
        }
    }
}

impl<const N: usize> Sub for Dual1<N> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self {
            v: self.v - o.v,
            g: self.g - o.g,
        }
    }
}

impl<const N: usize> Mul for Dual1<N> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        Self {
            v: self.v * o.v,
            g: o.g * self.v + self.g * o.v,
        }
    }
}

impl<const N: usize> Div for Dual1<N> {
    type Output = Self;
    #[inline]
    fn div(self, o: Self) -> Self {
        let r = 1.0 / o.v;
        Self {
            v: self.v * r,
            g: (self.g - o.g * (self.v * r)) * r,
        }
    }
}

impl<const N: usize> Neg for Dual1<N> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self {
            v: -self.v,
            g: -self.g,
        }
    }
}

impl<const N: usize> Add<f64> for Dual1<N> {
    type Output = Self;
    #[inline]
    fn add(self, o: f64) -> Self {
        Self {
            v: self.v + o,
            ..self
        }
    }
}

impl<const N: usize> Sub<f64> for Dual1<N> {
    type Output = Self;
    #[inline]
    fn sub(self, o: f64) -> Self {
        Self {
            v: self.v - o,
            ..self
        }
    }
}

impl<const N: usize> Mul<f64> for Dual1<N> {
    type Output = Self;
    #[inline]
    fn mul(self, o: f64) -> Self {
        Self {
            v: self.v * o,
            g: self.g * o,
        }
    }
}

/// A 3-vector of scalars, for the stencil formulas.
pub type V3<S> = [S; 3];

/// Dot product.
#[inline]
pub fn dot<S: Scalar>(a: &V3<S>, b: &V3<S>) -> S {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Dot product with a constant vector.
#[inline]
pub fn dot_c<S: Scalar>(a: &V3<S>, b: &nalgebra::Vector3<f64>) -> S {
    a[0] * b.x + a[1] * b.y + a[2] * b.z
}

/// Cross product.
#[inline]
pub fn cross<S: Scalar>(a: &V3<S>, b: &V3<S>) -> V3<S> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Cross product with a constant on the right.
#[inline]
pub fn cross_c<S: Scalar>(a: &V3<S>, b: &nalgebra::Vector3<f64>) -> V3<S> {
    [
        a[1] * b.z - a[2] * b.y,
        a[2] * b.x - a[0] * b.z,
        a[0] * b.y - a[1] * b.x,
    ]
}

/// `a·s + b·t` for scalars `s`, `t`.
#[cfg(test)]
#[inline]
pub fn lin2<S: Scalar>(a: &V3<S>, s: S, b: &V3<S>, t: S) -> V3<S> {
    [
        a[0] * s + b[0] * t,
        a[1] * s + b[1] * t,
        a[2] * s + b[2] * t,
    ]
}

/// `a · s`.
#[inline]
pub fn scale<S: Scalar>(a: &V3<S>, s: S) -> V3<S> {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `a + b`.
#[cfg(test)]
#[inline]
pub fn add<S: Scalar>(a: &V3<S>, b: &V3<S>) -> V3<S> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f<S: Scalar>(x: S, y: S) -> S {
        (x * y + x.sin()).sqrt() / (y.cos() + 2.0) + y.atan2(x - 3.0)
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let (x0, y0) = (0.7, -0.4);
        let d = f(Dual2::<2>::var(x0, 0), Dual2::<2>::var(y0, 1));
        let d1 = f(Dual1::<2>::var(x0, 0), Dual1::<2>::var(y0, 1));
        assert!((d1.g - d.g).norm() < 1e-14 && (d1.v - d.v).abs() < 1e-15);
        assert!((d.v - f(x0, y0)).abs() < 1e-14);
        let e = 1e-5;
        let gx = (f(x0 + e, y0) - f(x0 - e, y0)) / (2.0 * e);
        let gy = (f(x0, y0 + e) - f(x0, y0 - e)) / (2.0 * e);
        assert!((d.g[0] - gx).abs() < 1e-8 && (d.g[1] - gy).abs() < 1e-8);
        let e = 1e-4;
        let hxy = (f(x0 + e, y0 + e) - f(x0 + e, y0 - e) - f(x0 - e, y0 + e) + f(x0 - e, y0 - e))
            / (4.0 * e * e);
        let hxx = (f(x0 + e, y0) - 2.0 * f(x0, y0) + f(x0 - e, y0)) / (e * e);
        assert!(
            (d.hess(0, 1) - hxy).abs() < 1e-5,
            "{} {}",
            d.hess(0, 1),
            hxy
        );
        assert!((d.hess(1, 0) - hxy).abs() < 1e-5);
        assert!((d.hess(0, 0) - hxx).abs() < 1e-5);
    }
}
