//! The configuration space `A` of the wire (paper eq. 2) and its normalised units.
//!
//! A configuration `a = μ(0) = (τ1, τ2, τ3, f1, f2, f3)` is the wrench the wire exerts on the
//! base gripper at the clamp, in the clamp frame, torque \[N·m\] first, then force \[N\]
//! (paper eq. 6–7). `A = { a : (a2, a3, a5, a6) ≠ 0 }` (eq. 2).
//!
//! To compare configurations across wires, torques are measured in units of `c2/L` and forces
//! in units of `c2/L²` ([`WireParams::torque_scale`], [`WireParams::force_scale`]): in these
//! *normalised units* a wire of any stiffness and length with `c = (c1/c2, 1, c3/c2)` and
//! `L = 1` has the same shape, scaled by `L`.

use ftwire_core::{WireParams, ensure_finite};
use nalgebra::Vector6;

use crate::RodError;

/// Checks that `a` is finite and in `A` (eq. 2).
///
/// # Errors
/// [`RodError::Core`] naming the first non-finite component of `a`, or
/// [`RodError::OutsideA`] if `a2 = a3 = a5 = a6 = 0`.
///
/// # Example
/// ```
/// use nalgebra::Vector6;
/// use ftwire_rod::validate_configuration;
/// assert!(validate_configuration(&Vector6::new(0.0, 0.0, 0.1, -1.0, 0.0, 0.0)).is_ok());
/// assert!(validate_configuration(&Vector6::new(1.0, 0.0, 0.0, -1.0, 0.0, 0.0)).is_err());
/// ```
pub fn validate_configuration(a: &Vector6<f64>) -> Result<(), RodError> {
    ensure_finite("a", a.as_slice())?;
    if a[1] == 0.0 && a[2] == 0.0 && a[4] == 0.0 && a[5] == 0.0 {
        return Err(RodError::OutsideA { a: (*a).into() });
    }
    Ok(())
}

/// Expresses a configuration `a` \[N·m, N\] in normalised units: torques divided by
/// `c2/L`, forces by `c2/L²`.
///
/// # Example
/// ```
/// use nalgebra::Vector6;
/// use ftwire_rod::{WireParams, from_normalised, to_normalised};
/// let wire = WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?;
/// let a = Vector6::new(0.01, -0.02, 0.03, -0.1, 0.2, 0.05);
/// assert!((from_normalised(&wire, &to_normalised(&wire, &a)) - a).norm() < 1e-15);
/// # Ok::<(), ftwire_rod::RodError>(())
/// ```
pub fn to_normalised(wire: &WireParams, a: &Vector6<f64>) -> Vector6<f64> {
    let (ts, fs) = (wire.torque_scale(), wire.force_scale());
    Vector6::new(
        a[0] / ts,
        a[1] / ts,
        a[2] / ts,
        a[3] / fs,
        a[4] / fs,
        a[5] / fs,
    )
}

/// The inverse of [`to_normalised`]: a configuration in \[N·m, N\] from normalised units.
pub fn from_normalised(wire: &WireParams, normalised: &Vector6<f64>) -> Vector6<f64> {
    let (ts, fs) = (wire.torque_scale(), wire.force_scale());
    let n = normalised;
    Vector6::new(
        n[0] * ts,
        n[1] * ts,
        n[2] * ts,
        n[3] * fs,
        n[4] * fs,
        n[5] * fs,
    )
}
