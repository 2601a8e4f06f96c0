use nalgebra::{Vector3, Vector6};
use serde::{Deserialize, Serialize};

/// A wrench: torque \[N·m\] and force \[N\] in one frame, about that frame's origin.
///
/// Flattened, it is ordered torque first, as the wire configuration `a` is.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Wrench {
    /// Torque \[N·m\].
    pub torque: Vector3<f64>,
    /// Force \[N\].
    pub force: Vector3<f64>,
}

impl Wrench {
    /// Builds a wrench from torque \[N·m\] and force \[N\].
    pub fn new(torque: Vector3<f64>, force: Vector3<f64>) -> Self {
        Self { torque, force }
    }

    /// Builds a wrench from a 6-vector ordered `(τ1, τ2, τ3, f1, f2, f3)`.
    pub fn from_vector(v: &Vector6<f64>) -> Self {
        Self {
            torque: v.fixed_rows::<3>(0).into_owned(),
            force: v.fixed_rows::<3>(3).into_owned(),
        }
    }

    /// The 6-vector `(τ1, τ2, τ3, f1, f2, f3)`.
    pub fn to_vector(&self) -> Vector6<f64> {
        Vector6::new(
            self.torque.x,
            self.torque.y,
            self.torque.z,
            self.force.x,
            self.force.y,
            self.force.z,
        )
    }

    /// Expresses this wrench, given in frame B about B's origin, in frame A about A's origin,
    /// where `a_from_b` maps B coordinates to A coordinates.
    ///
    /// # Example
    /// ```
    /// use ftwire_core::{Pose, Wrench};
    /// use nalgebra::{Translation3, UnitQuaternion, Vector3};
    ///
    /// // A pure force along z at B, with B one metre along x of A: a torque −1 N·m about y in A.
    /// let a_from_b = Pose::from_parts(Translation3::new(1.0, 0.0, 0.0), UnitQuaternion::identity());
    /// let w = Wrench::new(Vector3::zeros(), Vector3::new(0.0, 0.0, 1.0)).transformed(&a_from_b);
    /// assert!((w.torque - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-15);
    /// ```
    pub fn transformed(&self, a_from_b: &crate::Pose) -> Self {
        let force = a_from_b.rotation * self.force;
        let torque = a_from_b.rotation * self.torque + a_from_b.translation.vector.cross(&force);
        Self { torque, force }
    }
}
