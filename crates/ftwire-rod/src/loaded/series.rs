//! The loaded solver's side of the stability test between grid points
//! ([`crate::stability::JacobianState`]): `J` with the part of its rate that `det J`'s
//! derivative sees, and the Taylor series of `J` at a grid point from the state there.
//!
//! The loaded solver integrates `X = (M_m, J_ω, J_v)` (nine rows), whose rate is linear in
//! `X` (see `Loaded::full_rate` and [`crate::load`]):
//!
//! ```text
//! X′ = B(R) + (E + P(μ)) X,   B: (0, R_·2) into row a_1, −(0, R_·1) into row a_2,
//! E X: t_i += c_i⁻¹ a_i, b_1 += t_2, b_2 −= t_1,
//! P(μ) X: a_i += K_ij a_j (K = m̂ C⁻¹ − û), a_1 += −n1 t_0 + n0 t_1, a_2 += −n2 t_0 + n0 t_2,
//!         t += −û t, b += −û b,
//! ```
//!
//! with `u = C⁻¹ m + u₀` affine in `m` (so `P(μ_k)` for `k ≥ 1` takes `u_k = C⁻¹ m_k`). The
//! series follow as for the unloaded solver (`stability::jacobian_series`), with the loaded
//! `m′ = m × u + n × e1`, `n′ = n × u − Rᵀ w` and their derivatives (`(Rᵀ w)′ = Rᵀ w × u`).
//!
//! Guarded by `loaded_series_matches_the_rate_and_finite_differences` below.

use super::{FULL, Loaded, LoadedFullArray, matrix_rows};
use crate::stability::{JacobianState, MatrixSeries, Rows, axpy, combine, cross, times_e1};

/// `J` (the rows of `J_ω`, then of `J_v`) of `X`'s nine rows.
#[inline(always)]
fn jacobian_rows_of(x: &Rows<9>) -> Rows<6> {
    std::array::from_fn(|i| x[3 + i])
}

/// `out += s · (P X + e · E X)` over the nine rows `a, t, b` of `X` (see the module docs),
/// with `ic = C⁻¹`.
#[inline(always)]
fn add_rate(
    out: &mut Rows<9>,
    s: f64,
    ic: &[f64; 3],
    [m, n, u]: &[[f64; 3]; 3],
    e: f64,
    x: &Rows<9>,
) {
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        // K = m̂ C⁻¹ − û off the diagonal; −û over the rows of t and of b.
        axpy(&mut out[i], s * (u[i2] - m[i2] * ic[i1]), &x[i1]);
        axpy(&mut out[i], s * (m[i1] * ic[i2] - u[i1]), &x[i2]);
        axpy(&mut out[3 + i], s * e * ic[i], &x[i]);
        for base in [3, 6] {
            axpy(&mut out[base + i], s * u[i2], &x[base + i1]);
            axpy(&mut out[base + i], -s * u[i1], &x[base + i2]);
        }
    }
    // −ê1 n̂ J_ω into a_1 and a_2; −ê1 J_ω into b_1 and b_2.
    axpy(&mut out[1], -s * n[1], &x[3]);
    axpy(&mut out[1], s * n[0], &x[4]);
    axpy(&mut out[2], -s * n[2], &x[3]);
    axpy(&mut out[2], s * n[0], &x[5]);
    axpy(&mut out[7], s * e, &x[5]);
    axpy(&mut out[8], -s * e, &x[4]);
}

impl Loaded {
    /// The Taylor series of `X = (M_m, J_ω, J_v)` at the full state `y`, for the step `h`
    /// (terms `hᵏ X⁽ᵏ⁾ / k!`; see the module docs and `stability::jacobian_series`).
    #[inline(always)]
    fn matrix_series(&self, y: &LoadedFullArray, h: f64) -> [Rows<9>; 4] {
        let ic = [self.inv_c.x, self.inv_c.y, self.inv_c.z];
        let strain = |m: &[f64; 3]| -> [f64; 3] { std::array::from_fn(|i| ic[i] * m[i]) };
        // R by rows (y holds it by columns), m, n, u = C⁻¹ m + u₀, Rᵀ w.
        let r0: [[f64; 3]; 3] = std::array::from_fn(|i| [y[i], y[3 + i], y[6 + i]]);
        let (m, n) = ([y[12], y[13], y[14]], [y[15], y[16], y[17]]);
        let u: [f64; 3] = std::array::from_fn(|i| ic[i] * m[i] + self.u0[i]);
        let w = [self.w.x, self.w.y, self.w.z];
        let rtw: [f64; 3] = std::array::from_fn(|j| (0..3).map(|i| r0[i][j] * w[i]).sum());
        let half = 0.5 * h;
        let m1 = combine([(h, &cross(&m, &u)), (h, &times_e1(&n))]);
        let n1 = combine([(h, &cross(&n, &u)), (-h, &rtw)]);
        let u1 = strain(&m1);
        // h Rᵀ′ w = h Rᵀ w × u.
        let rtw1 = combine([(h, &cross(&rtw, &u))]);
        let m2 = combine([
            (half, &cross(&m1, &u)),
            (half, &cross(&m, &u1)),
            (half, &times_e1(&n1)),
        ]);
        let n2 = combine([
            (half, &cross(&n1, &u)),
            (half, &cross(&n, &u1)),
            (-half, &rtw1),
        ]);
        let u2 = strain(&m2);
        let r1: [[f64; 3]; 3] = std::array::from_fn(|i| combine([(h, &cross(&r0[i], &u))]));
        let r2: [[f64; 3]; 3] = std::array::from_fn(|i| {
            combine([(half, &cross(&r1[i], &u)), (half, &cross(&r0[i], &u1))])
        });
        // B_k: (0, R_k e_2) into a_1, −(0, R_k e_1) into a_2.
        let base = |r: &[[f64; 3]; 3], scale: f64| -> Rows<9> {
            let mut rows = [[0.0; 6]; 9];
            for i in 0..3 {
                rows[1][3 + i] = scale * r[i][2];
                rows[2][3 + i] = -scale * r[i][1];
            }
            rows
        };
        let mu = [m, n, u];
        let mu1 = [m1, n1, u1];
        let mu2 = [m2, n2, u2];
        let x0 = matrix_rows(y);
        let third = h / 3.0;
        let mut x1 = base(&r0, h);
        add_rate(&mut x1, h, &ic, &mu, 1.0, &x0);
        let mut x2 = base(&r1, half);
        add_rate(&mut x2, half, &ic, &mu, 1.0, &x1);
        add_rate(&mut x2, half, &ic, &mu1, 0.0, &x0);
        let mut x3 = base(&r2, third);
        add_rate(&mut x3, third, &ic, &mu, 1.0, &x2);
        add_rate(&mut x3, third, &ic, &mu1, 0.0, &x1);
        add_rate(&mut x3, third, &ic, &mu2, 0.0, &x0);
        [x0, x1, x2, x3]
    }
}

