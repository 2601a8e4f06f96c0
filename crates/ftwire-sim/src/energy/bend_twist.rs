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
//! Each edge's reference director is the time-parallel transport of the stored director from the
//! stored tangent to the edge's current tangent (Bergou 2010, §4.1), written as a smooth function
//! of the edge vector, so the exact gradient and Hessian (by [`crate::dual`]) include every
//! reference-frame and reference-twist term.

use nalgebra::Vector3;

use crate::dual::{Scalar, V3, add, cross, dot, lin2, scale};
use crate::transport::{transport, transport_from_const};

/// Constants of one bending–twisting stencil.
pub(crate) struct Stencil<'a> {
    /// `(c1, c2, c3)` \[N·m²\].
    pub c: [f64; 3],
    /// Rest strains `(ū1, ū2, ū3)` \[1/m\].
    pub rest: Vector3<f64>,
    /// Rest Voronoi length ℓ \[m\].
    pub voronoi: f64,
    /// Stored reference tangents of the two edges.
    pub ref_t: [&'a Vector3<f64>; 2],
    /// Stored reference directors of the two edges.
    pub ref_d1: [&'a Vector3<f64>; 2],
}

fn unit<S: Scalar>(e: &V3<S>) -> V3<S> {
    let n = dot(e, e).sqrt();
    let inv = S::cst(1.0) / n;
    scale(e, inv)
}

/// The material frame `(t, m1, m2)` of an edge from its vector, stored reference and angle.
pub(crate) fn material_frame<S: Scalar>(
    e: &V3<S>,
    theta: S,
    ref_t: &Vector3<f64>,
    ref_d1: &Vector3<f64>,
) -> (V3<S>, V3<S>, V3<S>, V3<S>) {
    let t = unit(e);
    let d1 = transport_from_const(ref_t, &t, ref_d1);
    let d2 = cross(&t, &d1);
    let (s, c) = (theta.sin(), theta.cos());
    let m1 = lin2(&d1, c, &d2, s);
    let m2 = lin2(&d1, -s, &d2, c);
    (t, d1, m1, m2)
}

/// The strains `(u1, u2, u3)` \[1/m\] at the vertex.
pub(crate) fn strains<S: Scalar>(
    e0: &V3<S>,
    e1: &V3<S>,
    th0: S,
    th1: S,
    st: &Stencil<'_>,
) -> [S; 3] {
    let (t0, d1_0, m1_0, m2_0) = material_frame(e0, th0, st.ref_t[0], st.ref_d1[0]);
    let (t1, d1_1, m1_1, m2_1) = material_frame(e1, th1, st.ref_t[1], st.ref_d1[1]);
    let denom = dot(&t0, &t1) + 1.0;
    let kb = scale(&cross(&t0, &t1), S::cst(2.0) / denom);
    let inv = 0.5 / st.voronoi;
    let u2 = dot(&kb, &add(&m1_0, &m1_1)) * inv;
    let u3 = dot(&kb, &add(&m2_0, &m2_1)) * inv;
    let pd = transport(&t0, &t1, &d1_0);
    let y = dot(&cross(&pd, &d1_1), &t1);
    let x = dot(&pd, &d1_1);
    let m_ref = y.atan2(x);
    let u1 = (th1 - th0 + m_ref) * (1.0 / st.voronoi);
    [u1, u2, u3]
}

/// `(bending, twisting)` energy \[J\] of the vertex.
pub(crate) fn energy<S: Scalar>(
    e0: &V3<S>,
    e1: &V3<S>,
    th0: S,
    th1: S,
    st: &Stencil<'_>,
) -> (S, S) {
    let [u1, u2, u3] = strains(e0, e1, th0, th1, st);
    let half = 0.5 * st.voronoi;
    let d1 = u1 - st.rest.x;
    let d2 = u2 - st.rest.y;
    let d3 = u3 - st.rest.z;
    let bend = (d2 * d2 * st.c[1] + d3 * d3 * st.c[2]) * half;
    let twist = d1 * d1 * (st.c[0] * half);
    (bend, twist)
}
