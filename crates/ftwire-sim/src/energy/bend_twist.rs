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

use crate::dual::{Dual1, Dual2, Scalar, V3, add, cross, dot, lin2, scale};
use crate::transport::{transport, transport_from_const};

/// Constants of one bending–twisting stencil.
pub(crate) struct Stencil<'a> {
    /// `(c1, c2, c3)` \[N·m²\].
    pub c: &'a [f64; 3],
    /// Rest strains `(ū1, ū2, ū3)` \[1/m\].
    pub rest: &'a Vector3<f64>,
    /// Rest Voronoi length ℓ \[m\].
    pub voronoi: f64,
}

fn unit<S: Scalar>(e: &V3<S>) -> V3<S> {
    let n = dot(e, e).sqrt();
    let inv = S::cst(1.0) / n;
    scale(e, inv)
}

/// An edge's tangent, reference director and material directors.
#[derive(Clone, Copy)]
pub(crate) struct EdgeFrame<S> {
    pub t: V3<S>,
    pub d1: V3<S>,
    pub m1: V3<S>,
    pub m2: V3<S>,
}

/// The material frame `(t, m1, m2)` of an edge from its vector, stored reference and angle.
pub(crate) fn edge_frame<S: Scalar>(
    e: &V3<S>,
    theta: S,
    ref_t: &Vector3<f64>,
    ref_d1: &Vector3<f64>,
) -> EdgeFrame<S> {
    let t = unit(e);
    let d1 = transport_from_const(ref_t, &t, ref_d1);
    let d2 = cross(&t, &d1);
    let (s, c) = (theta.sin(), theta.cos());
    let m1 = lin2(&d1, c, &d2, s);
    let m2 = lin2(&d1, -s, &d2, c);
    EdgeFrame { t, d1, m1, m2 }
}

/// Lifts a per-edge dual number (variables `e_x, e_y, e_z, θ`) into the stencil's 8 variables
/// at positions `idx`.
pub(crate) fn lift(d: &Dual2<4>, idx: [usize; 4]) -> Dual2<8> {
    let mut out = Dual2::<8>::cst(d.v);
    for a in 0..4 {
        out.g[idx[a]] = d.g[a];
        for b in 0..4 {
            let (i, j) = (idx[a], idx[b]);
            if i <= j {
                out.h[(i, j)] = d.hess(a, b);
            }
        }
    }
    out
}

/// Lifts a whole edge frame.
pub(crate) fn lift_frame(f: &EdgeFrame<Dual2<4>>, idx: [usize; 4]) -> EdgeFrame<Dual2<8>> {
    let l3 = |v: &V3<Dual2<4>>| [lift(&v[0], idx), lift(&v[1], idx), lift(&v[2], idx)];
    EdgeFrame {
        t: l3(&f.t),
        d1: l3(&f.d1),
        m1: l3(&f.m1),
        m2: l3(&f.m2),
    }
}

/// The strains `(u1, u2, u3)` \[1/m\] at the vertex between two edges.
pub(crate) fn strains<S: Scalar>(
    f0: &EdgeFrame<S>,
    f1: &EdgeFrame<S>,
    th0: S,
    th1: S,
    st: &Stencil<'_>,
) -> [S; 3] {
    let denom = dot(&f0.t, &f1.t) + 1.0;
    let kb = scale(&cross(&f0.t, &f1.t), S::cst(2.0) / denom);
    let inv = 0.5 / st.voronoi;
    let u2 = dot(&kb, &add(&f0.m1, &f1.m1)) * inv;
    let u3 = dot(&kb, &add(&f0.m2, &f1.m2)) * inv;
    let pd = transport(&f0.t, &f1.t, &f0.d1);
    let y = dot(&cross(&pd, &f1.d1), &f1.t);
    let x = dot(&pd, &f1.d1);
    let m_ref = y.atan2(x);
    let u1 = (th1 - th0 + m_ref) * (1.0 / st.voronoi);
    [u1, u2, u3]
}

/// `(bending, twisting)` energy \[J\] of the vertex between two edges.
pub(crate) fn energy<S: Scalar>(
    f0: &EdgeFrame<S>,
    f1: &EdgeFrame<S>,
    th0: S,
    th1: S,
    st: &Stencil<'_>,
) -> (S, S) {
    let [u1, u2, u3] = strains(f0, f1, th0, th1, st);
    let half = 0.5 * st.voronoi;
    let d1 = u1 - st.rest.x;
    let d2 = u2 - st.rest.y;
    let d3 = u3 - st.rest.z;
    let bend = (d2 * d2 * st.c[1] + d3 * d3 * st.c[2]) * half;
    let twist = d1 * d1 * (st.c[0] * half);
    (bend, twist)
}

/// Lifts a per-edge first-order dual number into the stencil's 8 variables at `idx`.
pub(crate) fn lift1(d: &Dual1<4>, idx: [usize; 4]) -> Dual1<8> {
    let mut out = Dual1::<8>::cst(d.v);
    for (a, &i) in idx.iter().enumerate() {
        out.g[i] = d.g[a];
    }
    out
}

/// Lifts a whole first-order edge frame.
pub(crate) fn lift_frame1(f: &EdgeFrame<Dual1<4>>, idx: [usize; 4]) -> EdgeFrame<Dual1<8>> {
    let l3 = |v: &V3<Dual1<4>>| [lift1(&v[0], idx), lift1(&v[1], idx), lift1(&v[2], idx)];
    EdgeFrame {
        t: l3(&f.t),
        d1: l3(&f.d1),
        m1: l3(&f.m1),
        m2: l3(&f.m2),
    }
}
