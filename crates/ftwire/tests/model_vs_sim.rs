//! The Kirchhoff model against the independent discrete-elastic-rod simulator.
//!
//! Setup: configurations `a` sampled in `A_stable` (uniform in normalised units, torque · L/c2
//! and force · L²/c2), gravity off, straight rest shape; the simulated wire (N = 100 edges, the
//! issue's resolution) is clamped at the identity and at `b = Γ(a)`, and Newton starts from the
//! Kirchhoff shape (the same tip pose can hold several stable equilibria). The pass conditions
//! are the issue's: base wrench within 1 % of `|a|` (torque and force each, normalised) and
//! centreline within 0.5 mm of the model.
//!
//! What agreement means here. The simulator is a discretisation, so it differs from the model
//! by an `O(h²)` error, amplified where the wrench is ill-conditioned in the tip pose (near the
//! stability boundary, where the equilibrium is nearly critical). The DER's bending strain is
//! the turning angle in the mid-vertex material frame (`ftwire-sim`, `energy/bend_twist.rs`),
//! which removed the two largest `O(h²)` terms (worst gaps over `[−30, 30]⁶` at N = 100: force
//! 3.6 % → 0.9 %, shape 6.7 mm → 1.4 mm). What is asserted (the shape is compared on the
//! physical wire, `wire_centreline`, from clamp point to clamp point, without the ghost nodes):
//! - [`bounds_at_moderate_loads`]: every sample of `A_stable ∩ [−5, 5]⁶` (20 seeds × 20, both
//!   wires) meets the bounds at N = 100. The margin on the force is thin: the worst
//!   sample (the same normalised configuration on both wires, at seeds 2026 and 7) is at
//!   0.997 %; the 800 samples of a survey at seeds 10–49 stay under 0.8 %; torque and shape
//!   under 0.06 % and 0.08 mm.
//! - [`bounds_over_the_default_range`]: over the default sampler's range `[−30, 30]⁶` (30 seeds
//!   × 20, both wires), at least 90 % of the samples meet all three bounds at N = 100 (measured
//!   92.2 % and 91.0 %: a thin margin, 10 of these seeds alone give 89.5 % on the 2 mm wire),
//!   and the medians are an order of magnitude inside them. The misses are of two kinds. On
//!   the model's equilibrium branch, strongly loaded and close to the stability boundary, they
//!   are capped ([`BRANCH_MISS_CAP`]; worst measured torque 1.0 %, force 3.6 %, shape 10.4 mm).
//!   Very near the boundary the N = 100 rod can have no stable equilibrium near the model's:
//!   Newton fails or lands on another equilibrium of the same clamps, 44 mm or more away (15
//!   and 13 of 600; at most 5 % allowed). The normalised `σ_min` of `J(L)` does not predict
//!   these cases (the survey prints it). No sample is excluded; the misses are printed.
//! - [`the_gap_is_second_order_discretisation_error`]: over strongly bent configurations
//!   (`[−10, 10]⁶`), doubling N divides the wrench and shape gaps by about 4.
//!
//! - The loaded model, gravity on and rest strains, the simulator's base clamp at
//!   the identity so that its world gravity is in the base clamp frame:
//!   [`loaded_bounds_at_moderate_loads`] (every sample of the loaded model's
//!   `A_stable ∩ [−5, 5]⁶`, 20 random gravity directions × 10, both wires, with and without
//!   random rest strains up to 1.5 1/m: worst measured torque 0.054 %, force 0.73 %, shape
//!   0.15 mm); [`rest_strain_convention_matches_the_simulator`] (the simulator's
//!   `rest_strain` is the model's `u₀` on every axis; flipping one axis's sign misses by 66 %
//!   or more of `|a|`); [`the_loaded_gap_is_second_order_discretisation_error`] (with the
//!   simulated wire made axially stiff: at its default `EA` a few gravity-loaded samples level
//!   off at about 2e-4 of `|a|`, the stretching the inextensible model lacks); and the survey
//!   [`loaded_stability_near_the_boundary`] (ignored), the stability verdicts against the
//!   simulator's Hessian with gravity on: they agree down to 0.5 % from the model's boundary.
//!
//! Worst cases are printed:
//! `cargo test --release -p ftwire --test model_vs_sim -- --nocapture`; the survey by
//! half-width (ignored, seconds; `FTWIRE_SEEDS`, `FTWIRE_HALF_WIDTHS`, `FTWIRE_COUNT`):
//! `FTWIRE_SEEDS=10,11 FTWIRE_HALF_WIDTHS=5 cargo test --release -p ftwire --test model_vs_sim
//! -- --ignored survey --nocapture`.

