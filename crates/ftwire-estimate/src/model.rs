//! The wire model the estimators use, behind one trait.
//!
//! The estimators ask a model three things: the second gripper's pose `Γ(a)`, the Jacobian
//! `J(L)` with it, and the shape. [`KirchhoffModel`] answers with the paper's model
//! (`ftwire_rod::Rod`); a gravity- and rest-curvature-aware model will implement the same trait.

use ftwire_core::{Pose, WireParams};
use ftwire_rod::{JacobianSolution, Rod, Shape};
use nalgebra::Vector6;

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
}

impl WireModel for KirchhoffModel {
    fn wire(&self) -> &WireParams {
        self.rod.wire()
    }

    fn with_wire(&self, wire: WireParams) -> Self {
        Self {
            rod: Rod::new(wire).with_integrator(*self.rod.integrator()),
        }
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
