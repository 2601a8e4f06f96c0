//! A point of the centreline at arc length `s`, and its derivative with respect to `a`.
//!
//! The model's ODE runs from `t = 0`, so the first `s` metres of a wire of length `L` under
//! configuration `a` *are* a wire of length `s` under the same `a`: `p(s; a)` is the tip of that
//! shorter wire (`model.with_wire(wire.with_length(s))`), and its Jacobian `J(s)` is the shorter
//! wire's `J(L)`. `J(s) δa` is the body twist `(δω, δv)` of `q(s)` (`q + δq = q exp(ĵ)`), so the
//! position moves by `δp = R(s) δv`:
//!
//! ```text
//! ∂p(s)/∂a = R(s) · J(s)[rows 3..6]
//! ```
//!
//! Guarded by `tests/shape_fit.rs::marker_jacobian_matches_central_differences`.
//!
//! A `J(t)`-at-nodes API in `ftwire_rod` (the Jacobian state `J` kept at the grid points, as the
//! shape keeps `q`) would give all `V` marker Jacobians from one integration instead of `V`
//! shorter ones: `V / 2` to `V` times less work per Gauss–Newton step (the shorter wires average
//! `L / 2`, but a short wire still takes the integrator's minimum of 8 steps).

use ftwire_core::WireParams;
use nalgebra::{Matrix3x6, Vector3, Vector6};

use crate::{EstimateError, WireModel};

/// Arc lengths below this fraction of `L` are the clamp point itself (`p = 0`, `∂p/∂a = 0`).
const AT_CLAMP: f64 = 1e-12;

/// A centreline point and, if asked for, its derivatives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CentrelinePoint {
    /// `p(s; a)` \[m\], base clamp frame.
    pub position: Vector3<f64>,
    /// The unit tangent `R(s) e1`.
    pub tangent: Vector3<f64>,
    /// `∂p(s)/∂a` \[m per unit of a\] (zero unless asked for).
    pub jacobian: Matrix3x6<f64>,
}

/// The model of the first `s` metres of `model`'s wire, or `None` at the clamp point.
fn truncated<M: WireModel>(model: &M, s: f64) -> Result<Option<M>, EstimateError> {
    let wire: &WireParams = model.wire();
    let length = wire.length();
    if s <= AT_CLAMP * length {
        return Ok(None);
    }
    if s >= length {
        return Ok(Some(model.clone()));
    }
    Ok(Some(model.with_wire(wire.with_length(s)?)))
}

/// `p(s; a)` and the tangent; with `with_jacobian`, also `∂p(s)/∂a`. `s` is clamped to
/// `[0, L]`.
///
/// # Errors
/// As [`WireModel::tip`] and [`WireModel::jacobian`].
///
/// # Example
/// ```
/// use ftwire_core::WireParams;
/// use ftwire_estimate::{KirchhoffModel, WireModel, shape::centreline_point};
/// use nalgebra::Vector6;
/// let model = KirchhoffModel::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
/// let a = Vector6::new(0.0, 0.02, 0.01, -0.05, 0.03, 0.0);
/// let middle = centreline_point(&model, &a, 0.315, true)?;
/// let shape = model.shape(&a, 3)?;
/// assert!((middle.position - shape.positions[1]).norm() < 1e-9);
/// assert!(middle.jacobian.norm() > 0.0);
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
pub fn centreline_point<M: WireModel>(
    model: &M,
    a: &Vector6<f64>,
    s: f64,
    with_jacobian: bool,
) -> Result<CentrelinePoint, EstimateError> {
    let Some(part) = truncated(model, s)? else {
        return Ok(CentrelinePoint {
            position: Vector3::zeros(),
            tangent: Vector3::x(),
            jacobian: Matrix3x6::zeros(),
        });
    };
    if !with_jacobian {
        let tip = part.tip(a)?;
        return Ok(CentrelinePoint {
            position: tip.translation.vector,
            tangent: tip.rotation * Vector3::x(),
            jacobian: Matrix3x6::zeros(),
        });
    }
    let solution = part.jacobian(a)?;
    let rotation = solution.tip.rotation.to_rotation_matrix();
    let translational = solution.jacobian.fixed_rows::<3>(3).into_owned();
    Ok(CentrelinePoint {
        position: solution.tip.translation.vector,
        tangent: rotation * Vector3::x(),
        jacobian: rotation.matrix() * translational,
    })
}
