//! Bending and twisting energy of one interior vertex (Bergou et al. 2008, eq. 2–4 and §4.2;
//! reference twist from Bergou et al. 2010, §4.1 and eq. 7).
//!
//! At vertex `i`, between edges `e⁰ = x_i − x_{i−1}` and `e¹ = x_{i+1} − x_i`:
//! - curvature binormal `(κb)_i = 2 t⁰ × t¹ / (1 + t⁰·t¹)` (Bergou 2008, eq. 1);
//! - material curvatures, averaged over the two edges' material frames `(t, m1, m2)`:
//!   `u2 = κb·(m1⁰ + m1¹)/(2ℓ)`, `u3 = κb·(m2⁰ + m2¹)/(2ℓ)`, with `ℓ` the rest Voronoi length;
//!   with `R' = R û` (DESIGN.md) these are the Kirchhoff bending strains about body y and z;
//! - twist `u1 = (θ¹ − θ⁰ + m_ref)/ℓ`, with the reference twist `m_ref` the signed angle about
//!   `t¹` from the space-parallel transport of edge 0's reference director to edge 1's
//!   (Bergou 2010, §4.1);
//! - energy `ℓ/2·[c1 (u1 − ū1)² + c2 (u2 − ū2)² + c3 (u3 − ū3)²]` (Bergou 2008, eq. 3 and 4
//!   with anisotropic bending and natural strains).
//!
//! Evaluation. With `(t, a, b)` the tangent and reference directors of an edge and
//! `m1 = C a + S b`, `m2 = −S a + C b` (`C, S = cos θ, sin θ`), every quantity above reduces to
//! seven dot products between the two edges' directors, `c = t⁰·t¹`, `p = t¹·a⁰`, `q = t¹·b⁰`,
//! `r = t⁰·a¹`, `s = t⁰·b¹`, `α = a⁰·a¹`, `β = a⁰·b¹`:
//! - `ℓ(1 + c)·u2 = −C⁰q + S⁰p + C¹s − S¹r`, `ℓ(1 + c)·u3 = S⁰q + C⁰p − S¹s − C¹r`;
//! - `m_ref = atan2(y, x)` with `x = cα − rp − qs/(1 + c)`, `y = −cβ + sp − qr/(1 + c)`
//!   (the parallel transport `P(t⁰ → t¹)a⁰` dotted with `a¹` and `−b¹`).
//!
//! Each edge's directors depend on its own edge vector only, so they are differentiated once per
//! edge with 3 variables and the dot products assembled directly into the stencil's 8 variables;
//! this is what makes the exact Hessian cheap.
//!
//! Each edge's reference director is the time-parallel transport of the stored director from the
//! stored tangent to the edge's current tangent (Bergou 2010, §4.1), written as a smooth function
//! of the edge vector, so the exact gradient and Hessian (by [`crate::dual`]) include every
//! reference-frame and reference-twist term.

use nalgebra::Vector3;

use crate::dual::{Dual1, Dual2, Scalar, V3, cross, dot, scale};
use crate::transport::transport_from_const;

/// Constants of one bending–twisting stencil.
pub(crate) struct Stencil<'a> {
    /// `(c1, c2, c3)` \[N·m²\].
    pub c: &'a [f64; 3],
    /// Rest strains `(ū1, ū2, ū3)` \[1/m\].
    pub rest: &'a Vector3<f64>,
    /// Rest Voronoi length ℓ \[m\].
    pub voronoi: f64,
}

/// An edge's tangent `t` and reference directors `a = d1`, `b = d2 = t × a`.
#[derive(Clone, Copy)]
pub(crate) struct Directors<S> {
    pub t: V3<S>,
    pub a: V3<S>,
    pub b: V3<S>,
}

/// The directors of an edge from its vector and its stored reference (time-parallel transport).
pub(crate) fn directors<S: Scalar>(
    e: &V3<S>,
    ref_t: &Vector3<f64>,
    ref_d1: &Vector3<f64>,
) -> Directors<S> {
    let inv = S::cst(1.0) / dot(e, e).sqrt();
    let t = scale(e, inv);
    let a = transport_from_const(ref_t, &t, ref_d1);
    let b = cross(&t, &a);
    Directors { t, a, b }
}

