//! Bending and twisting energy of one interior vertex (Bergou et al. 2008, eq. 2–4 and §4.2;
//! reference twist from Bergou et al. 2010, §4.1 and eq. 7).
//!
//! At vertex `i`, between edges `e⁰ = x_i − x_{i−1}` and `e¹ = x_{i+1} − x_i`, turning by the
//! angle `φ` (`cos φ = t⁰·t¹`):
//! - curvature binormal `(κb)_i = 2 t⁰ × t¹ / (1 + t⁰·t¹)` (Bergou 2008, eq. 1), of magnitude
//!   `2 tan(φ/2)`;
//! - twist `u1 = Δ/ℓ`, with `Δ = θ¹ − θ⁰ + m_ref` the angle between the two material frames and
//!   the reference twist `m_ref` the signed angle about `t¹` from the space-parallel transport of
//!   edge 0's reference director to edge 1's (Bergou 2010, §4.1); `ℓ` the rest Voronoi length;
//! - material curvatures in the *mid-vertex* material frame, with the turning angle as the
//!   curvature magnitude:
//!   `u2 = g(φ)·sec(Δ/2)·κb·(m1⁰ + m1¹)/(2ℓ)`, `u3 = g(φ)·sec(Δ/2)·κb·(m2⁰ + m2¹)/(2ℓ)`, with
//!   `g(φ) = (φ/2)/tan(φ/2)`; with `R' = R û` (DESIGN.md) these are the Kirchhoff bending
//!   strains about body y and z;
//! - energy `ℓ/2·[c1 (u1 − ū1)² + c2 (u2 − ū2)² + c3 (u3 − ū3)²]` (Bergou 2008, eq. 3 and 4
//!   with anisotropic bending and natural strains); with a softening curvature `κs`
//!   (`RodParams::bending_softening`) the bending part `ℓ/2·e`, `e = c2 (u2 − ū2)² + c3 (u3 −
//!   ū3)²`, becomes `ℓ·s·(√(1 + e/s) − 1)`, `s = (c2 + c3)/2·κs²`.
//!
//! The two factors remove the largest `O(h²)` errors of the plain DER (measured against the
//! Kirchhoff model in `crates/ftwire/tests/model_vs_sim.rs`; numbers in `docs/model.md`):
//! - `g(φ)`: with the edges as the position steps and the vertices as rotations, the discrete
//!   rod is a Strang splitting of the Kirchhoff equations (half edge, rotation, edge, …, half
//!   edge); the exact flow of `R' = R û` over one Voronoi length turns by `|u|·ℓ`, so the
//!   curvature must be `φ/ℓ`, not `2 tan(φ/2)/ℓ`, which overestimates it by `κ²h²/12`;
//! - `sec(Δ/2)`: the average `(m1⁰ + m1¹)/2` of two directors `Δ` apart has length
//!   `cos(Δ/2)`, which underestimates both bending strains by `τ²h²/8` for a twist rate `τ`
//!   and couples twist and bending even for a round wire; the factor makes `(u2, u3)` the
//!   curvature in the frame halfway between the two material frames, so `u2² + u3² = (φ/ℓ)²`
//!   exactly when `c2 = c3`. It is evaluated as the Taylor polynomial
//!   `1 + x²/2 + 5x⁴/24` (`x = Δ/2`; error `O(Δ⁶)`, `< 1e-9` for `|Δ| < 0.1`), which stays
//!   smooth and bounded for any `Δ`.
//!
//! Evaluation. With `(t, a, b)` the tangent and reference directors of an edge and
//! `m1 = C a + S b`, `m2 = −S a + C b` (`C, S = cos θ, sin θ`), every quantity above reduces to
//! seven dot products between the two edges' directors, `c = t⁰·t¹`, `p = t¹·a⁰`, `q = t¹·b⁰`,
//! `r = t⁰·a¹`, `s = t⁰·b¹`, `α = a⁰·a¹`, `β = a⁰·b¹`:
//! - `ℓ(1 + c)·u2 = (−C⁰q + S⁰p + C¹s − S¹r)·g·sec`, `ℓ(1 + c)·u3 = (S⁰q + C⁰p − S¹s − C¹r)·g·sec`;
//! - `m_ref = atan2(y, x)` with `x = cα − rp − qs/(1 + c)`, `y = −cβ + sp − qr/(1 + c)`
//!   (the parallel transport `P(t⁰ → t¹)a⁰` dotted with `a¹` and `−b¹`), plus the multiple of
//!   2π that keeps it nearest the vertex's previous reference twist, so that it stays continuous
//!   along a motion (Bergou 2010, §4.1: the reference twist is updated incrementally).
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
use crate::state::nearest_turns;
use crate::transport::transport_from_const;