impl JacobianState<FULL> for Loaded {
    /// `J` and `X = [C⁻¹ M_m; 0]`: the rest of `J′` is `[−û J_ω; −ê1 J_ω − û J_v]`, a matrix
    /// with a zero diagonal times `J`, which adds nothing to `tr(adj J · J′)`.
    #[inline(always)]
    fn first_order(&self, y: &LoadedFullArray) -> (Rows<6>, Rows<6>) {
        let rows = matrix_rows(y);
        let ic = [self.inv_c.x, self.inv_c.y, self.inv_c.z];
        let mut x = [[0.0; 6]; 6];
        for (i, row) in x.iter_mut().take(3).enumerate() {
            *row = rows[i].map(|v| ic[i] * v);
        }
        (jacobian_rows_of(&rows), x)
    }

    fn series(&self, y: &LoadedFullArray, h: f64) -> MatrixSeries {
        self.matrix_series(y, h).map(|x| jacobian_rows_of(&x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Load;
    use crate::arith::Separate;
    use crate::integrator::{Integrator, Method};
    use crate::stability::between::determinant_and_derivative;
    use nalgebra::{Vector3, Vector6};

    /// With `h = 1` the series' terms are `X′`, `X″/2`, `X‴/6`: `X′` is the loaded solver's
    /// own rate, and `X″`, `X‴` the central differences of the lower terms along the
    /// solution, under weight and rest curvature on an anisotropic wire; and `first_order`'s
    /// matrix gives the derivative of `det J` that `J′` gives.
    #[test]
    fn loaded_series_matches_the_rate_and_finite_differences() {
        let load = Load::from_gravity(6450.0, 0.001, Vector3::new(0.3, -0.5, -9.81))
            .expect("valid")
            .with_natural_curvature(Vector3::new(0.4, -1.0, 2.0))
            .expect("valid");
        let a = Vector6::new(0.03, -0.07, 0.12, -0.2, 0.15, 0.04);
        let model = Loaded::new([0.13, 0.10, 0.06], &load, &a);
        let f =
            |y: &LoadedFullArray, out: &mut LoadedFullArray| model.full_rate::<Separate>(y, out);
        let integ = Integrator::new(Method::Rk8, 1).expect("valid");
        let mut y = model.full_initial();
        for _ in 0..300 {
            y = integ.step(&y, 1e-3, f);
        }
        let series = model.matrix_series(&y, 1.0);
        let mut rate = [0.0; FULL];
        f(&y, &mut rate);
        for (row, exact) in series[1].iter().zip(matrix_rows(&rate)) {
            for (x, e) in row.iter().zip(&exact) {
                assert!((x - e).abs() <= 1e-12 * (1.0 + e.abs()), "X′ {x} vs {e}");
            }
        }
        // Jacobi's formula with X = [C⁻¹ M_m; 0] gives the derivative of det J that J′ gives.
        let (j, x) = model.first_order(&y);
        let (_, slope) = determinant_and_derivative(j, x);
        let (_, exact) = determinant_and_derivative(j, jacobian_rows_of(&series[1]));
        assert!(
            (slope - exact).abs() <= 1e-9 * exact.abs(),
            "{slope} vs {exact}"
        );
        let eps = 5e-5;
        let (plus, minus) = (
            model.matrix_series(&integ.step(&y, eps, f), 1.0),
            model.matrix_series(&integ.step(&y, -eps, f), 1.0),
        );
        for k in 2..4 {
            let scale = series[k]
                .iter()
                .flatten()
                .fold(1.0f64, |s, v| s.max(v.abs()));
            for i in 0..9 {
                for j in 0..6 {
                    let fd = (plus[k - 1][i][j] - minus[k - 1][i][j]) / (2.0 * eps);
                    let e = (fd - k as f64 * series[k][i][j]).abs() / scale;
                    assert!(e < 1e-6, "term {k} ({i}, {j}): {e:e}");
                }
            }
        }
    }
}