/// The seven dot products `(c, p, q, r, s, α, β)` between two edges' directors.
pub(crate) fn dots<S: Scalar>(d0: &Directors<S>, d1: &Directors<S>) -> [S; 7] {
    [
        dot(&d0.t, &d1.t),
        dot(&d1.t, &d0.a),
        dot(&d1.t, &d0.b),
        dot(&d0.t, &d1.a),
        dot(&d0.t, &d1.b),
        dot(&d0.a, &d1.a),
        dot(&d0.a, &d1.b),
    ]
}

/// `u·w` for `u` a function of edge 0 (stencil variables 0..3) and `w` of edge 1 (3..6).
fn cross_dot2(u: &V3<Dual2<3>>, w: &V3<Dual2<3>>) -> Dual2<8> {
    let mut out = Dual2::<8>::cst(0.0);
    for k in 0..3 {
        let (x, y) = (&u[k], &w[k]);
        out.v += x.v * y.v;
        for i in 0..3 {
            out.g[i] += y.v * x.g[i];
            out.g[3 + i] += x.v * y.g[i];
            for j in i..3 {
                out.h[(i, j)] += y.v * x.hess(i, j);
                out.h[(3 + i, 3 + j)] += x.v * y.hess(i, j);
            }
            for j in 0..3 {
                out.h[(i, 3 + j)] += x.g[i] * y.g[j];
            }
        }
    }
    out
}

/// `u·w` for `u` a function of edge 0 and `w` of edge 1, gradient only.
fn cross_dot1(u: &V3<Dual1<3>>, w: &V3<Dual1<3>>) -> Dual1<8> {
    let mut out = Dual1::<8>::cst(0.0);
    for k in 0..3 {
        let (x, y) = (&u[k], &w[k]);
        out.v += x.v * y.v;
        for i in 0..3 {
            out.g[i] += y.v * x.g[i];
            out.g[3 + i] += x.v * y.g[i];
        }
    }
    out
}

/// [`dots`] with exact Hessians, in the stencil variables `(e⁰, e¹, θ⁰, θ¹)`.
pub(crate) fn dots2(d0: &Directors<Dual2<3>>, d1: &Directors<Dual2<3>>) -> [Dual2<8>; 7] {
    [
        cross_dot2(&d0.t, &d1.t),
        cross_dot2(&d0.a, &d1.t),
        cross_dot2(&d0.b, &d1.t),
        cross_dot2(&d0.t, &d1.a),
        cross_dot2(&d0.t, &d1.b),
        cross_dot2(&d0.a, &d1.a),
        cross_dot2(&d0.a, &d1.b),
    ]
}

/// [`dots`] with gradients, in the stencil variables `(e⁰, e¹, θ⁰, θ¹)`.
pub(crate) fn dots1(d0: &Directors<Dual1<3>>, d1: &Directors<Dual1<3>>) -> [Dual1<8>; 7] {
    [
        cross_dot1(&d0.t, &d1.t),
        cross_dot1(&d0.a, &d1.t),
        cross_dot1(&d0.b, &d1.t),
        cross_dot1(&d0.t, &d1.a),
        cross_dot1(&d0.t, &d1.b),
        cross_dot1(&d0.a, &d1.a),
        cross_dot1(&d0.a, &d1.b),
    ]
}

/// The strains `(u1, u2, u3)` \[1/m\] at the vertex from the seven dot products and the two
/// material angles.
pub(crate) fn strains<S: Scalar>(dots: &[S; 7], th0: S, th1: S, st: &Stencil<'_>) -> [S; 3] {
    let [c, p, q, r, s, alpha, beta] = *dots;
    let (c0, s0) = (th0.cos(), th0.sin());
    let (c1, s1) = (th1.cos(), th1.sin());
    let one_c = c + 1.0;
    let k = S::cst(1.0 / st.voronoi) / one_c;
    let u2 = (s0 * p - c0 * q + c1 * s - s1 * r) * k;
    let u3 = (s0 * q + c0 * p - s1 * s - c1 * r) * k;
    let x = c * alpha - r * p - q * s / one_c;
    let y = s * p - c * beta - q * r / one_c;
    let m_ref = y.atan2(x);
    let u1 = (th1 - th0 + m_ref) * (1.0 / st.voronoi);
    [u1, u2, u3]
}