/// Constants of one bending–twisting stencil.
pub(crate) struct Stencil<'a> {
    /// `(c1, c2, c3)` \[N·m²\].
    pub c: &'a [f64; 3],
    /// Rest strains `(ū1, ū2, ū3)` \[1/m\].
    pub rest: &'a Vector3<f64>,
    /// The curvature `κs` \[1/m\] of softening bending (`RodParams::bending_softening`).
    pub softening: Option<f64>,
    /// Rest Voronoi length ℓ \[m\].
    pub voronoi: f64,
    /// The vertex's last reference twist \[rad\] (`RodState::ref_twist`): of the values of
    /// `m_ref` that `atan2` gives modulo 2π, the one nearest it is taken.
    pub ref_twist: f64,
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
    let x = c * alpha - r * p - q * s / one_c;
    let y = s * p - c * beta - q * r / one_c;
    let raw = y.atan2(x);
    let m_ref = raw + nearest_turns(raw.re(), st.ref_twist);
    let twist = th1 - th0 + m_ref;
    let u1 = twist * (1.0 / st.voronoi);
    // Turning angle instead of 2·tan(φ/2), and the mid-vertex material frame instead of the
    // averaged directors (whose length is cos(Δ/2)); see the module docs.
    // Both factors are scalar functions of one stencil quantity; they are differentiated with
    // one-variable duals and applied as exact second-order Taylor expansions, which keeps the
    // stencil's eight-variable dual arithmetic (the Hessian cost) to four products.
    let g = taylor2(c, half_angle_ratio(Dual2::<1>::var(c.re(), 0)));
    let sec = taylor2(twist, half_twist_secant(Dual2::<1>::var(twist.re(), 0)));
    let k = k * (g * sec);
    let u2 = (s0 * p - c0 * q + c1 * s - s1 * r) * k;
    let u3 = (s0 * q + c0 * p - s1 * s - c1 * r) * k;
    [u1, u2, u3]
}

/// `f(x)` from its value and first two derivatives at `x.re()` (in `f`): exact for every
/// scalar type here, which carries at most second derivatives.
fn taylor2<S: Scalar>(x: S, f: Dual2<1>) -> S {
    let d = x - x.re();
    d * (d * (0.5 * f.hess(0, 0)) + f.g[0]) + f.v
}

/// `sec(Δ/2)` as its Taylor polynomial `1 + x²/2 + 5x⁴/24` (`x = Δ/2`): error `O(Δ⁶)`,
/// smooth and bounded for any `Δ`.
fn half_twist_secant<S: Scalar>(twist: S) -> S {
    let x2 = twist * twist * 0.25;
    x2 * (x2 * (5.0 / 24.0) + 0.5) + 1.0
}

/// `(φ/2)/tan(φ/2)` for `c = cos φ`, smooth in `c` on `(−1, 1]`.
pub(crate) fn half_angle_ratio<S: Scalar>(c: S) -> S {
    // y = tan²(φ/2) = (1 − c)/(1 + c); the ratio is atan(√y)/√y = Σ (−y)ⁿ/(2n + 1).
    let y = (S::cst(1.0) - c) / (c + 1.0);
    if y.re() < 1e-3 {
        let mut sum = S::cst(1.0 / 13.0);
        for n in (0..6).rev() {
            sum = S::cst(1.0 / (2 * n + 1) as f64) - y * sum;
        }
        sum
    } else {
        let t = y.sqrt();
        t.atan2(S::cst(1.0)) / t
    }
}

