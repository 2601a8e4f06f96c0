//! Newton from the Kirchhoff guess on strongly bent configurations (half-width 30, N = 100).
//!
//! The simulator is started from the Kirchhoff shape of `a` (sampled in `A_stable`, gravity
//! off) with its clamps at the identity and at `b = Γ(a)`.
//!
//! Diagnosis of the reported failures (2 of 40 at seed 7 on the 2 mm wire): with the guess's
//! Hessian positive definite (no regularisation), Newton takes tiny, energy-decreasing steps
//! and the residual wanders between 0.1 and 10: there is no equilibrium near the guess. Both
//! configurations lie within 0.5 % and 5 % of the continuum's stability boundary along their
//! own ray (`s·a` is unstable for `s = 1.005` and `1.05`), and the discrete rod's fold sits
//! `O(h²)` away from the continuum's: along `s·a` the wrench gap grows from 0.07 % at
//! `s = 0.8` to 0.8 % at `s = 0.99` and the branch ends before `s = 1`; at N = 400 the first one
//! converges (gap 0.3 %). With 5000 iterations Newton reaches another, far equilibrium (gap
//! 70 %). No solver change can find an equilibrium that the N = 100 discretisation does not
//! have; these cases are reported as [`ftwire_sim::SimError::NewtonFailed`].
//!
//! What is asserted (seeds 7, 11, 12): configurations more than 5 % inside `A_stable` along
//! their ray converge to a stable minimum with the model's wrench to within 8 % of `|a|`, with
//! at most 5 % exceptions (seed 7: none allowed); configurations closer to the boundary may
//! fail or land elsewhere, at most a third of them. The ray is a crude distance to the
//! boundary. The survey (seeds 21, 22; 250 configurations per wire and seed; with the
//! turning-angle bending of `ftwire-sim`) measured, of 764 configurations "inside", 2 that
//! converge to a far equilibrium (gap 43 %; the same normalised configuration on both wires), all
//! others converged and stable; and of 236 near the boundary, 21 that fail (2) or converge far
//! (gap up to 206 %). Such a far equilibrium is the same at N = 100, 200 and 400 and is reached
//! with Newton steps limited to 0.2 % of `L` as well: it is a different equilibrium of the
//! discretised rod for the same clamps, next to an ill-conditioned model solution (the smallest
//! singular value of the seed-11 case's `J(L)` is 0.007 in SI units, its others 0.27–14.5), not a
//! solver divergence. A converged result far from the guess is not flagged by the solver yet.
//! Survey:
//! `cargo test --release -p ftwire --test sim_from_kirchhoff -- --ignored --nocapture`.

mod common;

use common::{samples, setup, wires};
use ftwire_core::Pose;
use ftwire_lab::initial_guess::kirchhoff_guess;
use ftwire_sim::{RodParams, World};
use nalgebra::Vector6;

/// One solve from the Kirchhoff guess.
#[derive(Debug, Clone)]
enum Outcome {
    /// Converged: stability and the wrench gap `|a_sim − a| / |a|` (normalised units).
    Solved {
        stable: bool,
        gap: f64,
        iterations: usize,
    },
    /// Newton failed.
    Failed(String),
}

fn solve(model: &ftwire_rod::Rod, world: &World, a: &Vector6<f64>) -> Outcome {
    let b = model.tip(a).expect("a is in A");
    let guess = kirchhoff_guess(model, a, world.rod()).expect("a is in A");
    match world.solve_with_guess(&guess, &Pose::identity(), &b) {
        Ok(eq) => {
            let wire = model.wire();
            let scale = Vector6::new(
                1.0 / wire.torque_scale(),
                1.0 / wire.torque_scale(),
                1.0 / wire.torque_scale(),
                1.0 / wire.force_scale(),
                1.0 / wire.force_scale(),
                1.0 / wire.force_scale(),
            );
            let sim = eq.base_wrench.to_vector().component_mul(&scale);
            let a_n = a.component_mul(&scale);
            Outcome::Solved {
                stable: eq.stable_minimum,
                gap: (sim - a_n).norm() / a_n.norm(),
                iterations: eq.convergence.iterations,
            }
        }
        Err(e) => Outcome::Failed(e.to_string()),
    }
}

#[derive(Debug, Default)]
struct Tally {
    total: usize,
    converged: usize,
    stable: usize,
    worst_gap: f64,
    iterations: usize,
    failures: Vec<String>,
}

