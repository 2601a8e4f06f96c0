//! SE(3) maps: hat/vee, the exponential and logarithm of se(3), and the adjoint.
//!
//! Twists are ordered **angular first**, `ξ = (ω, v)`, as the Jacobian `J(t)` of the model
//! (DESIGN.md "The model"; Bretl & McCarthy 2014, §3) and the perturbation `δb = (w δθ, δx)` of
//! the paper (Mishani & Sintov, eq. 9) are. A [`Pose`] `g = (R, p)` maps child to parent
//! coordinates; a body twist `ξ` perturbs it as `g exp(ξ̂)`.

use ftwire_core::Pose;
use nalgebra::{Matrix3, Matrix6, Translation3, UnitQuaternion, Vector3, Vector6};

/// The skew-symmetric matrix `v̂` with `v̂ w = v × w`.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// let (v, w) = (Vector3::new(1.0, 2.0, 3.0), Vector3::new(-1.0, 0.5, 2.0));
/// assert!((ftwire_rod::se3::hat(&v) * w - v.cross(&w)).norm() < 1e-15);
/// ```
#[inline]
pub fn hat(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// The inverse of [`hat`] on skew-symmetric matrices: `vee(v̂) = v`. Reads the
/// skew-symmetric part of `m`.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use ftwire_rod::se3::{hat, vee};
/// let v = Vector3::new(1.0, 2.0, 3.0);
/// assert_eq!(vee(&hat(&v)), v);
/// ```
#[inline]
pub fn vee(m: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        0.5 * (m[(2, 1)] - m[(1, 2)]),
        0.5 * (m[(0, 2)] - m[(2, 0)]),
        0.5 * (m[(1, 0)] - m[(0, 1)]),
    )
}

/// Coefficients `(a, b)` of `V = I + a ω̂ + b ω̂²` with `a = (1 − cos θ)/θ²`,
/// `b = (θ − sin θ)/θ³`, by series near `θ = 0`.
fn v_coefficients(theta: f64) -> (f64, f64) {
    let t2 = theta * theta;
    if theta < 1e-4 {
        (0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0)
    } else {
        (
            (1.0 - theta.cos()) / t2,
            (theta - theta.sin()) / (t2 * theta),
        )
    }
}

/// The exponential of a twist `ξ = (ω, v)` of se(3): the pose `exp(ξ̂)`.
///
/// # Example
/// ```
/// use nalgebra::Vector6;
/// use ftwire_rod::se3::{exp, log};
/// let xi = Vector6::new(0.1, -0.2, 0.3, 1.0, 2.0, -0.5);
/// assert!((log(&exp(&xi)) - xi).norm() < 1e-12);
/// ```
pub fn exp(xi: &Vector6<f64>) -> Pose {
    let w: Vector3<f64> = xi.fixed_rows::<3>(0).into_owned();
    let v: Vector3<f64> = xi.fixed_rows::<3>(3).into_owned();
    let (a, b) = v_coefficients(w.norm());
    let wh = hat(&w);
    let p = v + a * (wh * v) + b * (wh * (wh * v));
    Pose::from_parts(Translation3::from(p), UnitQuaternion::from_scaled_axis(w))
}

/// The logarithm of a pose: the twist `ξ = (ω, v)` with `exp(ξ̂) = g`, `|ω| ≤ π`.
///
/// # Example
/// ```
/// use ftwire_rod::se3::log;
/// assert!(log(&ftwire_core::Pose::identity()).norm() == 0.0);
/// ```
pub fn log(g: &Pose) -> Vector6<f64> {
    let w = g.rotation.scaled_axis();
    let theta = w.norm();
    let p = g.translation.vector;
    let wh = hat(&w);
    // V⁻¹ = I − ½ ω̂ + c ω̂², c = (1 − θ sin θ / (2 (1 − cos θ))) / θ².
    let c = if theta < 1e-4 {
        1.0 / 12.0 + theta * theta / 720.0
    } else {
        (1.0 - theta * theta.sin() / (2.0 * (1.0 - theta.cos()))) / (theta * theta)
    };
    let v = p - 0.5 * (wh * p) + c * (wh * (wh * p));
    Vector6::new(w.x, w.y, w.z, v.x, v.y, v.z)
}

