//! The Kirchhoff model against the independent discrete-elastic-rod simulator (issue 3).
//!
//! Setup: configurations `a` sampled in `A_stable` (uniform in normalised units, torque · L/c2
//! and force · L²/c2), gravity off, straight rest shape; the simulated wire is clamped at the
//! identity and at `b = Γ(a)`, and Newton starts from the Kirchhoff shape (the same tip pose can
//! hold several stable equilibria).
//!
//! What agreement means here. The simulator is a discretisation, so it differs from the model
//! by an `O(h²)` error; that error is amplified where the wrench is ill-conditioned in the tip
//! pose (a taut, nearly straight wire, whose tension is hypersensitive to the end distance; and
//! near the stability boundary, where `J(L)` is nearly singular). Two tests:
//! - [`bounds_at_moderate_loads`]: the pass conditions over `A_stable ∩ [−5, 5]⁶`: the
//!   centreline within 0.5 mm at N = 100, and the base wrench within 1 % of `|a|` (torque and
//!   force each, normalised) at N = 200. (At N = 100 the worst force error of a taut wire is
//!   about 2 %, the discretisation error of its tension.)
//! - [`the_gap_is_second_order_discretisation_error`]: over strongly bent configurations
//!   (`[−10, 10]⁶`), doubling N divides the wrench and shape gaps by about 4.
//!
//! Worst cases are printed:
//! `cargo test --release -p ftwire --test model_vs_sim -- --nocapture`.

use ftwire::bridge::kirchhoff_guess;
use ftwire_core::{Pose, WireParams};
use ftwire_rod::sampling::Sampler;
use ftwire_sim::{RodParams, World};
use nalgebra::Vector6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn wires() -> [(&'static str, RodParams); 2] {
    [
        ("nitinol 2 mm × 630 mm", RodParams::nitinol_2mm_630()),
        ("nitinol 3 mm × 820 mm", RodParams::nitinol_3mm_820()),
    ]
}

/// Model and simulator for one wire at `edges`, gravity off.
fn setup(preset: RodParams, edges: usize) -> (ftwire_rod::Rod, World) {
    let params = RodParams { edges, ..preset }.without_gravity();
    let wire = WireParams::new(params.stiffness, params.length, params.radius).expect("preset");
    let world = World::new(params).expect("preset is valid");
    (ftwire_rod::Rod::new(wire), world)
}

/// The gaps between simulator and model for one configuration.
#[derive(Debug, Clone, Copy, Default)]
struct Gap {
    /// |τ_sim − τ| / |a|, normalised units.
    torque: f64,
    /// |f_sim − f| / |a|, normalised units.
    force: f64,
    /// Largest distance between the simulated centreline nodes and the model \[mm\].
    shape_mm: f64,
}

impl Gap {
    fn max(self, other: Gap) -> Gap {
        Gap {
            torque: self.torque.max(other.torque),
            force: self.force.max(other.force),
            shape_mm: self.shape_mm.max(other.shape_mm),
        }
    }
}

fn gap(model: &ftwire_rod::Rod, world: &World, a: &Vector6<f64>) -> Gap {
    let b = model.tip(a).expect("a is in A");
    let guess = kirchhoff_guess(model, a, world.rod()).expect("a is in A");
    let eq = world
        .solve_with_guess(&guess, &Pose::identity(), &b)
        .unwrap_or_else(|e| panic!("a = {a:?}: {e}"));
    assert!(
        eq.stable_minimum,
        "a = {a:?}: the simulator finds a saddle where the model is stable"
    );

    let wire = model.wire();
    let (torque_scale, force_scale) = (1.0 / wire.torque_scale(), 1.0 / wire.force_scale());
    let sim = eq.base_wrench.to_vector();
    let norm_a = (a.fixed_rows::<3>(0).scale(torque_scale).norm_squared()
        + a.fixed_rows::<3>(3).scale(force_scale).norm_squared())
    .sqrt();
    let torque = (sim.fixed_rows::<3>(0) - a.fixed_rows::<3>(0)).norm() * torque_scale / norm_a;
    let force = (sim.fixed_rows::<3>(3) - a.fixed_rows::<3>(3)).norm() * force_scale / norm_a;

    // The simulator's interior nodes sit at arc lengths (k − ½)h, odd multiples of h/2.
    let rod = world.rod();
    let shape = model
        .shape(a, 2 * (rod.edges() - 1) + 1)
        .expect("a is in A");
    let shape_mm = eq
        .centreline()
        .iter()
        .enumerate()
        .take(rod.edges())
        .skip(1)
        .map(|(k, node)| (node.coords - shape.positions[2 * k - 1]).norm() * 1e3)
        .fold(0.0, f64::max);
    Gap {
        torque,
        force,
        shape_mm,
    }
}

fn samples(model: &ftwire_rod::Rod, half_width: f64, count: usize, seed: u64) -> Vec<Vector6<f64>> {
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

#[test]
fn bounds_at_moderate_loads() {
    for (name, preset) in wires() {
        let (model, world_100) = setup(preset, 100);
        let (_, world_200) = setup(preset, 200);
        let mut worst_100 = Gap::default();
        let mut worst_200 = Gap::default();
        for a in samples(&model, 5.0, 20, 2026) {
            worst_100 = worst_100.max(gap(&model, &world_100, &a));
            worst_200 = worst_200.max(gap(&model, &world_200, &a));
        }
        eprintln!("{name}: worst over A_stable ∩ [−5, 5]⁶, N = 100: {worst_100:?}");
        eprintln!("{name}: worst over A_stable ∩ [−5, 5]⁶, N = 200: {worst_200:?}");
        assert!(worst_100.shape_mm < 0.5, "{name}: {worst_100:?}");
        assert!(worst_200.torque < 0.01, "{name}: {worst_200:?}");
        assert!(worst_200.force < 0.01, "{name}: {worst_200:?}");
    }
}

#[test]
fn the_gap_is_second_order_discretisation_error() {
    for (name, preset) in wires() {
        let (model, world_100) = setup(preset, 100);
        let (_, world_200) = setup(preset, 200);
        let mut worst_100 = Gap::default();
        for a in samples(&model, 10.0, 10, 99) {
            let coarse = gap(&model, &world_100, &a);
            let fine = gap(&model, &world_200, &a);
            worst_100 = worst_100.max(coarse);
            // Doubling N divides an O(h²) error by about 4; a modelling mismatch would not go.
            for (what, c, f) in [
                ("torque", coarse.torque, fine.torque),
                ("force", coarse.force, fine.force),
                ("shape", coarse.shape_mm, fine.shape_mm),
            ] {
                if c > 1e-4 {
                    let ratio = c / f;
                    assert!(
                        (2.4..6.0).contains(&ratio),
                        "{name}, a = {a:?}: {what} gap {c:.3e} at N = 100, {f:.3e} at N = 200"
                    );
                }
            }
        }
        eprintln!("{name}: worst over A_stable ∩ [−10, 10]⁶, N = 100: {worst_100:?}");
    }
}