mod common;

use common::{samples, setup, wires};
use ftwire_core::{Pose, WireParams};
use ftwire_lab::initial_guess::kirchhoff_guess;
use ftwire_rod::Load;
use ftwire_rod::sampling::Sampler;
use ftwire_sim::{RodParams, World};
use nalgebra::{Vector3, Vector6};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The gaps between simulator and model for one configuration.
#[derive(Debug, Clone, Copy, Default)]
struct Gap {
    /// |τ_sim − τ| / |a|, normalised units.
    torque: f64,
    /// |f_sim − f| / |a|, normalised units.
    force: f64,
    /// Largest distance between the simulated wire (clamp point to clamp point) and the model
    /// \[mm\].
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

    // The physical wire: the base clamp point (arc length 0), the interior nodes at (k − ½)h,
    // the tip clamp point (L = (N − 1)h); the model is sampled at every multiple of h/2.
    let rod = world.rod();
    let shape = model
        .shape(a, 2 * (rod.edges() - 1) + 1)
        .expect("a is in A");
    let points = eq.wire_centreline();
    let last = points.len() - 1;
    let shape_mm = points
        .iter()
        .enumerate()
        .map(|(k, point)| {
            let index = match k {
                0 => 0,
                k if k == last => 2 * (rod.edges() - 1),
                k => 2 * k - 1,
            };
            (point.coords - shape.positions[index]).norm() * 1e3
        })
        .fold(0.0, f64::max);
    Gap {
        torque,
        force,
        shape_mm,
    }
}

/// The pass conditions.
fn within_bounds(g: &Gap) -> bool {
    g.torque < 0.01 && g.force < 0.01 && g.shape_mm < 0.5
}

/// Seeds of [`bounds_at_moderate_loads`]: 20 × 20 samples per wire.
const MODERATE_SEEDS: [u64; 20] = [
    2026, 7, 1, 2, 3, 4, 5, 6, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19,
];

/// Seeds of [`bounds_over_the_default_range`]: 30 × 20 samples per wire (fewer make the rate a
/// property of the seeds: 10 of these seeds alone give 89.5 % on the 2 mm wire).
const DEFAULT_RANGE_SEEDS: [u64; 30] = [
    2026, 7, 1, 2, 3, 4, 5, 6, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24,
    25, 26, 27, 28, 29,
];

#[test]
fn bounds_at_moderate_loads() {
    for (name, preset) in wires() {
        let (model, world) = setup(preset, 100);
        let mut worst = Gap::default();
        let mut count = 0;
        for seed in MODERATE_SEEDS {
            for a in samples(&model, 5.0, 20, seed) {
                let g = gap(&model, &world, &a);
                assert!(within_bounds(&g), "{name}, seed {seed}, a = {a:?}: {g:?}");
                worst = worst.max(g);
                count += 1;
            }
        }
        eprintln!("{name}: worst of {count} samples of A_stable ∩ [−5, 5]⁶, N = 100: {worst:?}");
    }
}

/// Largest miss allowed on the model's own equilibrium branch over `[−30, 30]⁶`: torque 2 %,
/// force 6 % of `|a|`, shape 20 mm. Measured over [`DEFAULT_RANGE_SEEDS`], both wires (600
/// samples each): the worst misses on the branch are 1.0 %, 3.6 % and 10.4 mm.
const BRANCH_MISS_CAP: Gap = Gap {
    torque: 0.02,
    force: 0.06,
    shape_mm: 20.0,
};

