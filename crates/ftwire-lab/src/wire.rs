//! Wires as users name them ([`ftwire_app::config::wire`], re-exported here whole) or give
//! them by their numbers ([`from_numbers`], with the simulator's default rod's radius and
//! density when not given), and the simulator's rod of a wire.

use ftwire_core::WireParams;
use nalgebra::Vector3;

pub use ftwire_app::config::wire::*;
use ftwire_sim::RodParams;

use crate::error::LabError;

/// The simulator's parameters of `wire`, with gravity `gravity` \[m/s²\] in the world frame
/// (zero switches it off) and `edges` edges.
pub fn rod_params(wire: &WireSpec, gravity: Vector3<f64>, edges: usize) -> RodParams {
    RodParams {
        stiffness: wire.c,
        length: wire.length,
        radius: wire.radius,
        density: wire.density,
        gravity,
        rest_strain: Vector3::from(wire.natural_curvature),
        edges,
        ..RodParams::default()
    }
}

/// The radius \[m\] of a wire given by its numbers when none is given (`--radius`, a line of
/// `solve --batch`): that of the simulator's default rod, `RodParams::default()` (the 2 mm
/// nitinol wire of the paper's Table I).
pub fn default_radius() -> f64 {
    RodParams::default().radius
}

/// The density \[kg/m³\] of a wire given by its numbers when none is given (`--density`): the
/// default rod's (nitinol's).
pub fn default_density() -> f64 {
    RodParams::default().density
}

/// The gravity \[m/s²\] of the simulator when none is given (`sim-equilibrium --gravity`): the
/// default rod's.
pub fn default_gravity() -> [f64; 3] {
    RodParams::default().gravity.into()
}

/// A wire given by its numbers (command-line options, a line of `solve --batch`), checked:
/// stiffnesses and length finite and positive, the radius below half the length
/// ([`check_radius`]); `names` spell the radius and the length in the error as the user gave
/// them.
///
/// # Errors
/// Bad input saying what is wrong.
///
/// # Example
/// ```
/// use ftwire_lab::wire::from_numbers;
/// let c = [0.042, 0.055, 0.055];
/// let wire = from_numbers(c, 0.63, 0.001, ["--radius", "--length"])?;
/// assert_eq!(wire.length(), 0.63);
/// let e = from_numbers(c, 0.63, 0.5, ["radius", "length"]).expect_err("a disc");
/// assert!(e.to_string().starts_with("radius 0.5: "), "{e}");
/// # Ok::<(), ftwire_lab::LabError>(())
/// ```
pub fn from_numbers(
    c: [f64; 3],
    length: f64,
    radius: f64,
    [radius_name, length_name]: [&str; 2],
) -> Result<WireParams, LabError> {
    let wire = WireParams::new(c, length, radius)
        .map_err(|e| LabError::bad_input(format!("invalid wire: {e}")))?;
    check_radius(&wire, radius_name, length_name).map_err(LabError::bad_input)?;
    Ok(wire)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The presets' numbers live in `ftwire-app`, which never sees the simulator: they must be
    /// the simulator's presets.
    #[test]
    fn every_preset_loads_and_matches_the_simulator() -> Result<(), WireSpecError> {
        for name in PRESETS {
            let wire = WireSpec::load(name)?;
            assert_eq!(wire.name, name);
            let back = rod_params(&wire, Vector3::new(0.0, 0.0, -9.81), 100);
            let original = match name {
                "nitinol-2mm-630" => RodParams::nitinol_2mm_630(),
                "nitinol-3mm-910" => RodParams::nitinol_3mm_910(),
                "nitinol-3mm-820" => RodParams::nitinol_3mm_820(),
                _ => RodParams::electric_cable_3mm_920(),
            };
            assert_eq!(back, original, "{name}");
        }
        Ok(())
    }
}
