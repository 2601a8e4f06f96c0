//! Obstacles: oriented boxes and a floor, as signed-distance functions.
//!
//! Each obstacle exposes a signed distance `d(p)` (positive outside) with its gradient and
//! Hessian, which the contact penalty ([`crate::energy::contact`]) turns into a smooth energy.

use ftwire_core::{Pose, ensure_finite, ensure_positive};
use nalgebra::{Matrix3, Point3, Vector3};

use crate::error::SimError;

/// A solid box obstacle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxObstacle {
    pose: Pose,
    half_extents: Vector3<f64>,
}

impl BoxObstacle {
    /// A box centred at `pose` (world from box; its axes are the box's edges) with
    /// `half_extents` \[m\] along its own x, y, z axes.
    ///
    /// # Errors
    /// [`SimError::Core`] for a non-finite pose or a non-positive half extent.
    ///
    /// # Example
    /// ```
    /// use ftwire_sim::BoxObstacle;
    /// use nalgebra::{Isometry3, Point3, Vector3};
    /// let b = BoxObstacle::new(Isometry3::identity(), Vector3::new(1.0, 1.0, 1.0))?;
    /// assert!((b.signed_distance(&Point3::new(3.0, 0.0, 0.0)) - 2.0).abs() < 1e-15);
    /// # Ok::<(), ftwire_sim::SimError>(())
    /// ```
    pub fn new(pose: Pose, half_extents: Vector3<f64>) -> Result<Self, SimError> {
        ensure_finite("obstacle pose", pose.translation.vector.as_slice())?;
        ensure_finite("obstacle pose", pose.rotation.coords.as_slice())?;
        ensure_positive("half_extents.x", half_extents.x)?;
        ensure_positive("half_extents.y", half_extents.y)?;
        ensure_positive("half_extents.z", half_extents.z)?;
        Ok(Self { pose, half_extents })
    }

    /// Pose of the box (world from box).
    pub fn pose(&self) -> &Pose {
        &self.pose
    }

    /// Half extents \[m\] along the box axes.
    pub fn half_extents(&self) -> &Vector3<f64> {
        &self.half_extents
    }

    /// Thickness of the box's thinnest dimension \[m\].
    pub fn thickness(&self) -> f64 {
        2.0 * self.half_extents.min()
    }

    /// Signed distance \[m\] from a world point to the box surface (negative inside).
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        self.distance_derivatives(p).0
    }

    /// Signed distance, its gradient and its Hessian with respect to the world point.
    pub(crate) fn distance_derivatives(
        &self,
        p: &Point3<f64>,
    ) -> (f64, Vector3<f64>, Matrix3<f64>) {
        let r = self.pose.rotation;
        let q = self.pose.inverse_transform_point(p).coords;
        let excess = q.abs() - self.half_extents;
        if excess.max() <= 0.0 {
            // Inside: distance to the nearest face, gradient its outward normal.
            let axis = excess.imax();
            let mut n = Vector3::zeros();
            n[axis] = q[axis].signum();
            return (excess[axis], r * n, Matrix3::zeros());
        }
        let mut diff = Vector3::zeros();
        let mut projector = Matrix3::zeros();
        for a in 0..3 {
            if excess[a] > 0.0 {
                diff[a] = excess[a] * q[a].signum();
                projector[(a, a)] = 1.0;
            }
        }
        let d = diff.norm();
        let n = diff / d;
        let hess_local = (projector - n * n.transpose()) / d;
        let rm = r.to_rotation_matrix();
        (d, r * n, rm.matrix() * hess_local * rm.matrix().transpose())
    }
}

/// A horizontal floor: the half-space `z < height` of the world frame is solid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Floor {
    /// Height of the floor surface \[m\], world z (default `0`).
    pub height: f64,
}

impl Default for Floor {
    fn default() -> Self {
        Self { height: 0.0 }
    }
}

impl Floor {
    /// Signed distance \[m\] of a world point above the floor.
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        p.z - self.height
    }
}

/// Anything the wire can touch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Obstacle {
    /// An oriented box.
    Box(BoxObstacle),
    /// The floor.
    Floor(Floor),
}

impl Obstacle {
    /// Signed distance, gradient, Hessian with respect to a world point.
    pub(crate) fn distance_derivatives(
        &self,
        p: &Point3<f64>,
    ) -> (f64, Vector3<f64>, Matrix3<f64>) {
        match self {
            Obstacle::Box(b) => b.distance_derivatives(p),
            Obstacle::Floor(f) => (f.signed_distance(p), Vector3::z(), Matrix3::zeros()),
        }
    }

    /// Thickness of the thinnest part \[m\] (infinite for the floor).
    pub fn thickness(&self) -> f64 {
        match self {
            Obstacle::Box(b) => b.thickness(),
            Obstacle::Floor(_) => f64::INFINITY,
        }
    }
}