/// A simulated wire farther than this from the model \[mm\] sits on another equilibrium for the
/// same clamps. Measured: 43.6 mm and more (with force gaps of 34 % and more); misses on the
/// model's branch stay under 10.4 mm, and a gap between the cap and this is a failure.
const OTHER_BRANCH_MM: f64 = 30.0;

#[test]
fn bounds_over_the_default_range() {
    let half_width = Sampler::default().half_width;
    let cap = |g: &Gap| {
        g.torque < BRANCH_MISS_CAP.torque
            && g.force < BRANCH_MISS_CAP.force
            && g.shape_mm < BRANCH_MISS_CAP.shape_mm
    };
    for (name, preset) in wires() {
        let (model, world) = setup(preset, 100);
        let mut gaps = Vec::new();
        let (mut misses, mut elsewhere, mut total) = (Vec::new(), 0, 0);
        for seed in DEFAULT_RANGE_SEEDS {
            for a in samples(&model, half_width, 20, seed) {
                total += 1;
                let an = ftwire_rod::to_normalised(model.wire(), &a);
                match try_gap(&model, &world, &a) {
                    Ok(g) if within_bounds(&g) => gaps.push(g),
                    Ok(g) => {
                        if g.shape_mm > OTHER_BRANCH_MM {
                            elsewhere += 1;
                        } else {
                            // A miss on the model's branch must stay under the cap.
                            assert!(cap(&g), "{name}, seed {seed}: {g:?} at a_n = {an:.2?}");
                        }
                        misses.push(format!("{g:?} at a_n = {:.2?}", an.as_slice()));
                        gaps.push(g);
                    }
                    Err(e) => {
                        elsewhere += 1;
                        misses.push(format!("{e} at a_n = {:.2?}", an.as_slice()));
                    }
                }
            }
        }
        let median = |f: fn(&Gap) -> f64| quantiles(gaps.iter().map(f).collect())[0];
        let (torque, force, shape) = (
            median(|g| g.torque),
            median(|g| g.force),
            median(|g| g.shape_mm),
        );
        eprintln!(
            "{name}: [−{half_width}, {half_width}]⁶, N = 100: {} of {total} within the bounds, \
             {elsewhere} on another equilibrium or failed; medians torque {torque:.1e}, \
             force {force:.1e}, shape {shape:.3} mm",
            total - misses.len()
        );
        for m in &misses {
            eprintln!("  outside: {m}");
        }
        assert!(
            misses.len() * 10 <= total,
            "{name}: {} of {total} samples outside the bounds",
            misses.len()
        );
        assert!(
            elsewhere * 20 <= total,
            "{name}: {elsewhere} of {total} samples on another equilibrium or failed"
        );
        assert!(
            torque < 1e-3 && force < 1e-3 && shape < 0.15,
            "{name}: medians {torque:.1e}, {force:.1e}, {shape:.3} mm"
        );
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

// ---------------------------------------------------------------------------------------------
// The loaded model: gravity on and rest curvature.

/// Model and simulator for one wire at `edges` edges, with gravity `gravity` \[m/s²\] and rest
/// strains `rest` \[1/m\]. The simulator's gravity is in its world frame; the base clamp sits
/// at the identity there ([`gap`] solves with `base = I`), so it is also the base clamp frame,
/// the model's frame for the weight. The model's weight per length is the simulator's
/// `density · π · radius² · gravity`, and its rest strains are the simulator's `rest_strain`
/// (both `u₀` of DESIGN.md: energy `½ Σ c_i (u_i − u₀_i)²`).
fn setup_loaded(
    preset: RodParams,
    edges: usize,
    gravity: Vector3<f64>,
    rest: Vector3<f64>,
) -> (ftwire_rod::Rod, World) {
    let params = RodParams {
        edges,
        gravity,
        rest_strain: rest,
        ..preset
    };
    let wire = WireParams::new(params.stiffness, params.length, params.radius).expect("preset");
    let load = Load::from_gravity(params.density, params.radius, gravity)
        .and_then(|l| l.with_natural_curvature(rest))
        .expect("finite load");
    let world = World::new(params).expect("preset is valid");
    (ftwire_rod::Rod::new(wire).with_load(load), world)
}

/// A uniformly random direction, seeded.
fn random_direction(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    loop {
        let v = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        if (0.1..=1.0).contains(&v.norm()) {
            return v.normalize();
        }
    }
}

/// Gravity directions × samples per direction of [`loaded_bounds_at_moderate_loads`].
const LOADED_DIRECTIONS: u64 = 20;
/// Samples of `A_stable ∩ [−5, 5]⁶` per gravity direction.
const LOADED_SAMPLES: usize = 10;

/// The worst gap over [`LOADED_DIRECTIONS`] random gravity directions (9.81 m/s²) and
/// [`LOADED_SAMPLES`] samples of the loaded model's `A_stable ∩ [−5, 5]⁶` each, with rest
/// strains from `rest(rng)`; every sample must meet the bounds.
fn loaded_worst(
    name: &str,
    preset: RodParams,
    seed: u64,
    rest: impl Fn(&mut ChaCha8Rng) -> Vector3<f64>,
) -> Gap {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut worst = Gap::default();
    for direction in 0..LOADED_DIRECTIONS {
        let gravity = random_direction(&mut rng) * 9.81;
        let rest = rest(&mut rng);
        let (model, world) = setup_loaded(preset, 100, gravity, rest);
        for a in samples(&model, 5.0, LOADED_SAMPLES, seed * 100 + direction) {
            let g = gap(&model, &world, &a);
            assert!(
                within_bounds(&g),
                "{name}, g = {gravity:?}, rest strain {rest:?}, a = {a:?}: {g:?}"
            );
            worst = worst.max(g);
        }
    }
    worst
}

/// With gravity on in random directions of the base clamp frame (the wires' real weight), and
/// with gravity and a rest curvature/twist, every sample of the loaded model's
/// `A_stable ∩ [−5, 5]⁶` meets the bounds against the simulator at N = 100 (base wrench
/// within 1 % of `|a|`, shape within 0.5 mm). The rest strains are random up to 1.5 1/m on
/// each axis (twist and both bendings), which pins the sign convention of every axis: the
/// energy is even in `u − u₀`, so only a rest strain can tell a flipped axis.
#[test]
fn loaded_bounds_at_moderate_loads() {
    for (name, preset) in wires() {
        let gravity_only = loaded_worst(name, preset, 16, |_| Vector3::zeros());
        let with_rest = loaded_worst(name, preset, 17, |rng| {
            Vector3::from_fn(|_, _| rng.random_range(-1.5..=1.5))
        });
        eprintln!(
            "{name}, N = 100, A_stable ∩ [−5, 5]⁶ of the loaded model, {} samples each: \
             gravity on: worst {gravity_only:?}; gravity and rest strain: worst {with_rest:?}",
            LOADED_DIRECTIONS as usize * LOADED_SAMPLES
        );
    }
}

/// Under load, the gap is the simulator's `O(h²)` discretisation error, not a modelling
/// mismatch: doubling N divides it by about 4 (gravity in random directions, random rest
/// strains up to 1.5 1/m, `A_stable ∩ [−10, 10]⁶`).
///
/// The simulated wire is made 100 times stiffer axially here. At its default `EA` a few
/// samples with gravity on level off, as N grows, at about 2e-4 of `|a|` in force (e.g.
/// 5.5e-4, 2.8e-4, 2.1e-4, 2.0e-4 at N = 100, 200, 400, 800): the simulator's stretching,
/// which the inextensible model does not have. With `EA × 100` the same sample converges as
/// `h²` (3.7e-4, 9.4e-5, 2.5e-5, 7.5e-6); see [`loaded_gap_by_n`] (`FTWIRE_EA`).
#[test]
fn the_loaded_gap_is_second_order_discretisation_error() {
    let mut rng = ChaCha8Rng::seed_from_u64(61);
    let stiff = |(model, world): (ftwire_rod::Rod, World)| {
        let params = RodParams {
            axial_stiffness: Some(world.rod().axial_stiffness() * 100.0),
            ..*world.rod().params()
        };
        (model, World::new(params).expect("valid"))
    };
    for (name, preset) in wires() {
        let mut worst_100 = Gap::default();
        for direction in 0..4 {
            let gravity = random_direction(&mut rng) * 9.81;
            let rest = Vector3::from_fn(|_, _| rng.random_range(-1.5..=1.5));
            let (model, world_100) = stiff(setup_loaded(preset, 100, gravity, rest));
            let (_, world_200) = stiff(setup_loaded(preset, 200, gravity, rest));
            for a in samples(&model, 10.0, 4, 70 + direction) {
                let coarse = gap(&model, &world_100, &a);
                let fine = gap(&model, &world_200, &a);
                worst_100 = worst_100.max(coarse);
                for (what, c, f) in [
                    ("torque", coarse.torque, fine.torque),
                    ("force", coarse.force, fine.force),
                    ("shape", coarse.shape_mm, fine.shape_mm),
                ] {
                    if c > 1e-4 {
                        let ratio = c / f;
                        assert!(
                            (2.4..6.0).contains(&ratio),
                            "{name}, g = {gravity:?}, u₀ = {rest:?}, a = {a:?}: {what} gap \
                             {c:.3e} at N = 100, {f:.3e} at N = 200"
                        );
                    }
                }
            }
        }
        eprintln!("{name}, loaded: worst over A_stable ∩ [−10, 10]⁶, N = 100: {worst_100:?}");
    }
}

/// Survey: the loaded gaps at N = 100, 200, 400 (`FTWIRE_NS`) for a few samples, gravity in
/// random directions and random rest strains, optionally without gravity or rest strain
/// (`FTWIRE_NO_GRAVITY`, `FTWIRE_NO_REST`), axial stiffness × `FTWIRE_EA` (1):
/// `cargo test --release -p ftwire --test model_vs_sim -- --ignored loaded_gap_by_n --nocapture`.
#[test]
#[ignore = "survey, seconds; run by hand"]
fn loaded_gap_by_n() {
    let mut rng = ChaCha8Rng::seed_from_u64(61);
    let g_on = std::env::var("FTWIRE_NO_GRAVITY").is_err();
    let rest_on = std::env::var("FTWIRE_NO_REST").is_err();
    let ea = env_f64("FTWIRE_EA", 1.0);
    for (name, preset) in wires() {
        for direction in 0..4 {
            let gravity = random_direction(&mut rng) * if g_on { 9.81 } else { 0.0 };
            let rest = Vector3::from_fn(|_, _| rng.random_range(-1.5..=1.5))
                * if rest_on { 1.0 } else { 0.0 };
            let worlds: Vec<_> = env_list("FTWIRE_NS", &[100.0, 200.0, 400.0])
                .iter()
                .map(|&n| {
                    let (model, world) = setup_loaded(preset, n as usize, gravity, rest);
                    let params = RodParams {
                        axial_stiffness: Some(world.rod().axial_stiffness() * ea),
                        ..*world.rod().params()
                    };
                    (model, World::new(params).expect("valid"))
                })
                .collect();
            for a in samples(&worlds[0].0, 10.0, 4, 70 + direction) {
                let gaps: Vec<String> = worlds
                    .iter()
                    .map(|(m, w)| {
                        let g = gap(m, w, &a);
                        format!("{:.2e}/{:.2e}/{:.3}", g.torque, g.force, g.shape_mm)
                    })
                    .collect();
                println!(
                    "{name} dir {direction}: N = {:?}: {}",
                    env_list("FTWIRE_NS", &[100.0, 200.0, 400.0]),
                    gaps.join("  ")
                );
            }
        }
    }
}

/// Survey: the loaded model's stability verdict (`det J` keeps its sign) against the
/// simulator's (Newton from the model's shape at the model's tip; `stable_minimum`, the sign of
/// the Hessian) near the stability boundary, gravity on in random directions. Along random rays
/// `s·d` in normalised units the model's boundary `s*` is found by bisection; the two verdicts
/// are compared at `s*·(1 ± ε)`. Measured (40 rays per wire, N = 100): no disagreement at
/// `ε ≥ 0.5 %` on either wire; at 0.2 % one of 80 on the 2 mm wire; at 0.1 % 4 of 80 and
/// 4 of 78; at 0.05 % 9 of 80 and 5 of 78 (mostly the model stable and the N = 100 rod not: the
/// discretisation moves the boundary slightly). Where the model is unstable, the simulator often
/// (10–30 %) descends from the model's saddle to another, stable equilibrium of the same
/// clamps (its wrench more than 5 % of `|a|` away); those are counted apart, not as
/// disagreements. `FTWIRE_COUNT` rays per wire (20), `FTWIRE_N` edges (100):
/// `cargo test --release -p ftwire --test model_vs_sim -- --ignored loaded_stability --nocapture`.
#[test]
#[ignore = "survey, seconds; run by hand"]
fn loaded_stability_near_the_boundary() {
    let rays = env_f64("FTWIRE_COUNT", 20.0) as usize;
    let edges = env_f64("FTWIRE_N", 100.0) as usize;
    let margins = [0.1, 0.02, 0.005, 0.002, 0.001, 0.0005];
    let mut rng = ChaCha8Rng::seed_from_u64(81);
    for (name, preset) in wires() {
        // Per margin: model stable & simulator not; model unstable & simulator stable at the
        // model's equilibrium; compared; model unstable & simulator on another, stable one.
        let mut tally = vec![(0, 0, 0, 0); margins.len()];
        let mut skipped = 0;
        for _ in 0..rays {
            let gravity = random_direction(&mut rng) * 9.81;
            let (model, world) = setup_loaded(preset, edges, gravity, Vector3::zeros());
            let wire = *model.wire();
            let d = Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0)).normalize();
            let stable = |s: f64| {
                model
                    .is_stable(&ftwire_rod::from_normalised(&wire, &(d * s)))
                    .unwrap_or(false)
            };
            // First unstable scale on a coarse scan, then bisection.
            let Some(hi) = (1..=60).map(|k| 0.5 * f64::from(k)).find(|&s| !stable(s)) else {
                skipped += 1;
                continue;
            };
            let (mut lo, mut hi) = (hi - 0.5, hi);
            if !stable(lo) {
                skipped += 1;
                continue;
            }
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                if stable(mid) { lo = mid } else { hi = mid }
            }
            let boundary = 0.5 * (lo + hi);
            for (k, eps) in margins.iter().enumerate() {
                for side in [-1.0, 1.0] {
                    let a =
                        ftwire_rod::from_normalised(&wire, &(d * boundary * (1.0 + side * eps)));
                    let model_stable = stable(boundary * (1.0 + side * eps));
                    let Ok(b) = model.tip(&a) else { continue };
                    let Ok(guess) = kirchhoff_guess(&model, &a, world.rod()) else {
                        continue;
                    };
                    // The simulator's verdict, and whether its equilibrium is the model's (base
                    // wrench within 5 % of |a|): from a saddle, Newton's line search can descend
                    // to another equilibrium of the same clamps.
                    let (sim_stable, same) =
                        match world.solve_with_guess(&guess, &Pose::identity(), &b) {
                            Ok(eq) => {
                                let scale = Vector6::new(
                                    wire.torque_scale(),
                                    wire.torque_scale(),
                                    wire.torque_scale(),
                                    wire.force_scale(),
                                    wire.force_scale(),
                                    wire.force_scale(),
                                );
                                let sim = eq.base_wrench.to_vector().component_div(&scale);
                                let an = a.component_div(&scale);
                                (eq.stable_minimum, (sim - an).norm() < 0.05 * an.norm())
                            }
                            Err(_) => (false, false),
                        };
                    tally[k].2 += 1;
                    match (model_stable, sim_stable, same) {
                        (true, false, _) => tally[k].0 += 1,
                        (false, true, true) => tally[k].1 += 1,
                        (false, true, false) => tally[k].3 += 1,
                        _ => {}
                    }
                }
            }
        }
        for (eps, (ms, mu, n, elsewhere)) in margins.iter().zip(&tally) {
            println!(
                "{name}, N = {edges}, gravity on: at s*(1 ± {eps}): {n} compared; model stable \
                 & simulator not: {ms}; model unstable & simulator stable there: {mu}; model \
                 unstable & simulator on another, stable equilibrium: {elsewhere}"
            );
        }
        println!("{name}: {skipped} rays without a boundary in (0, 30]");
    }
}