fn tally(model: &ftwire_rod::Rod, world: &World, configs: &[Vector6<f64>]) -> Tally {
    let mut t = Tally::default();
    for a in configs {
        t.total += 1;
        match solve(model, world, a) {
            Outcome::Solved {
                stable,
                gap,
                iterations,
            } => {
                t.converged += 1;
                t.iterations += iterations;
                if stable {
                    t.stable += 1;
                } else {
                    t.failures.push(format!("saddle at a = {:?}", a.as_slice()));
                }
                if gap > t.worst_gap {
                    t.worst_gap = gap;
                }
                if gap > 0.08 {
                    t.failures
                        .push(format!("gap {gap:.3e} at a = {:?}", a.as_slice()));
                }
            }
            Outcome::Failed(e) => t.failures.push(format!("a = {:?}: {e}", a.as_slice())),
        }
    }
    t
}

/// How far `a` is from the continuum's stability boundary along its own ray: the smallest
/// tested `s > 1` with `s·a` unstable (`s = 1.01, 1.02, …`), or `None` beyond `2`.
fn boundary_ratio(model: &ftwire_rod::Rod, a: &Vector6<f64>) -> Option<f64> {
    let grid = [1.005, 1.01, 1.02, 1.03, 1.05, 1.1, 1.2, 1.5, 2.0];
    grid.into_iter()
        .find(|&s| !model.is_stable(&(a * s)).unwrap_or(false))
}

/// Solves every configuration and sorts the outcomes by their distance to the boundary.
#[derive(Debug, Default)]
struct Report {
    /// Configurations more than 5 % inside `A_stable` along their ray.
    inside: Tally,
    /// Configurations within 5 % of the boundary.
    near_boundary: Tally,
}

fn report(model: &ftwire_rod::Rod, world: &World, configs: &[Vector6<f64>]) -> Report {
    let mut r = Report::default();
    for a in configs {
        let near = boundary_ratio(model, a).is_some_and(|s| s <= 1.05);
        let bucket = if near {
            &mut r.near_boundary
        } else {
            &mut r.inside
        };
        let t = tally(model, world, std::slice::from_ref(a));
        bucket.total += t.total;
        bucket.converged += t.converged;
        bucket.stable += t.stable;
        bucket.iterations += t.iterations;
        bucket.worst_gap = bucket.worst_gap.max(t.worst_gap);
        bucket.failures.extend(t.failures);
    }
    r
}

/// The configurations of the report: seed 7, 40 samples, 2 mm wire; the two that fail are
/// within 5 % of the stability boundary.
#[test]
fn the_reported_configurations_fail_only_at_the_boundary() {
    let (model, world) = setup(RodParams::nitinol_2mm_630(), 100);
    let r = report(&model, &world, &samples(&model, 30.0, 40, 7));
    println!("seed 7, 40 configurations: {r:#?}");
    assert!(r.inside.failures.is_empty(), "{:#?}", r.inside.failures);
    // (Seed 7 is the reported case; its inside configurations must all pass.)
    assert_eq!(r.inside.total + r.near_boundary.total, 40);
    assert!(r.inside.total >= 25, "{r:?}");
}

#[test]
fn strongly_bent_configurations_converge_on_both_wires() {
    for (name, preset) in wires() {
        let (model, world) = setup(preset, 100);
        for seed in [11, 12] {
            let r = report(&model, &world, &samples(&model, 30.0, 50, seed));
            println!("{name}, seed {seed}: {r:#?}");
            // Inside: the survey measured about 1 % failing or far (see the module docs).
            assert!(
                r.inside.failures.len() * 20 <= r.inside.total,
                "{name}: more than 5 % of {} failed: {:#?}",
                r.inside.total,
                r.inside.failures
            );
            assert!(r.inside.total >= 30, "{name}: {r:?}");
            // Near the boundary: measured 0 of 8 (seed 11) and 1 of 5 / 1 of 4 (seed 12, a far
            // equilibrium with a gap of 169 %) fail.
            assert!(
                r.near_boundary.failures.len() * 3 <= r.near_boundary.total,
                "{name}: {:#?}",
                r.near_boundary.failures
            );
        }
    }
}

#[test]
#[ignore = "survey: 2 wires × 2 seeds × 250 configurations, about a minute in release"]
fn survey_from_kirchhoff() {
    for (name, preset) in wires() {
        let (model, world) = setup(preset, 100);
        for seed in [21, 22] {
            let start = std::time::Instant::now();
            let r = report(&model, &world, &samples(&model, 30.0, 250, seed));
            for (label, t) in [("inside", &r.inside), ("near boundary", &r.near_boundary)] {
                println!(
                    "{name}, seed {seed}, {label}: converged {}/{}, stable {}, failures {}, \
                     worst gap {:.3e}",
                    t.converged,
                    t.total,
                    t.stable,
                    t.failures.len(),
                    t.worst_gap,
                );
                for f in &t.failures {
                    println!("  {f}");
                }
            }
            println!("  {:.1} s", start.elapsed().as_secs_f64());
        }
    }
}
