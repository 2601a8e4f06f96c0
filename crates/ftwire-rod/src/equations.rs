//! The equations of the Kirchhoff wire (paper §II-A, eq. 1, 3, 4; Bretl & McCarthy 2014).
//!
//! Conventions (DESIGN.md "The model"): `q(t) = (R(t), p(t))` is the wire frame at arc length
//! `t` relative to the base clamp, `q(0) = I`, x axis along the tangent; `μ(t) = (m, n)` is the
//! internal wrench (torque first) in the body frame; `u = (μ1/c1, μ2/c2, μ3/c3)`.
//!
//! # Closed forms used by the solver (derived here, checked by tests)
//!
//! The wrench is constant in the base frame (`n' = 0`, `m' + p' × n = 0` there), so with
//! `a = (m0, n0)`:
//!
//! ```text
//! μ(t) = Ad_{q(t)}ᵀ a = ( Rᵀ (m0 − p × n0),  Rᵀ n0 )                          (A)
//! ```
//!
//! which satisfies eq. 3 identically. Perturbing `a` moves `q` to `q exp(ĵ)` with `j = J δa`,
//! and differentiating (A) gives `M(t) = ∂μ(t)/∂a` algebraically:
//!
//! ```text
//! M(t) = Ad_{q(t)}ᵀ + K(μ(t)) J(t),   K(m, n) = [[m̂, n̂], [n̂, 0]]                (B)
//! ```
//!
//! so the Jacobian solves integrate only `q` and `J` (eq. 1 and `J' = G M + H J` of eq. 4),
//! 48 states instead of 90, and never `μ` or `M` (the solver's flat states and right-hand
//! sides are in the private `kirchhoff` module). Tests check (A) and (B) against an
//! independent integration of the full system (eq. 3 and `M' = F M`) and `J` against finite
//! differences. The shape-only solves integrate `q` and `m` (eq. 1 and the top of eq. 3,
//! `ShapeArray`) and read `n = Rᵀ n0` from the frame: with `m` a state, each stage's chain of
//! dependent operations is shorter than through (A).

use nalgebra::{Matrix6, Vector6};

use crate::se3::hat;

/// The right-hand side of the costate ODE, paper eq. 3: `μ'` for stiffnesses `c` \[N·m²\].
///
/// # Example
/// ```
/// use nalgebra::Vector6;
/// // A pure force along the tangent (a straight wire under tension) is an equilibrium.
/// let rate = ftwire_rod::costate_rate([1.0, 2.0, 3.0], &Vector6::new(0.0, 0.0, 0.0, 1.0, 0.0, 0.0));
/// assert_eq!(rate, Vector6::zeros());
/// ```
pub fn costate_rate(c: [f64; 3], mu: &Vector6<f64>) -> Vector6<f64> {
    let u = [mu[0] / c[0], mu[1] / c[1], mu[2] / c[2]];
    Vector6::new(
        u[2] * mu[1] - u[1] * mu[2],
        mu[5] + u[0] * mu[2] - u[2] * mu[0],
        -mu[4] + u[1] * mu[0] - u[0] * mu[1],
        u[2] * mu[4] - u[1] * mu[5],
        u[0] * mu[5] - u[2] * mu[3],
        u[1] * mu[3] - u[0] * mu[4],
    )
}

