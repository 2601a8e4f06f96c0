//! Shared setup of the tests that compare the Kirchhoff model with the simulator.
#![allow(dead_code)]

use ftwire_core::WireParams;
use ftwire_rod::sampling::Sampler;
use ftwire_sim::{RodParams, World};
use nalgebra::Vector6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// The two nitinol wires of the cross-checks, with their names.
pub fn wires() -> [(&'static str, RodParams); 2] {
    [
        ("nitinol 2 mm × 630 mm", RodParams::nitinol_2mm_630()),
        ("nitinol 3 mm × 820 mm", RodParams::nitinol_3mm_820()),
    ]
}

/// Model and simulator for one wire at `edges`, gravity off.
pub fn setup(preset: RodParams, edges: usize) -> (ftwire_rod::Rod, World) {
    let params = RodParams { edges, ..preset }.without_gravity();
    let wire = WireParams::new(params.stiffness, params.length, params.radius).expect("preset");
    let world = World::new(params).expect("preset is valid");
    (ftwire_rod::Rod::new(wire), world)
}

/// `count` configurations of `A_stable`, uniform in normalised units in `[−hw, hw]⁶`, seeded.
pub fn samples(
    model: &ftwire_rod::Rod,
    half_width: f64,
    count: usize,
    seed: u64,
) -> Vec<Vector6<f64>> {
    let sampler = Sampler::new(half_width).expect("positive half-width");
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|_| {
            sampler
                .sample_stable(model, &mut rng)
                .expect("A_stable is not empty")
        })
        .collect()
}