/// `(bending, twisting)` energy \[J\] of the vertex.
pub(crate) fn energy<S: Scalar>(dots: &[S; 7], th0: S, th1: S, st: &Stencil<'_>) -> (S, S) {
    let [u1, u2, u3] = strains(dots, th0, th1, st);
    let half = 0.5 * st.voronoi;
    let d1 = u1 - st.rest.x;
    let d2 = u2 - st.rest.y;
    let d3 = u3 - st.rest.z;
    let linear = d2 * d2 * st.c[1] + d3 * d3 * st.c[2];
    let bend = match st.softening {
        None => linear * half,
        // `c̄ κs² (√(1 + e/(c̄ κs²)) − 1)` per unit length, `e` twice the linear density.
        Some(kappa) => {
            let scale = 0.5 * (st.c[1] + st.c[2]) * kappa * kappa;
            ((linear * (1.0 / scale) + 1.0).sqrt() - 1.0) * (scale * st.voronoi)
        }
    };
    let twist = d1 * d1 * (st.c[0] * half);
    (bend, twist)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dual::{add, lin2};
    use crate::transport::transport;
    use std::f64::consts::PI;

    /// The strains from their geometric definition: the turning angle `φ` about the binormal
    /// `b̂`, the material twist angle `Δ`, and the curvature in the frame halfway between the
    /// two material frames (angles `α⁰, α¹` of `b̂` in them).
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
        let cr = cross(&f0.t, &f1.t);
        let sin_phi = dot(&cr, &cr).sqrt();
        let phi = sin_phi.atan2(dot(&f0.t, &f1.t));
        let b = scale(&cr, 1.0 / sin_phi);
        let a0 = dot(&b, &m20).atan2(dot(&b, &m10));
        let a1 = dot(&b, &m21).atan2(dot(&b, &m11));
        let half = ((a1 - a0 + PI).rem_euclid(2.0 * PI) - PI) / 2.0;
        let mid = a0 + half;
        let pd = transport(&f0.t, &f1.t, &f0.a);
        let m_ref = dot(&cross(&pd, &f1.a), &f1.t).atan2(dot(&pd, &f1.a));
        let twist = th[1] - th[0] + m_ref;
        // The plain DER's averaged director is shorter by cos(Δ/2): the artefact corrected.
        let avg = add(&m10, &m11);
        assert!((dot(&b, &avg) - 2.0 * (twist / 2.0).cos() * mid.cos()).abs() < 1e-12);
        [twist / l, phi / l * mid.cos(), phi / l * mid.sin()]
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
        // A material twist of 0.08 rad between the edges (sec(Δ/2) is a Taylor polynomial,
        // exact to ~1e-11 here).
        let th0 = 0.4;
        let m_ref = reference(&e0, &e1, [0.0, 0.0], &refs, 1.0)[0];
        let th = [th0, th0 - m_ref + 0.08];
        let st = Stencil {
            c: &[1.0, 1.0, 1.0],
            rest: &Vector3::zeros(),
            softening: None,
            voronoi: 0.01,
            ref_twist: 0.0,
        };
        let d0: Directors<f64> = directors(&[e0.x, e0.y, e0.z], &refs[0].0, &refs[0].1);
        let d1: Directors<f64> = directors(&[e1.x, e1.y, e1.z], &refs[1].0, &refs[1].1);
        let fast = strains(&dots(&d0, &d1), th[0], th[1], &st);
        let slow = reference(&e0, &e1, th, &refs, 0.01);
        for (f, s) in fast.iter().zip(&slow) {
            assert!(
                (f - s).abs() < 2e-9 * (1.0 + s.abs()),
                "{fast:?} vs {slow:?}"
            );
        }
    }

    /// The reference twist is taken on the branch nearest the vertex's previous one,
    /// not always in `(−π, π]`: a reference director turned 3.1 rad past its neighbour's reads
    /// as `3.1 − 2π` when the previous value was just below −π.
    #[test]
    fn the_reference_twist_keeps_the_branch_of_its_previous_value() {
        let e = [0.01, 0.0, 0.0];
        let x = Vector3::x();
        let turned = Vector3::new(0.0, 3.1_f64.cos(), 3.1_f64.sin());
        let d0: Directors<f64> = directors(&e, &x, &Vector3::y());
        let d1: Directors<f64> = directors(&e, &x, &turned);
        let (c, rest) = ([1.0; 3], Vector3::zeros());
        let stencil = |ref_twist| Stencil {
            c: &c,
            rest: &rest,
            softening: None,
            voronoi: 0.01,
            ref_twist,
        };
        let principal = strains(&dots(&d0, &d1), 0.0, 0.0, &stencil(0.0))[0];
        let continued = strains(&dots(&d0, &d1), 0.0, 0.0, &stencil(-3.2))[0];
        assert!((principal.abs() * 0.01 - 3.1).abs() < 1e-12);
        assert!((continued - (principal - 2.0 * PI / 0.01 * principal.signum())).abs() < 1e-9);
        assert!((continued * 0.01 + 3.2).abs() < 0.1);
    }
}
