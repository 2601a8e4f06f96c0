//! The wire model the estimators use, behind one trait.
//!
//! The estimators ask a model three things: the second gripper's pose `Γ(a)`, the Jacobian
//! `J(L)` with it, and the shape. [`KirchhoffModel`] answers with the Kirchhoff rod of
//! `ftwire_rod::Rod`: the paper's weightless, straight-at-rest model by default, or the loaded
//! model with a weight per length and rest strains ([`KirchhoffModel::with_load`]).

use ftwire_core::{Pose, WireParams};
use ftwire_rod::{JacobianSolution, Load, Rod, Shape};
use nalgebra::{Vector3, Vector6};

use crate::EstimateError;

/// A wire model: the map from a configuration `a` to the wire's shape, for one set of wire
/// parameters, and the family of such maps over the parameters (for identification).
///
/// Implementations are plain data, cheap to clone, and shareable between threads.
pub trait WireModel: Clone + Send + Sync {
    /// The wire parameters this model solves with.
    fn wire(&self) -> &WireParams;

    /// The same model with other wire parameters (everything else, e.g. a distributed load,
    /// kept).
    #[must_use]
    fn with_wire(&self, wire: WireParams) -> Self;

    /// The wire's weight per length `w` \[N/m\] in the base clamp frame (zero for a weightless
    /// model).
    fn weight_per_length(&self) -> Vector3<f64>;

    /// The same model with weight per length `w` (base clamp frame), everything else kept.
    ///
    /// # Errors
    /// When `w` is not finite, or the model cannot carry a weight.
    fn with_weight_per_length(&self, w: Vector3<f64>) -> Result<Self, EstimateError>;

    /// `Γ(a)`: the second gripper's clamp pose in the base clamp frame.
    ///
    /// # Errors
    /// When `a` is not finite or outside `A`, or the solve diverges.
    fn tip(&self, a: &Vector6<f64>) -> Result<Pose, EstimateError>;

    /// `Γ(a)`, `J(L)`, `M(L)` and the stability record.
    ///
    /// # Errors
    /// As [`WireModel::tip`].
    fn jacobian(&self, a: &Vector6<f64>) -> Result<JacobianSolution, EstimateError>;

    /// The shape at `nodes` nodes uniformly spaced in arc length, both ends included.
    ///
    /// # Errors
    /// As [`WireModel::tip`], and when `nodes` is out of the model's range.
    fn shape(&self, a: &Vector6<f64>, nodes: usize) -> Result<Shape, EstimateError>;

    /// Whether `a ∈ A_stable`.
    ///
    /// # Errors
    /// As [`WireModel::tip`].
    fn is_stable(&self, a: &Vector6<f64>) -> Result<bool, EstimateError>;
}

/// The paper's model: a weightless Kirchhoff rod with a straight rest shape (`ftwire_rod`).
///
/// # Example
/// ```
/// use ftwire_core::WireParams;
/// use ftwire_estimate::{KirchhoffModel, WireModel};
/// use nalgebra::Vector6;
/// let model = KirchhoffModel::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
/// let tip = model.tip(&Vector6::new(0.0, 0.0, 0.01, 0.0, 0.0, 0.0))?;
/// assert!(tip.translation.vector.y > 0.0);
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KirchhoffModel {
    rod: Rod,
}

impl KirchhoffModel {
    /// The Kirchhoff model of `wire`, with the default integrator.
    pub fn new(wire: WireParams) -> Self {
        Self {
            rod: Rod::new(wire),
        }
    }

    /// The model over an existing rod (keeps its integrator settings).
    pub fn from_rod(rod: Rod) -> Self {
        Self { rod }
    }

    /// The underlying rod.
    pub fn rod(&self) -> &Rod {
        &self.rod
    }

    /// The same model with a distributed load: a weight per length and rest strains
    /// ([`ftwire_rod::Load`]; the loaded model, beyond the paper).
    #[must_use]
    pub fn with_load(self, load: Load) -> Self {
        Self {
            rod: self.rod.with_load(load),
        }
    }
}

impl WireModel for KirchhoffModel {
    fn wire(&self) -> &WireParams {
        self.rod.wire()
    }

    fn with_wire(&self, wire: WireParams) -> Self {
        Self {
            rod: Rod::new(wire)
                .with_integrator(*self.rod.integrator())
                .with_load(*self.rod.load()),
        }
    }

    fn weight_per_length(&self) -> Vector3<f64> {
        self.rod.load().weight_per_length
    }

    fn with_weight_per_length(&self, w: Vector3<f64>) -> Result<Self, EstimateError> {
        ftwire_core::ensure_finite("weight_per_length", w.as_slice())?;
        Ok(self.with_load(Load {
            weight_per_length: w,
            ..*self.rod.load()
        }))
    }

    fn tip(&self, a: &Vector6<f64>) -> Result<Pose, EstimateError> {
        Ok(self.rod.tip(a)?)
    }

    fn jacobian(&self, a: &Vector6<f64>) -> Result<JacobianSolution, EstimateError> {
        Ok(self.rod.jacobian(a)?)
    }

    fn shape(&self, a: &Vector6<f64>, nodes: usize) -> Result<Shape, EstimateError> {
        Ok(self.rod.shape(a, nodes)?)
    }

    fn is_stable(&self, a: &Vector6<f64>) -> Result<bool, EstimateError> {
        Ok(self.rod.is_stable(a)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn with_wire_changes_only_the_wire() -> Result<(), EstimateError> {
        let a = Vector6::new(0.0, 0.02, 0.01, -0.05, 0.03, 0.0);
        let short = KirchhoffModel::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
        let long = short.with_wire(short.wire().with_length(1.26)?);
        assert_relative_eq!(long.wire().length(), 1.26);
        assert_eq!(long.wire().c(), short.wire().c());
        // The first 0.63 m of the longer wire is the shorter wire: same a, same ODE from t = 0,
        // so the middle node of a 3-node shape of the long wire is the short wire's tip.
        let tip_short = short.tip(&a)?;
        let shape_long = long.shape(&a, 3)?;
        assert!((shape_long.positions[1] - tip_short.translation.vector).norm() < 1e-9);
        assert!((shape_long.positions[2] - tip_short.translation.vector).norm() > 0.1);
        Ok(())
    }
}
