//! Building the kinematic model from URDF text (parsed by `urdf-rs`).

use std::collections::HashMap;

use ftwire_core::Pose;
use nalgebra::{Translation3, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::RobotError;
use crate::chain::{ARM_DOF, ArmChain, JointLimit, RevoluteJoint};

/// The embedded SDA10F URDF: `data/robots/sda10f.urdf` of the ftwire repository, compiled in so
/// that the product needs no data files at run time.
pub const SDA10F_URDF: &str = include_str!("../../../data/robots/sda10f.urdf");

/// Which URDF links bound the two arm chains.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ChainNames {
    /// The robot base link; every pose is expressed in it (default `torso_base_link`).
    pub base_link: String,
    /// The left arm's flange link (default `arm_left_link_tool0`).
    pub left_tool0: String,
    /// The right arm's flange link (default `arm_right_link_tool0`).
    pub right_tool0: String,
}

impl Default for ChainNames {
    fn default() -> Self {
        Self {
            base_link: "torso_base_link".into(),
            left_tool0: "arm_left_link_tool0".into(),
            right_tool0: "arm_right_link_tool0".into(),
        }
    }
}

/// The kinematic structure read from a URDF: the shared torso joint and both arms.
pub(crate) struct Kinematics {
    pub torso: RevoluteJoint,
    pub left: ArmChain,
    pub right: ArmChain,
}

pub(crate) fn parse(text: &str, names: &ChainNames) -> Result<Kinematics, RobotError> {
    let robot = urdf_rs::read_from_string(text).map_err(|e| RobotError::Urdf {
        message: e.to_string(),
    })?;
    let (torso_l, left) = chain(&robot, &names.base_link, &names.left_tool0)?;
    let (torso_r, right) = chain(&robot, &names.base_link, &names.right_tool0)?;
    if torso_l != torso_r {
        return Err(RobotError::Model {
            message: format!(
                "the arms do not share their first joint ({} vs {})",
                torso_l.name, torso_r.name
            ),
        });
    }
    Ok(Kinematics {
        torso: torso_l,
        left,
        right,
    })
}

fn origin(pose: &urdf_rs::Pose) -> Pose {
    let [x, y, z] = pose.xyz.0;
    let [r, p, yaw] = pose.rpy.0;
    // URDF rpy is R = Rz(yaw) Ry(pitch) Rx(roll), nalgebra's euler-angle convention.
    Pose::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_euler_angles(r, p, yaw),
    )
}

/// Walks from `tip` up to `base`, folding fixed joints into the next joint's origin, and returns
/// the first revolute joint (the torso) and the arm chain after it.
fn chain(
    robot: &urdf_rs::Robot,
    base: &str,
    tip: &str,
) -> Result<(RevoluteJoint, ArmChain), RobotError> {
    let by_child: HashMap<&str, &urdf_rs::Joint> = robot
        .joints
        .iter()
        .map(|j| (j.child.link.as_str(), j))
        .collect();
    let mut path = Vec::new();
    let mut link = tip;
    while link != base {
        let joint = by_child.get(link).ok_or_else(|| RobotError::Model {
            message: format!("no joint leads to link `{link}` on the way from `{tip}` to `{base}`"),
        })?;
        if path.len() > robot.joints.len() {
            return Err(RobotError::Model {
                message: "the joint graph has a cycle".into(),
            });
        }
        path.push(*joint);
        link = joint.parent.link.as_str();
    }
    path.reverse();

    let mut pending = Pose::identity();
    let mut movable = Vec::new();
    for joint in path {
        let o = origin(&joint.origin);
        if !o.translation.vector.iter().all(|v| v.is_finite())
            || !o.rotation.coords.iter().all(|v| v.is_finite())
        {
            return Err(RobotError::Model {
                message: format!("joint `{}` has a non-finite origin", joint.name),
            });
        }
        match joint.joint_type {
            urdf_rs::JointType::Fixed => pending *= o,
            urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                let axis =
                    Unit::try_new(Vector3::from(joint.axis.xyz.0), 1e-9).ok_or_else(|| {
                        RobotError::Model {
                            message: format!(
                                "joint `{}` has a zero or non-finite axis",
                                joint.name
                            ),
                        }
                    })?;
                let limit = if joint.joint_type == urdf_rs::JointType::Continuous {
                    JointLimit {
                        min: -std::f64::consts::PI,
                        max: std::f64::consts::PI,
                    }
                } else {
                    JointLimit {
                        min: joint.limit.lower,
                        max: joint.limit.upper,
                    }
                };
                if !(limit.min.is_finite() && limit.max.is_finite() && limit.min < limit.max) {
                    return Err(RobotError::Model {
                        message: format!(
                            "joint `{}` has limits [{}, {}]; finite limits with lower < upper are needed",
                            joint.name, limit.min, limit.max
                        ),
                    });
                }
                movable.push(RevoluteJoint {
                    name: joint.name.clone(),
                    origin: pending * o,
                    axis,
                    limit,
                });
                pending = Pose::identity();
            }
            _ => {
                return Err(RobotError::Model {
                    message: format!(
                        "joint `{}` is {:?}; only revolute, continuous and fixed joints are supported",
                        joint.name, joint.joint_type
                    ),
                });
            }
        }
    }
    if movable.len() != ARM_DOF + 1 {
        return Err(RobotError::Model {
            message: format!(
                "the chain from `{base}` to `{tip}` has {} movable joints; a torso joint plus {ARM_DOF} arm joints are expected",
                movable.len()
            ),
        });
    }
    let mut it = movable.into_iter();
    let torso = it.next().ok_or_else(|| RobotError::Model {
        message: "no torso joint".into(),
    })?;
    let arm: Vec<RevoluteJoint> = it.collect();
    let joints: [RevoluteJoint; ARM_DOF] = arm.try_into().map_err(|_| RobotError::Model {
        message: "wrong number of arm joints".into(),
    })?;
    Ok((
        torso,
        ArmChain {
            joints,
            flange: pending,
        },
    ))
}