/// `(bending, twisting)` energy \[J\] of the vertex.
pub(crate) fn energy<S: Scalar>(dots: &[S; 7], th0: S, th1: S, st: &Stencil<'_>) -> (S, S) {
    let [u1, u2, u3] = strains(dots, th0, th1, st);
    let half = 0.5 * st.voronoi;
    let d1 = u1 - st.rest.x;
    let d2 = u2 - st.rest.y;
    let d3 = u3 - st.rest.z;
    let bend = (d2 * d2 * st.c[1] + d3 * d3 * st.c[2]) * half;
    let twist = d1 * d1 * (st.c[0] * half);
    (bend, twist)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dual::{add, lin2};
    use crate::transport::transport;

    /// The direct vector formulas of Bergou et al., as a reference for the dot-product form.
    fn reference(
        e0: &Vector3<f64>,
        e1: &Vector3<f64>,
        th: [f64; 2],
        refs: &[(Vector3<f64>, Vector3<f64>); 2],
        l: f64,
    ) -> [f64; 3] {
        let frame = |e: &Vector3<f64>, th: f64, r: &(Vector3<f64>, Vector3<f64>)| {
            let d: Directors<f64> = directors(&[e.x, e.y, e.z], &r.0, &r.1);
            let (s, c) = th.sin_cos();
            (d, lin2(&d.a, c, &d.b, s), lin2(&d.a, -s, &d.b, c))
        };
        let (f0, m10, m20) = frame(e0, th[0], &refs[0]);
        let (f1, m11, m21) = frame(e1, th[1], &refs[1]);
        let kb = scale(&cross(&f0.t, &f1.t), 2.0 / (1.0 + dot(&f0.t, &f1.t)));
        let u2 = dot(&kb, &add(&m10, &m11)) / (2.0 * l);
        let u3 = dot(&kb, &add(&m20, &m21)) / (2.0 * l);
        let pd = transport(&f0.t, &f1.t, &f0.a);
        let m_ref = dot(&cross(&pd, &f1.a), &f1.t).atan2(dot(&pd, &f1.a));
        [(th[1] - th[0] + m_ref) / l, u2, u3]
    }

    #[test]
    fn dot_product_form_matches_the_vector_formulas() {
        let e0 = Vector3::new(0.01, 0.002, -0.001);
        let e1 = Vector3::new(0.008, 0.005, 0.003);
        let refs = [
            (
                Vector3::new(1.0, 0.1, 0.0).normalize(),
                Vector3::new(0.0, 0.3, 1.0),
            ),
            (
                Vector3::new(0.9, 0.4, 0.2).normalize(),
                Vector3::new(-0.2, 0.1, 1.0),
            ),
        ];
        let refs = refs.map(|(t, d): (Vector3<f64>, Vector3<f64>)| {
            (t, crate::transport::perpendicular(&t, &d))
        });
        let th = [0.4, -1.1];
        let st = Stencil {
            c: &[1.0, 1.0, 1.0],
            rest: &Vector3::zeros(),
            voronoi: 0.01,
        };
        let d0: Directors<f64> = directors(&[e0.x, e0.y, e0.z], &refs[0].0, &refs[0].1);
        let d1: Directors<f64> = directors(&[e1.x, e1.y, e1.z], &refs[1].0, &refs[1].1);
        let fast = strains(&dots(&d0, &d1), th[0], th[1], &st);
        let slow = reference(&e0, &e1, th, &refs, 0.01);
        for (f, s) in fast.iter().zip(&slow) {
            assert!(
                (f - s).abs() < 1e-10 * (1.0 + s.abs()),
                "{fast:?} vs {slow:?}"
            );
        }
    }
}
