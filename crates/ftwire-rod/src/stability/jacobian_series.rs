//! `J` and its first three derivatives along the wire at a grid point of the Jacobian solves,
//! from the flat state there (no integration): the data of the interpolant of `det J` between
//! grid points (see the parent module).
//!
//! With closed form (B) of [`crate::equations`], eq. 4's `J' = G M + H J` is linear in `J`:
//!
//! ```text
//! J' = B(q) + (E + P(μ)) J,    B(q) = [C⁻¹ [Rᵀ, −Rᵀ p̂]; 0],    E J = [0; −ê1 J_top],
//! P(μ) J = [C⁻¹ (m̂ J_top + n̂ J_bot) − û J_top; −û J_bot]      (u = C⁻¹ m)
//! ```
//!
//! with `P` linear in `μ = (m, n)`. Differentiating along the wire,
//!
//! ```text
//! J''  = B' + (E + P(μ)) J'  + P(μ') J
//! J''' = B'' + (E + P(μ)) J'' + 2 P(μ') J' + P(μ'') J
//! ```
//!
//! with `μ'` from eq. 3 (`m' = m × u + n × e1`, `n' = n × u`) and its derivative `μ''`, and
//! `B'`, `B''` from `R' = R û`, `R'' = R' û + R û'`, `p' = R e1`, `p'' = R' e1` (row `i` of
//! `−Rᵀ p̂` is `(p × R e_i)ᵀ`, whose derivatives follow by Leibniz's rule).
//!
//! [`jacobian_series`] gives these derivatives as the terms `hᵏ J⁽ᵏ⁾ / k!` of the Taylor series
//! over a step `h`; `first_order` (of [`JacobianState`]) gives `J` and `B`, all that the
//! derivative of `det J` needs (see the parent module). Guarded by
//! `series_matches_the_rate_and_finite_differences` below.

use crate::kirchhoff::{FrameState, FullArray, Kirchhoff, jacobian_row};

/// A matrix of six columns given by its rows.
pub(crate) type Rows<const R: usize> = [[f64; 6]; R];

/// The first terms of a matrix's Taylor series in `θ = (t − t_k)/h` at a grid point `t_k`:
/// `X, h X′, h² X″/2, h³ X‴/6`, each by rows.
pub(crate) type MatrixSeries = [Rows<6>; 4];

/// What the test between grid points needs from a solver's state of `D` numbers.
pub(crate) trait JacobianState<const D: usize> {
    /// `J` and a matrix `X` with `tr(adj J · X) = tr(adj J · J′)`, so that
    /// `(det J)′ = tr(adj J · X)` (Jacobi's formula), both by rows, at the state `y`.
    fn first_order(&self, y: &[f64; D]) -> (Rows<6>, Rows<6>);
    /// The Taylor series of `J` at the state `y` in `θ = (t − t_k)/h`.
    fn series(&self, y: &[f64; D], h: f64) -> MatrixSeries;
}

/// `out += s · (P X + e · E X)` over the rows of `X = (top, bottom)` (three rows each), for
/// `P = [[C⁻¹ m̂ − û, C⁻¹ n̂], [0, −û]]` with `ic = C⁻¹`: zero diagonals, so four terms in a
/// top row and two in a bottom row (as in `Kirchhoff::full_rate`); `E X` puts `−ê1` times
/// the top rows, `(0, x_2, −x_1)`, into the bottom rows.
#[inline(always)]
fn add_rate(
    out: &mut Rows<6>,
    s: f64,
    ic: &[f64; 3],
    [m, n, u]: &[[f64; 3]; 3],
    e: f64,
    x: &Rows<6>,
) {
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        // (v̂)_(i, i+1) = −v_(i+2), (v̂)_(i, i+2) = v_(i+1).
        let top = [
            (u[i2] - ic[i] * m[i2], i1),
            (ic[i] * m[i1] - u[i1], i2),
            (-ic[i] * n[i2], 3 + i1),
            (ic[i] * n[i1], 3 + i2),
        ];
        for (c, k) in top {
            axpy(&mut out[i], s * c, &x[k]);
        }
        axpy(&mut out[3 + i], s * u[i2], &x[3 + i1]);
        axpy(&mut out[3 + i], -s * u[i1], &x[3 + i2]);
    }
    axpy(&mut out[4], s * e, &x[2]);
    axpy(&mut out[5], -s * e, &x[1]);
}

/// `row += s · x`.
#[inline(always)]
pub(crate) fn axpy(row: &mut [f64; 6], s: f64, x: &[f64; 6]) {
    for (r, x) in row.iter_mut().zip(x) {
        *r += s * x;
    }
}

