//! The planners' state spaces: normalised `A` with the base gripper fixed (the paper), and
//! `Z = A × Q` with the base gripper moving too (Sintov et al. 2020).
//!
//! A state is a point of `R^D` in which the Euclidean distance is the planners' metric:
//! normalised `a` (torque in `c2/L`, force in `c2/L²`), then, for `Z`, the base gripper's
//! offset from the scene's base pose (translation in [`MovingBase::translation_unit`], rotation
//! vector in [`MovingBase::rotation_unit`]).

use ftwire_core::{Pose, WireParams};
use ftwire_rod::{from_normalised, to_normalised};
use nalgebra::{SVector, Translation3, UnitQuaternion, Vector3};

use crate::ZPoint;

/// A planning space of dimension `D`: a box of states and the map to configurations.
pub trait Space<const D: usize> {
    /// The box's lower corner.
    fn lower(&self) -> SVector<f64, D>;
    /// The box's upper corner.
    fn upper(&self) -> SVector<f64, D>;
    /// The configuration of a state.
    fn config(&self, x: &SVector<f64, D>) -> ZPoint;
    /// The state of a configuration.
    fn state(&self, config: &ZPoint) -> SVector<f64, D>;
}

/// Normalised `A`, the base gripper held at one pose (the paper's planner).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedBase {
    /// The wire (for the normalised units).
    pub wire: WireParams,
    /// World from the base gripper's clamp frame.
    pub base: Pose,
    /// Lower corner of the box of normalised `a` that is sampled.
    pub lower: SVector<f64, 6>,
    /// Upper corner of that box.
    pub upper: SVector<f64, 6>,
}

impl FixedBase {
    /// The box `[−half_width, half_width]⁶` of normalised `a`.
    pub fn new(wire: WireParams, base: Pose, half_width: f64) -> Self {
        Self {
            wire,
            base,
            lower: SVector::repeat(-half_width),
            upper: SVector::repeat(half_width),
        }
    }

    /// The smallest box holding the configurations `a` (physical units), padded by `pad`
    /// normalised units on every side: the planner then samples near its start and goal, where
    /// the arms can follow (most of a wide box is out of the second arm's reach).
    pub fn around(wire: WireParams, base: Pose, configurations: &[ZPoint], pad: f64) -> Self {
        let mut lower = SVector::<f64, 6>::repeat(f64::INFINITY);
        let mut upper = SVector::<f64, 6>::repeat(f64::NEG_INFINITY);
        for c in configurations {
            let x = to_normalised(&wire, &c.a);
            lower = lower.inf(&x);
            upper = upper.sup(&x);
        }
        if configurations.is_empty() {
            (lower, upper) = (SVector::zeros(), SVector::zeros());
        }
        Self {
            wire,
            base,
            lower: lower.add_scalar(-pad),
            upper: upper.add_scalar(pad),
        }
    }
}

impl Space<6> for FixedBase {
    fn lower(&self) -> SVector<f64, 6> {
        self.lower
    }
    fn upper(&self) -> SVector<f64, 6> {
        self.upper
    }
    fn config(&self, x: &SVector<f64, 6>) -> ZPoint {
        ZPoint {
            a: from_normalised(&self.wire, x),
            base: self.base,
        }
    }
    fn state(&self, config: &ZPoint) -> SVector<f64, 6> {
        to_normalised(&self.wire, &config.a)
    }
}

/// `Z = A × Q`: normalised `a` and the base gripper's offset from a reference pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MovingBase {
    /// The wire (for the normalised units).
    pub wire: WireParams,
    /// The reference pose of the base gripper (world from clamp); offsets are from it.
    pub base: Pose,
    /// Lower corner of the box of normalised `a` that is sampled.
    pub a_lower: SVector<f64, 6>,
    /// Upper corner of that box.
    pub a_upper: SVector<f64, 6>,
    /// Largest base translation from the reference \[m\] per axis (default `0.15`).
    pub translation_range: f64,
    /// Largest base rotation-vector component from the reference \[rad\] (default `0.5`).
    pub rotation_range: f64,
    /// Base translation worth one unit of normalised `a` in the metric \[m\] (default `0.05`).
    pub translation_unit: f64,
    /// Base rotation worth one unit of normalised `a` in the metric \[rad\] (default `0.25`).
    pub rotation_unit: f64,
}

impl MovingBase {
    /// A `Z` space around `base` with the default ranges and units, `a` in
    /// `[−half_width, half_width]⁶` (normalised).
    pub fn new(wire: WireParams, base: Pose, half_width: f64) -> Self {
        Self {
            wire,
            base,
            a_lower: SVector::repeat(-half_width),
            a_upper: SVector::repeat(half_width),
            translation_range: 0.15,
            rotation_range: 0.5,
            translation_unit: 0.05,
            rotation_unit: 0.25,
        }
    }
}

impl MovingBase {
    /// The same space with the box of normalised `a` set to `[lower, upper]` (e.g. a
    /// [`FixedBase::around`] box).
    #[must_use]
    pub fn with_a_box(self, lower: SVector<f64, 6>, upper: SVector<f64, 6>) -> Self {
        Self {
            a_lower: lower,
            a_upper: upper,
            ..self
        }
    }

    fn corner(&self, a: &SVector<f64, 6>, sign: f64) -> SVector<f64, 12> {
        let t = sign * self.translation_range / self.translation_unit;
        let r = sign * self.rotation_range / self.rotation_unit;
        SVector::from_fn(|i, _| match i {
            0..=5 => a[i],
            6..=8 => t,
            _ => r,
        })
    }
}

impl Space<12> for MovingBase {
    fn lower(&self) -> SVector<f64, 12> {
        self.corner(&self.a_lower, -1.0)
    }
    fn upper(&self) -> SVector<f64, 12> {
        self.corner(&self.a_upper, 1.0)
    }
    fn config(&self, x: &SVector<f64, 12>) -> ZPoint {
        let a = from_normalised(&self.wire, &x.fixed_rows::<6>(0).into_owned());
        let t: Vector3<f64> = x.fixed_rows::<3>(6) * self.translation_unit;
        let r: Vector3<f64> = x.fixed_rows::<3>(9) * self.rotation_unit;
        let base = Pose::from_parts(
            Translation3::from(self.base.translation.vector + t),
            UnitQuaternion::from_scaled_axis(r) * self.base.rotation,
        );
        ZPoint { a, base }
    }
    fn state(&self, config: &ZPoint) -> SVector<f64, 12> {
        let a = to_normalised(&self.wire, &config.a);
        let t =
            (config.base.translation.vector - self.base.translation.vector) / self.translation_unit;
        let r = (config.base.rotation * self.base.rotation.inverse()).scaled_axis()
            / self.rotation_unit;
        SVector::from_fn(|i, _| match i {
            0..=5 => a[i],
            6..=8 => t[i - 6],
            _ => r[i - 9],
        })
    }
}
