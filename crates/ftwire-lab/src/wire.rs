//! Wires as users name them ([`ftwire_app::config::wire`], re-exported here whole), and the
//! simulator's rod of a wire.

use nalgebra::Vector3;

pub use ftwire_app::config::wire::*;
use ftwire_sim::RodParams;

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