/// The rest-strain convention is pinned axis by axis: with a rest strain of 1.5 1/m on one axis
/// (twist, bending about y, bending about z) and no gravity, the model with the simulator's
/// `rest_strain` as its `u₀` meets the bounds, and the model with that axis's sign flipped
/// misses them by far (the cross-check can see a wrong convention).
#[test]
fn rest_strain_convention_matches_the_simulator() {
    let (name, preset) = wires()[0];
    let mut worst_flipped = f64::INFINITY;
    for axis in 0..3 {
        let rest = Vector3::from_fn(|i, _| if i == axis { 1.5 } else { 0.0 });
        let (model, world) = setup_loaded(preset, 100, Vector3::zeros(), rest);
        let flipped = model.with_load(Load::none().with_natural_curvature(-rest).expect("finite"));
        for a in samples(&model, 5.0, 5, 40 + axis as u64) {
            let g = gap(&model, &world, &a);
            assert!(within_bounds(&g), "{name}, u₀ = {rest:?}, a = {a:?}: {g:?}");
            // The same check against the model with this axis flipped: the simulator, clamped
            // at that model's tip and started from its shape, does not reproduce its wrench.
            let f = try_gap(&flipped, &world, &a);
            assert!(
                f.as_ref().map_or(true, |f| !within_bounds(f)),
                "axis {axis}: the flipped model agrees too: {f:?}"
            );
            if let Ok(f) = f {
                worst_flipped = worst_flipped.min(f.torque.max(f.force));
            }
        }
    }
    eprintln!("{name}: smallest wrench gap with one rest-strain axis flipped: {worst_flipped:.3}");
}