/// `a × b`.
#[inline(always)]
pub(crate) fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `Σ_j s_j v_j`, lane by lane.
#[inline(always)]
pub(crate) fn combine<const N: usize>(terms: [(f64, &[f64; 3]); N]) -> [f64; 3] {
    std::array::from_fn(|i| terms.iter().map(|(s, v)| s * v[i]).sum())
}

/// `v × e1 = (0, v_z, −v_y)`.
#[inline(always)]
pub(crate) fn times_e1(v: &[f64; 3]) -> [f64; 3] {
    [0.0, v[2], -v[1]]
}

/// The Taylor series of `J` at the flat state `y` of the Jacobian solves, for the step `h`
/// (see the module docs; the terms are the derivatives times `hᵏ/k!`, so that products of
/// series are Cauchy products):
///
/// ```text
/// J₁ = h (B₀ + (E + P(μ₀)) J₀)
/// J₂ = h/2 (B₁ + (E + P(μ₀)) J₁ + P(μ₁) J₀)
/// J₃ = h/3 (B₂ + (E + P(μ₀)) J₂ + P(μ₁) J₁ + P(μ₂) J₀)
/// ```
///
/// with `μ_k`, `B_k` the series' terms of `μ` and of `B(q)` (`B₁ = h B′`, `B₂ = h² B″/2`).
#[inline(always)]
pub(crate) fn jacobian_series(model: &Kirchhoff, y: &FullArray, h: f64) -> MatrixSeries {
    let q = FrameState::from_slice(y);
    let ic = model.inv_c();
    let strain = |m: &[f64; 3]| -> [f64; 3] { std::array::from_fn(|i| ic[i] * m[i]) };
    let (m, n) = model.costate(&q);
    let (m, n) = ([m.x, m.y, m.z], [n.x, n.y, n.z]);
    let u = strain(&m);
    // Eq. 3 (m′ = m × u + n × e1, n′ = n × u) and its derivative, as series terms.
    let m1 = combine([(h, &cross(&m, &u)), (h, &times_e1(&n))]);
    let n1 = combine([(h, &cross(&n, &u))]);
    let u1 = strain(&m1);
    let half = 0.5 * h;
    let m2 = combine([
        (half, &cross(&m1, &u)),
        (half, &cross(&m, &u1)),
        (half, &times_e1(&n1)),
    ]);
    let n2 = combine([(half, &cross(&n1, &u)), (half, &cross(&n, &u1))]);
    let u2 = strain(&m2);
    // R′ = R û, so row i of R′ is r_i × u: R₁ = h R û, R₂ = h/2 (R₁ û + R û₁); p′ = R e1.
    let r0: [[f64; 3]; 3] = std::array::from_fn(|i| [q.r[(i, 0)], q.r[(i, 1)], q.r[(i, 2)]]);
    let r1: [[f64; 3]; 3] = std::array::from_fn(|i| combine([(h, &cross(&r0[i], &u))]));
    let r2: [[f64; 3]; 3] =
        std::array::from_fn(|i| combine([(half, &cross(&r1[i], &u)), (half, &cross(&r0[i], &u1))]));
    let r = [r0, r1, r2];
    let column = |k: usize, i: usize| [r[k][0][i], r[k][1][i], r[k][2][i]];
    let p = [
        [q.p.x, q.p.y, q.p.z],
        combine([(h, &column(0, 0))]),
        combine([(half, &column(1, 0))]),
    ];
    // B_k: row i of the top is c_i⁻¹ (R_k e_i, Σ_j p_j × R_(k−j) e_i).
    let base = |k: usize, scale: f64| -> Rows<6> {
        let mut rows = [[0.0; 6]; 6];
        for (i, row) in rows.iter_mut().take(3).enumerate() {
            let mut s = [0.0; 3];
            for (j, p) in p.iter().enumerate().take(k + 1) {
                let c = cross(p, &column(k - j, i));
                s = std::array::from_fn(|l| s[l] + c[l]);
            }
            let e = column(k, i);
            *row = [e[0], e[1], e[2], s[0], s[1], s[2]].map(|v| scale * ic[i] * v);
        }
        rows
    };
    let mu = [m, n, u];
    let mu1 = [m1, n1, u1];
    let mu2 = [m2, n2, u2];
    let j0: Rows<6> = std::array::from_fn(|i| jacobian_row(y, i));
    let mut j1 = base(0, h);
    add_rate(&mut j1, h, &ic, &mu, 1.0, &j0);
    let third = h / 3.0;
    let mut j2 = base(1, half);
    add_rate(&mut j2, half, &ic, &mu, 1.0, &j1);
    add_rate(&mut j2, half, &ic, &mu1, 0.0, &j0);
    let mut j3 = base(2, third);
    add_rate(&mut j3, third, &ic, &mu, 1.0, &j2);
    add_rate(&mut j3, third, &ic, &mu1, 0.0, &j1);
    add_rate(&mut j3, third, &ic, &mu2, 0.0, &j0);
    [j0, j1, j2, j3]
}

