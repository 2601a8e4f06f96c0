//! The perturbation map from `A` to `B` (paper §III-A, eq. 8–11).
//!
//! A small change `δa` of the configuration moves the second gripper from `b_i` to
//! `b_(i+1) = b_i M(δb)` (eq. 10), with `M(δb) = [[exp(ŵ δθ), δx], [0, 1]]` (eq. 8) and
//! `δb = (w δθ, δx)` (eq. 9), and to first order `δb ≈ J(L) δa` (eq. 11). Note that eq. 8 is
//! not the se(3) exponential: the translation is `δx` itself. The two agree to first order,
//! which is all eq. 11 claims.

use ftwire_core::Pose;
use nalgebra::{Matrix6, Translation3, UnitQuaternion, Vector3, Vector6};

/// `M(δb)` of eq. 8 for `δb = (w δθ, δx)`.
///
/// # Example
/// ```
/// use nalgebra::Vector6;
/// use ftwire_rod::perturbation::{delta_b, perturbation_pose};
/// let db = Vector6::new(0.01, -0.02, 0.03, 0.001, 0.002, -0.003);
/// assert!((delta_b(&Pose::identity(), &perturbation_pose(&db)) - db).norm() < 1e-15);
/// # use ftwire_rod::Pose;
/// ```
pub fn perturbation_pose(db: &Vector6<f64>) -> Pose {
    let w = Vector3::new(db[0], db[1], db[2]);
    Pose::from_parts(
        Translation3::new(db[3], db[4], db[5]),
        UnitQuaternion::from_scaled_axis(w),
    )
}

/// `δb` between two poses of the second gripper (eq. 9–10): the `δb` with
/// `b_next = b M(δb)`, rotation part as exponential coordinates with `δθ ∈ [0, π]`.
pub fn delta_b(b: &Pose, b_next: &Pose) -> Vector6<f64> {
    let rel = b.inverse() * b_next;
    let w = rel.rotation.scaled_axis();
    let x = rel.translation.vector;
    Vector6::new(w.x, w.y, w.z, x.x, x.y, x.z)
}

/// `b M(δb)` (eq. 10).
pub fn apply(b: &Pose, db: &Vector6<f64>) -> Pose {
    b * perturbation_pose(db)
}

/// The first-order prediction `δb ≈ J(L) δa` (eq. 11).
pub fn predict(jacobian: &Matrix6<f64>, da: &Vector6<f64>) -> Vector6<f64> {
    jacobian * da
}