// ---------------------------------------------------------------------------------------------
// Survey (diagnostic, ignored).

/// Conditioning of `J(L)` in normalised units: rows `(δω, δv/L)`, columns `δa` normalised.
/// Returns `(σ_min, σ_max)`.
fn normalised_singular_values(model: &ftwire_rod::Rod, a: &Vector6<f64>) -> (f64, f64, f64) {
    let wire = model.wire();
    let sol = model.jacobian(a).expect("a is in A");
    let l = wire.length();
    let (ts, fs) = (wire.torque_scale(), wire.force_scale());
    let mut j = sol.jacobian;
    for r in 3..6 {
        for c in 0..6 {
            j[(r, c)] /= l;
        }
    }
    for c in 0..6 {
        let s = if c < 3 { ts } else { fs };
        for r in 0..6 {
            j[(r, c)] *= s;
        }
    }
    let sv = j.singular_values();
    let (lo, hi) = sv.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), &v| {
        (lo.min(v), hi.max(v))
    });
    (lo, hi, sol.stability.det_j_min)
}

fn env_f64(name: &str, default: f64) -> f64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// A comma-separated list of numbers from the environment, or `default`.
fn env_list(name: &str, default: &[f64]) -> Vec<f64> {
    std::env::var(name)
        .ok()
        .and_then(|v| v.split(',').map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| default.to_vec())
}

