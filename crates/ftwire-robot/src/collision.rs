//! Coarse collision checks for a planner's `Z_free`: the arms' links as capsules between
//! consecutive joint origins, checked against each other and against oriented boxes.
//!
//! The model is deliberately coarse (a capsule per link, radii from the SDA10F's outline, not
//! from meshes): use it with a margin, not as a contact model. The torso body itself is not
//! modelled; add it as an [`OrientedBox`] if a planner needs it.

use ftwire_core::Pose;
use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

use crate::chain::{ARM_DOF, ArmJoints};
use crate::{Arm, Robot, RobotError};

/// Number of capsules per arm: shoulder (joint 1 → 2), five links between joint origins 2 → 7,
/// and the wrist-and-gripper capsule (joint 7 → gripper clamp point).
pub const LINK_CAPSULES: usize = ARM_DOF;

/// A capsule: the points within `radius` of the segment `a`–`b`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Capsule {
    /// One end of the axis segment \[m\].
    pub a: Point3<f64>,
    /// The other end \[m\].
    pub b: Point3<f64>,
    /// Radius \[m\].
    pub radius: f64,
}

/// A box with its own pose: the points `pose · x` with `|x_i| ≤ half_extents_i`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OrientedBox {
    pose: Pose,
    half_extents: Vector3<f64>,
}

impl OrientedBox {
    /// A box centred at `pose` (parent from box, e.g. robot base from box) with half extents
    /// \[m\] along the box's own axes.
    ///
    /// # Errors
    /// [`RobotError::Core`] if the pose is not finite; [`RobotError::InvalidParameter`] if a
    /// half extent is negative or not finite.
    ///
    /// # Example
    /// ```
    /// use ftwire_robot::OrientedBox;
    /// use nalgebra::{Point3, Vector3};
    /// let b = OrientedBox::new(ftwire_core::Pose::identity(), Vector3::new(0.5, 0.5, 0.5))?;
    /// assert_eq!(ftwire_robot::point_box_distance(&Point3::new(1.5, 0.0, 0.0), &b), 1.0);
    /// assert!(OrientedBox::new(ftwire_core::Pose::identity(), Vector3::new(-1.0, 1.0, 1.0)).is_err());
    /// # Ok::<(), ftwire_robot::RobotError>(())
    /// ```
    pub fn new(pose: Pose, half_extents: Vector3<f64>) -> Result<Self, RobotError> {
        ftwire_core::ensure_finite("box translation", pose.translation.vector.as_slice())?;
        ftwire_core::ensure_finite("box rotation", pose.rotation.coords.as_slice())?;
        for &h in half_extents.iter() {
            if !(h.is_finite() && h >= 0.0) {
                return Err(RobotError::InvalidParameter {
                    name: "half_extents",
                    value: h,
                    allowed: "finite half extents >= 0 m",
                });
            }
        }
        Ok(Self { pose, half_extents })
    }

    /// An axis-aligned box from its corners \[m\] (any order per axis).
    ///
    /// # Errors
    /// [`RobotError::Core`] if a corner is not finite.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Point3;
    /// let b = ftwire_robot::OrientedBox::aabb(Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 2.0, 3.0))?;
    /// assert_eq!(b.half_extents().y, 1.0);
    /// # Ok::<(), ftwire_robot::RobotError>(())
    /// ```
    pub fn aabb(min: Point3<f64>, max: Point3<f64>) -> Result<Self, RobotError> {
        ftwire_core::ensure_finite("box min", min.coords.as_slice())?;
        ftwire_core::ensure_finite("box max", max.coords.as_slice())?;
        let centre = nalgebra::center(&min, &max);
        Self::new(
            Pose::translation(centre.x, centre.y, centre.z),
            (max - min).abs() / 2.0,
        )
    }

    /// Parent from box.
    pub fn pose(&self) -> &Pose {
        &self.pose
    }

    /// Half extents along the box's axes \[m\].
    pub fn half_extents(&self) -> &Vector3<f64> {
        &self.half_extents
    }
}