/// `F(μ) = ∂μ'/∂μ` of paper eq. 4 (DESIGN.md lists it entry by entry).
pub fn f_matrix(c: [f64; 3], mu: &Vector6<f64>) -> Matrix6<f64> {
    let [c1, c2, c3] = c;
    let m = mu;
    let (d32, d13, d21) = (
        1.0 / c3 - 1.0 / c2,
        1.0 / c1 - 1.0 / c3,
        1.0 / c2 - 1.0 / c1,
    );
    Matrix6::from_row_slice(&[
        0.0,
        d32 * m[2],
        d32 * m[1],
        0.0,
        0.0,
        0.0, //
        d13 * m[2],
        0.0,
        d13 * m[0],
        0.0,
        0.0,
        1.0, //
        d21 * m[1],
        d21 * m[0],
        0.0,
        0.0,
        -1.0,
        0.0, //
        0.0,
        -m[5] / c2,
        m[4] / c3,
        0.0,
        m[2] / c3,
        -m[1] / c2, //
        m[5] / c1,
        0.0,
        -m[3] / c3,
        -m[2] / c3,
        0.0,
        m[0] / c1, //
        -m[4] / c1,
        m[3] / c2,
        0.0,
        m[1] / c2,
        -m[0] / c1,
        0.0,
    ])
}

/// `G = [[diag(1/c1, 1/c2, 1/c3), 0], [0, 0]]` of paper eq. 4.
pub fn g_matrix(c: [f64; 3]) -> Matrix6<f64> {
    let mut g = Matrix6::zeros();
    for (i, ci) in c.iter().enumerate() {
        g[(i, i)] = 1.0 / ci;
    }
    g
}

/// `H(μ) = −ad_ξ` of paper eq. 4 for the body twist `ξ = (u, e1)`.
pub fn h_matrix(c: [f64; 3], mu: &Vector6<f64>) -> Matrix6<f64> {
    let xi = Vector6::new(mu[0] / c[0], mu[1] / c[1], mu[2] / c[2], 1.0, 0.0, 0.0);
    -crate::se3::ad(&xi)
}

/// `M(t) = ∂μ(t)/∂a` from the frame, costate and Jacobian at `t`, by the closed form (B) of
/// this module: `M = Ad_qᵀ + [[m̂, n̂], [n̂, 0]] J`.
pub fn m_matrix(q: &ftwire_core::Pose, mu: &Vector6<f64>, j: &Matrix6<f64>) -> Matrix6<f64> {
    let mut k = Matrix6::zeros();
    let mh = hat(&mu.fixed_rows::<3>(0).into_owned());
    let nh = hat(&mu.fixed_rows::<3>(3).into_owned());
    k.fixed_view_mut::<3, 3>(0, 0).copy_from(&mh);
    k.fixed_view_mut::<3, 3>(0, 3).copy_from(&nh);
    k.fixed_view_mut::<3, 3>(3, 0).copy_from(&nh);
    crate::se3::adjoint(q).transpose() + k * j
}

/// An a-priori bound `σ` \[1/m\] on how fast the solution turns: the larger of the
/// curvature bound and the load wavenumber,
///
/// ```text
/// |u(t)| ≤ √(2 (H + |n|) / c_min),   H = ½ Σ μi²/ci + μ4 (conserved),   and   √(|n| / c_min),
/// ```
///
/// both constant along the wire (`½ Σ μi²/ci = H − μ4 ≤ H + |n|`). The adaptive integrator
/// takes steps in proportion to `σ L`.
///
/// # Example
/// ```
/// use nalgebra::Vector6;
/// // Pure bending: the bound is the exact curvature τ / c3.
/// let s = ftwire_rod::equations::turning_scale([1.0, 1.0, 0.5], &Vector6::new(0.0, 0.0, 2.0, 0.0, 0.0, 0.0));
/// assert!((s - 4.0).abs() < 1e-12);
/// ```
pub fn turning_scale(c: [f64; 3], a: &Vector6<f64>) -> f64 {
    let c_min = c[0].min(c[1]).min(c[2]);
    let h = 0.5 * (a[0] * a[0] / c[0] + a[1] * a[1] / c[1] + a[2] * a[2] / c[2]) + a[3];
    let n = (a[3] * a[3] + a[4] * a[4] + a[5] * a[5]).sqrt();
    let curvature = (2.0 * (h + n).max(0.0) / c_min).sqrt();
    curvature.max((n / c_min).sqrt())
}