fn try_gap(model: &ftwire_rod::Rod, world: &World, a: &Vector6<f64>) -> Result<Gap, String> {
    let b = model.tip(a).map_err(|e| e.to_string())?;
    let guess = kirchhoff_guess(model, a, world.rod()).map_err(|e| e.to_string())?;
    let eq = world
        .solve_with_guess(&guess, &Pose::identity(), &b)
        .map_err(|e| e.to_string())?;
    if !eq.stable_minimum {
        return Err("saddle".into());
    }
    Ok(gap(model, world, a))
}

fn quantiles(mut v: Vec<f64>) -> [f64; 3] {
    if v.is_empty() {
        return [f64::NAN; 3];
    }
    v.sort_by(f64::total_cmp);
    let q = |p: f64| v[((v.len() - 1) as f64 * p).round() as usize];
    [q(0.5), q(0.9), q(1.0)]
}

/// Survey of the gaps at N = 100 (`FTWIRE_N`), `FTWIRE_COUNT` (40) samples per seed and
/// half-width, half-widths `FTWIRE_HALF_WIDTHS` (3,5,10,30), seeds `FTWIRE_SEEDS` (1), axial
/// stiffness × `FTWIRE_EA` (1):
/// `cargo test --release -p ftwire --test model_vs_sim -- --ignored survey --nocapture`.
#[test]
#[ignore = "survey, seconds; run by hand"]
fn survey() {
    let edges = env_f64("FTWIRE_N", 100.0) as usize;
    let count = env_f64("FTWIRE_COUNT", 40.0) as usize;
    let seeds = env_list("FTWIRE_SEEDS", &[1.0]);
    let half_widths = env_list("FTWIRE_HALF_WIDTHS", &[3.0, 5.0, 10.0, 30.0]);
    let ea = env_f64("FTWIRE_EA", 1.0);
    for (name, preset) in wires() {
        let (model, world) = setup(preset, edges);
        let params = RodParams {
            axial_stiffness: Some(world.rod().axial_stiffness() * ea),
            ..*world.rod().params()
        };
        let world = World::new(params).expect("valid");
        for &hw in &half_widths {
            let mut rows = Vec::new();
            let mut failures = 0;
            let all = seeds
                .iter()
                .flat_map(|&seed| samples(&model, hw, count, seed as u64));
            for a in all {
                let an = ftwire_rod::to_normalised(model.wire(), &a);
                let (smin, smax, det_min) = normalised_singular_values(&model, &a);
                match try_gap(&model, &world, &a) {
                    Ok(g) => rows.push((g, an, smin, smax, det_min)),
                    Err(e) => {
                        failures += 1;
                        eprintln!("  failure at a_n = {:?}: {e}", an.as_slice());
                    }
                }
            }
            let tq = quantiles(rows.iter().map(|r| r.0.torque).collect());
            let fq = quantiles(rows.iter().map(|r| r.0.force).collect());
            let sq = quantiles(rows.iter().map(|r| r.0.shape_mm).collect());
            println!(
                "{name}, N = {edges}, half-width {hw}: {} ok, {failures} failed; \
                 torque med/p90/max {:.2e} {:.2e} {:.2e}; force {:.2e} {:.2e} {:.2e}; \
                 shape mm {:.3} {:.3} {:.3}",
                rows.len(),
                tq[0],
                tq[1],
                tq[2],
                fq[0],
                fq[1],
                fq[2],
                sq[0],
                sq[1],
                sq[2]
            );
            rows.sort_by(|x, y| {
                let kx = x.0.torque.max(x.0.force).max(x.0.shape_mm / 50.0);
                let ky = y.0.torque.max(y.0.force).max(y.0.shape_mm / 50.0);
                ky.total_cmp(&kx)
            });
            for (g, an, smin, smax, det_min) in rows.iter().take(4) {
                println!(
                    "    torque {:.2e} force {:.2e} shape {:.3} mm | |a_n| {:.1} σmin {:.2e} \
                     σmax {:.2e} detmin {:.1e} | a_n [{}]",
                    g.torque,
                    g.force,
                    g.shape_mm,
                    an.norm(),
                    smin,
                    smax,
                    det_min,
                    an.iter()
                        .map(|v| format!("{v:.2}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                );
            }
        }
    }
}