/// Capsule radii of one arm's links \[m\], shoulder first (see [`LINK_CAPSULES`]).
///
/// Defaults, from the SDA10F's outline (coarse, slightly generous): shoulder `0.10`, upper arm
/// `0.09`, `0.08`, elbow/forearm `0.075`, `0.07`, wrist `0.06`, wrist + gripper `0.05`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LinkRadii {
    /// Radius of each capsule \[m\].
    pub radii: [f64; LINK_CAPSULES],
}

impl Default for LinkRadii {
    fn default() -> Self {
        Self {
            radii: [0.10, 0.09, 0.08, 0.075, 0.07, 0.06, 0.05],
        }
    }
}

/// Distance between two segments `p0`–`p1` and `q0`–`q1` \[m\] (degenerate segments allowed):
/// [`ftwire_core::geometry::segment_distance`], the workspace's one implementation, on points.
///
/// # Example
/// ```
/// use nalgebra::Point3;
/// let d = ftwire_robot::segment_segment_distance(
///     &Point3::new(0.0, 0.0, 0.0), &Point3::new(1.0, 0.0, 0.0),
///     &Point3::new(0.5, -1.0, 2.0), &Point3::new(0.5, 1.0, 2.0),
/// );
/// assert!((d - 2.0).abs() < 1e-12);
/// ```
#[inline]
pub fn segment_segment_distance(
    p0: &Point3<f64>,
    p1: &Point3<f64>,
    q0: &Point3<f64>,
    q1: &Point3<f64>,
) -> f64 {
    ftwire_core::geometry::segment_distance(&p0.coords, &p1.coords, &q0.coords, &q1.coords)
}

/// Distance from a point to a box \[m\] (0 inside).
pub fn point_box_distance(p: &Point3<f64>, b: &OrientedBox) -> f64 {
    let local = b.pose.inverse_transform_point(p);
    let h = b.half_extents;
    let outside = Vector3::from_fn(|i, _| (local[i].abs() - h[i]).max(0.0));
    outside.norm()
}

/// Distance from a segment to a box \[m\] (0 if they meet).
///
/// parry3d-f64's GJK distance between the segment, carried into the box's frame, and the box
/// as a cuboid: exact to rounding for these polytopes (the comparison with a golden-section
/// search is in `crates/ftwire-robot/docs/parry.md`). The test
/// `segment_distances_match_brute_force` checks it against a sampled minimum.
///
/// # Example
/// ```
/// use nalgebra::{Point3, Vector3};
/// let b = ftwire_robot::OrientedBox::new(ftwire_core::Pose::identity(), Vector3::new(0.5, 0.5, 0.5))?;
/// // A segment passing over the box's top face, 0.25 m above it.
/// let d = ftwire_robot::segment_box_distance(&Point3::new(-2.0, 0.0, 0.75), &Point3::new(2.0, 0.0, 0.75), &b);
/// assert!((d - 0.25).abs() < 1e-12);
/// # Ok::<(), ftwire_robot::RobotError>(())
/// ```
pub fn segment_box_distance(p0: &Point3<f64>, p1: &Point3<f64>, b: &OrientedBox) -> f64 {
    use parry3d_f64::math::{Pose as ParryPose, Vector as ParryVector};
    use parry3d_f64::query::details::distance_support_map_support_map;
    use parry3d_f64::shape::{Cuboid, Segment};
    // parry 0.31 speaks glam (glamx `DVec3`), not nalgebra: three numbers cross by hand.
    let glam = |v: &Vector3<f64>| ParryVector::new(v.x, v.y, v.z);
    let a = b.pose.inverse_transform_point(p0).coords;
    let c = b.pose.inverse_transform_point(p1).coords;
    distance_support_map_support_map(
        &ParryPose::identity(),
        &Cuboid::new(glam(&b.half_extents)),
        &Segment::new(glam(&a), glam(&c)),
    )
}

/// Which two bodies are in contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Contact {
    /// Capsule `left` of the left arm meets capsule `right` of the right arm.
    Arms {
        /// Capsule index of the left arm (0 = shoulder).
        left: usize,
        /// Capsule index of the right arm.
        right: usize,
    },
    /// Capsule `link` of `arm` meets obstacle number `obstacle`.
    Obstacle {
        /// The arm.
        arm: Arm,
        /// Capsule index (0 = shoulder).
        link: usize,
        /// Index in the obstacle slice.
        obstacle: usize,
    },
}