/// The adjoint `Ad_g = [[R, 0], [p̂ R, R]]` of a pose `g = (R, p)`, acting on twists ordered
/// `(ω, v)`: `g exp(ξ̂) g⁻¹ = exp((Ad_g ξ)^)`. Its transpose maps wrenches `(m, n)` expressed at
/// `g`'s parent frame to `g`'s frame: `Ad_gᵀ (m, n) = (Rᵀ(m − p × n), Rᵀ n)`.
///
/// # Example
/// ```
/// use nalgebra::{Translation3, UnitQuaternion, Vector6};
/// use ftwire_rod::se3::{adjoint, exp};
/// let g = ftwire_core::Pose::from_parts(
///     Translation3::new(0.3, -0.1, 0.2),
///     UnitQuaternion::from_euler_angles(0.2, -0.4, 1.0),
/// );
/// let xi = Vector6::new(0.1, 0.2, -0.3, 0.5, -0.2, 0.1);
/// let lhs = g * exp(&xi) * g.inverse();
/// let rhs = exp(&(adjoint(&g) * xi));
/// assert!((lhs.to_homogeneous() - rhs.to_homogeneous()).norm() < 1e-12);
/// ```
pub fn adjoint(g: &Pose) -> Matrix6<f64> {
    let r = g.rotation.to_rotation_matrix().into_inner();
    let pr = hat(&g.translation.vector) * r;
    let mut ad = Matrix6::zeros();
    ad.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
    ad.fixed_view_mut::<3, 3>(3, 0).copy_from(&pr);
    ad.fixed_view_mut::<3, 3>(3, 3).copy_from(&r);
    ad
}

/// The small adjoint `ad_ξ = [[ω̂, 0], [v̂, ω̂]]` of a twist `ξ = (ω, v)`: the Lie bracket
/// `[ξ, η] = ad_ξ η`. The model's `H = −ad_ξ` for the body twist `ξ = (u, e1)`.
///
/// # Example
/// ```
/// use nalgebra::Vector6;
/// let xi = Vector6::new(0.1, 0.2, -0.3, 0.5, -0.2, 0.1);
/// assert!((ftwire_rod::se3::ad(&xi) * xi).norm() < 1e-15);
/// ```
pub fn ad(xi: &Vector6<f64>) -> Matrix6<f64> {
    let wh = hat(&xi.fixed_rows::<3>(0).into_owned());
    let vh = hat(&xi.fixed_rows::<3>(3).into_owned());
    let mut m = Matrix6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&wh);
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(&vh);
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(&wh);
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn twist() -> impl Strategy<Value = Vector6<f64>> {
        prop::array::uniform6(-3.0..3.0f64).prop_map(|a| Vector6::from_column_slice(&a))
    }

    proptest! {
        #[test]
        fn log_inverts_exp(xi in twist()) {
            prop_assume!(xi.fixed_rows::<3>(0).norm() < 3.1);
            prop_assert!((log(&exp(&xi)) - xi).norm() < 1e-9);
        }

        #[test]
        fn exp_matches_matrix_exponential(xi in twist()) {
            // 4×4 matrix exponential by scaling and squaring of a Taylor series.
            let mut x = nalgebra::Matrix4::zeros();
            x.fixed_view_mut::<3, 3>(0, 0).copy_from(&hat(&xi.fixed_rows::<3>(0).into_owned()));
            x.fixed_view_mut::<3, 1>(0, 3).copy_from(&xi.fixed_rows::<3>(3));
            let scaled = x / 1024.0;
            let mut term = nalgebra::Matrix4::identity();
            let mut sum = nalgebra::Matrix4::identity();
            for k in 1..20 {
                term = term * scaled / f64::from(k);
                sum += term;
            }
            for _ in 0..10 {
                sum = sum * sum;
            }
            prop_assert!((exp(&xi).to_homogeneous() - sum).norm() < 1e-9);
        }

        #[test]
        fn adjoint_conjugates(xi in twist(), eta in twist()) {
            let g = exp(&eta);
            let lhs = g * exp(&xi) * g.inverse();
            let rhs = exp(&(adjoint(&g) * xi));
            prop_assert!((lhs.to_homogeneous() - rhs.to_homogeneous()).norm() < 1e-9);
        }

        #[test]
        fn small_adjoint_is_derivative_of_adjoint(xi in twist(), eta in twist()) {
            let h = 1e-6;
            let fd = (adjoint(&exp(&(xi * h))) - adjoint(&exp(&(-xi * h)))) / (2.0 * h);
            prop_assert!((fd * eta - ad(&xi) * eta).norm() < 1e-6 * (1.0 + eta.norm() * xi.norm()));
        }
    }

    #[test]
    fn small_angles_use_the_series() {
        let xi = Vector6::new(1e-9, -2e-9, 0.0, 1.0, 2.0, 3.0);
        assert!((log(&exp(&xi)) - xi).norm() < 1e-14);
    }
}