impl JacobianState<48> for Kirchhoff {
    /// `J` and `X = B(q)`: `(det J)′ = tr(adj J · J′) = tr(adj J · B) + det J · tr(E + P(μ))`,
    /// and `E + P(μ)` has a zero diagonal.
    #[inline(always)]
    fn first_order(&self, y: &FullArray) -> (Rows<6>, Rows<6>) {
        let ic = self.inv_c();
        let mut b = [[0.0; 6]; 6];
        for (i, row) in b.iter_mut().take(3).enumerate() {
            let e = [y[i], y[4 + i], y[8 + i]];
            let s = cross(&[y[3], y[7], y[11]], &e);
            *row = [e[0], e[1], e[2], s[0], s[1], s[2]].map(|v| ic[i] * v);
        }
        (std::array::from_fn(|i| jacobian_row(y, i)), b)
    }

    #[inline(always)]
    fn series(&self, y: &FullArray, h: f64) -> MatrixSeries {
        jacobian_series(self, y, h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arith::Separate;
    use crate::integrator::{Integrator, Method, Rhs};
    use crate::kirchhoff::FullRhs;
    use crate::stability::between::determinant_and_derivative;
    use nalgebra::Vector6;
    use std::marker::PhantomData;

    /// With `h = 1` the series' terms are `J′`, `J″/2`, `J‴/6`: `J′` is the solver's own
    /// rate, and `J″`, `J‴` the central differences of the lower derivatives along the
    /// solution (whose error falls as `ε²`), on an anisotropic and a round wire; the terms
    /// for another `h` are these times `hᵏ`; and `first_order`'s `X` gives the derivative of
    /// `det J` that `J′` gives.
    #[test]
    fn series_matches_the_rate_and_finite_differences() {
        let a = Vector6::new(0.3, -0.7, 1.2, -2.0, 1.5, 0.4);
        for c in [[1.3, 1.0, 0.6], [0.042, 0.055, 0.055]] {
            let model = Kirchhoff::new(c, &a);
            let f = FullRhs::<Separate> {
                model: &model,
                arith: PhantomData,
            };
            let integ = Integrator::new(Method::Rk8, 1).expect("valid");
            let mut y: FullArray = FrameState::initial();
            for _ in 0..300 {
                y = integ.step(&y, 1e-3, f);
            }
            let series = jacobian_series(&model, &y, 1.0);
            let mut rate = [0.0; 48];
            f.rate(&y, &mut rate);
            for (i, row) in series[1].iter().enumerate() {
                let exact = jacobian_row(&rate, i);
                for (x, e) in row.iter().zip(&exact) {
                    assert!((x - e).abs() <= 1e-12 * (1.0 + e.abs()), "J′ {x} vs {e}");
                }
            }
            let eps = 5e-5;
            let (plus, minus) = (
                jacobian_series(&model, &integ.step(&y, eps, f), 1.0),
                jacobian_series(&model, &integ.step(&y, -eps, f), 1.0),
            );
            for k in 1..4 {
                let scale = series[k]
                    .iter()
                    .flatten()
                    .fold(1.0f64, |s, v| s.max(v.abs()));
                for i in 0..6 {
                    for j in 0..6 {
                        // d/dt of the term k − 1 is k times the term k.
                        let fd = (plus[k - 1][i][j] - minus[k - 1][i][j]) / (2.0 * eps);
                        let e = (fd - k as f64 * series[k][i][j]).abs() / scale;
                        assert!(e < 1e-6, "c = {c:?}, term {k} ({i}, {j}): {e:e}");
                    }
                }
            }
            // Jacobi's formula with X = B gives the derivative of det J that J′ gives.
            let (j, x) = model.first_order(&y);
            assert_eq!(j, series[0]);
            let (_, slope) = determinant_and_derivative(j, x);
            let (_, exact) = determinant_and_derivative(j, series[1]);
            assert!(
                (slope - exact).abs() <= 1e-9 * exact.abs(),
                "{slope} vs {exact}"
            );
            let h = 0.03;
            let scaled = jacobian_series(&model, &y, h);
            for k in 0..4 {
                for (a, b) in scaled[k].iter().flatten().zip(series[k].iter().flatten()) {
                    let b = b * h.powi(k as i32);
                    assert!(
                        (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                        "term {k}: {a} vs {b}"
                    );
                }
            }
        }
    }
}