impl Robot {
    /// The capsules of one arm at one posture, in the robot base frame: between the origins of
    /// joints 1…7, then from joint 7 to the gripper clamp point.
    ///
    /// # Errors
    /// As [`Robot::fk`].
    ///
    /// # Example
    /// ```
    /// use ftwire_robot::{Arm, LinkRadii, Robot};
    /// let robot = Robot::sda10f()?;
    /// let q = *robot.preferred_posture(Arm::Left);
    /// let caps = robot.arm_capsules(Arm::Left, 0.0, &q, &LinkRadii::default())?;
    /// assert_eq!(caps.len(), 7);
    /// assert!((caps[0].radius - 0.10).abs() < 1e-12);
    /// # Ok::<(), ftwire_robot::RobotError>(())
    /// ```
    pub fn arm_capsules(
        &self,
        arm: Arm,
        torso: f64,
        q: &ArmJoints,
        radii: &LinkRadii,
    ) -> Result<[Capsule; LINK_CAPSULES], RobotError> {
        self.check_torso(torso)?;
        self.check_joints(arm, q)?;
        Ok(self.capsules_unchecked(arm, torso, q, radii))
    }

    pub(crate) fn capsules_unchecked(
        &self,
        arm: Arm,
        torso: f64,
        q: &ArmJoints,
        radii: &LinkRadii,
    ) -> [Capsule; LINK_CAPSULES] {
        let f = self.frames(arm, torso, q, self.grippers().get(arm));
        let tip = Point3::from(f.end.translation.vector);
        std::array::from_fn(|i| Capsule {
            a: f.origins[i],
            b: if i + 1 < ARM_DOF {
                f.origins[i + 1]
            } else {
                tip
            },
            radius: radii.radii[i],
        })
    }

    /// Whether the two arms' capsules overlap at this posture. The two shoulder capsules are
    /// not checked against each other: they meet at the torso by construction.
    ///
    /// Returns the first contact found, or `None` if the arms are apart.
    ///
    /// # Errors
    /// As [`Robot::fk`], for either arm.
    pub fn arms_collision(
        &self,
        torso: f64,
        left: &ArmJoints,
        right: &ArmJoints,
        radii: &LinkRadii,
    ) -> Result<Option<Contact>, RobotError> {
        let l = self.arm_capsules(Arm::Left, torso, left, radii)?;
        let r = self.arm_capsules(Arm::Right, torso, right, radii)?;
        Ok(capsule_sets_contact(&l, &r))
    }

    /// Whether one arm's capsules meet any of `obstacles` (boxes in the robot base frame).
    /// Returns the first contact found, or `None`.
    ///
    /// # Errors
    /// As [`Robot::fk`].
    pub fn arm_obstacle_collision(
        &self,
        arm: Arm,
        torso: f64,
        q: &ArmJoints,
        obstacles: &[OrientedBox],
        radii: &LinkRadii,
    ) -> Result<Option<Contact>, RobotError> {
        let caps = self.arm_capsules(arm, torso, q, radii)?;
        for (link, c) in caps.iter().enumerate() {
            for (obstacle, b) in obstacles.iter().enumerate() {
                if segment_box_distance(&c.a, &c.b, b) <= c.radius {
                    return Ok(Some(Contact::Obstacle {
                        arm,
                        link,
                        obstacle,
                    }));
                }
            }
        }
        Ok(None)
    }
}

pub(crate) fn capsule_sets_contact(
    l: &[Capsule; LINK_CAPSULES],
    r: &[Capsule; LINK_CAPSULES],
) -> Option<Contact> {
    for (i, a) in l.iter().enumerate() {
        for (j, b) in r.iter().enumerate() {
            if i == 0 && j == 0 {
                continue;
            }
            if segment_segment_distance(&a.a, &a.b, &b.a, &b.b) <= a.radius + b.radius {
                return Some(Contact::Arms { left: i, right: j });
            }
        }
    }
    None
}
