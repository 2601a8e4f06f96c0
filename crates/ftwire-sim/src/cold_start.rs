//! Cold start: a straight wire bent into place by continuation.
//!
//! With the clamps exactly `L` apart the straight, untwisted wire is the only admissible
//! shape, and its equilibrium is known (exact without gravity and natural curvature, a few
//! Newton iterations from straight otherwise). It is also a bifurcation point: moving the tip
//! straight inward compresses the wire past its Euler load at once, the buckled amplitude grows
//! as the square root of the shortening, and a continuation step started there has no regular
//! predictor and no preferred side. A straight-line path in pose space from the taut pose to a
//! bent target has exactly that defect at its start (shortening linear in the path parameter,
//! but the bending it forces only quadratic).
//!
//! The cold start therefore goes in two legs, both run by the quasi-static continuation
//! ([`crate::continuation`]):
//!
//! 1. **Bend.** The tip clamp follows the ends of planar circular arcs of turning angle
//!    `ψ ∈ [0, ψ₁]` and length `L` from the base clamp, in the plane spanned by the base tangent
//!    and a direction `n` chosen from the target (its position's component across the base
//!    tangent, else its tangent's, else the softer bending direction). Each arc is an exact
//!    equilibrium of the weightless, naturally straight rod (uniform curvature, no force), and
//!    along this path the tip turns linearly in `ψ` while it moves inward only as `ψ²·L/24`:
//!    the rotation forces the bending mode, so the path is regular from its first step and
//!    picks its side. Gravity and natural curvature only perturb it. `ψ₁` is the turning angle
//!    of the arc whose chord equals the target's clamp distance, capped at
//!    [`MAX_BEND`] rad; a taut target (chord `L`) has no bend leg.
//! 2. **Carry.** The tip clamp moves from the end of the arc to the target pose along the
//!    ordinary continuation path (translation interpolated linearly, rotation by slerp),
//!    following the branch and reporting snaps.
//!
//! **Coarse, then fine.** Both legs cost a few hundred Newton iterations, each linear in the
//! number of edges, so for `N > 2·`[`COARSE_EDGES`] they run on the same world discretised with
//! [`COARSE_EDGES`] edges; the coarse equilibrium, interpolated along its arc length (positions
//! linearly between nodes, material frames by slerp between edges), is then the initial guess
//! of a Newton solve at the full `N` ([`crate::World::solve_with_guess`]). The coarse and fine
//! rods differ by an `O(h²)` discretisation error, small against the basin of the equilibrium,
//! so the fine solve lands on the same branch. If that fine solve fails, or ends on a saddle,
//! the whole path is run again at full resolution.
//!
//! Everything is built in the base clamp frame, so the result is covariant under a rigid
//! motion of both clamps. If the continuation fails, or ends on a saddle,
//! [`crate::World::solve_cold`] falls back to Newton from a smooth length-exact guess
//! ([`crate::World::solve_smooth_guess`]) and says so in [`crate::Motion::cold_start`].

use ftwire_core::Pose;
use nalgebra::{Translation3, Unit, UnitQuaternion, Vector3};

use crate::continuation;
use crate::discrete_rod::DiscreteRod;
use crate::equilibrium::Equilibrium;
use crate::error::SimError;
use crate::guess;
use crate::motion::{ColdStart, Motion};
use crate::state::{InitialGuess, RodState};
use crate::transport::perpendicular;
use crate::world::World;

/// Largest turning angle \[rad\] of the bend leg.
pub const MAX_BEND: f64 = 1.0;

/// Edges of the coarse discretisation on which the cold start's path runs (module docs).
pub const COARSE_EDGES: usize = 25;

/// The clamp pose at the end of a planar arc of length `l`, turning angle `psi`, leaving the
/// base along its x axis and bending towards the unit vector `n` (base frame, ⟂ x).
pub(crate) fn arc_end(base: &Pose, l: f64, psi: f64, n: &Unit<Vector3<f64>>) -> Pose {
    // sin ψ/ψ and (1 − cos ψ)/ψ, with their series near 0.
    let (along, across) = if psi.abs() < 1e-4 {
        (1.0 - psi * psi / 6.0, psi / 2.0 - psi.powi(3) / 24.0)
    } else {
        (psi.sin() / psi, (1.0 - psi.cos()) / psi)
    };
    let p = Vector3::x() * (l * along) + n.as_ref() * (l * across);
    let axis = Unit::new_normalize(Vector3::x().cross(n));
    let local = Pose::from_parts(
        Translation3::from(p),
        UnitQuaternion::from_axis_angle(&axis, psi),
    );
    base * local
}

/// The turning angle of the arc of length `l` whose chord is `chord` (`0 ≤ chord ≤ l`): the
/// root of `2·sin(ψ/2)/ψ = chord/l` in `[0, 2π)`.
pub(crate) fn bend_for_chord(l: f64, chord: f64) -> f64 {
    let ratio = (chord / l).clamp(0.0, 1.0);
    let f = |psi: f64| {
        if psi < 1e-8 {
            1.0
        } else {
            2.0 * (0.5 * psi).sin() / psi
        }
    };
    let (mut lo, mut hi) = (0.0, 2.0 * std::f64::consts::PI);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        // f decreases from 1 at ψ = 0 to 0 at ψ = 2π.
        if f(mid) > ratio {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The bending direction `n` (base frame, unit, ⟂ x) of the bend leg for a target `local`
/// (tip pose in the base frame).
pub(crate) fn bend_direction(world: &World, local: &Pose) -> Unit<Vector3<f64>> {
    let x = Vector3::x();
    let across = |v: Vector3<f64>| v - x * x.dot(&v);
    let reach = local.translation.vector;
    let l = world.rod().params().length;
    let position = across(reach);
    if position.norm() > 1e-3 * l {
        return Unit::new_normalize(position);
    }
    let tangent = across(local.rotation * x);
    if tangent.norm() > 1e-3 {
        return Unit::new_normalize(tangent);
    }
    // Bulge along the softer bending direction: bending about y (c2) moves the wire along z.
    let c = world.rod().params().stiffness;
    let soft = if c[1] <= c[2] {
        Vector3::z()
    } else {
        Vector3::y()
    };
    Unit::new_normalize(perpendicular(&x, &soft))
}

/// Adds `leg` to `total` (steps, iterations, snaps with their progress mapped into
/// `[from, to]`), and takes its equilibrium.
fn append(total: &mut Motion, leg: Motion, from: f64, to: f64) {
    total.steps += leg.steps;
    total.iterations += leg.iterations;
    for mut snap in leg.snaps {
        snap.progress = from + (to - from) * snap.progress;
        total.snaps.push(snap);
    }
    total.equilibrium = leg.equilibrium;
}

/// One leg of the path: a continuation from `from` to the clamp poses, its last step solved to
/// `tolerance`.
fn leg(
    world: &World,
    from: &Equilibrium,
    base: &Pose,
    tip: &Pose,
    tolerance: f64,
) -> Result<Motion, SimError> {
    match continuation::run_to(world, from, base, tip, tolerance) {
        (motion, None) => Ok(motion),
        (_, Some(e)) => Err(e),
    }
}

/// Runs the continuation cold start (module docs); returns the motion and its bend angle.
pub(crate) fn bend_and_carry(
    world: &World,
    base: &Pose,
    tip: &Pose,
) -> Result<(Motion, f64), SimError> {
    let l = world.rod().params().length;
    let local = base.inverse() * tip;
    let chord = local.translation.vector.norm();
    let bend = bend_for_chord(l, chord).min(MAX_BEND);
    let n = bend_direction(world, &local);
    // The straight, untwisted wire with its tip clamp `L` along the base tangent.
    let straight = RodState::straight(world.rod(), base);
    let (b0, t0) = (straight.base, straight.tip);
    let start: Equilibrium = Equilibrium::newton_from(world, straight, &b0, &t0)?;
    let mut total = Motion {
        steps: 0,
        iterations: start.convergence.iterations,
        snaps: Vec::new(),
        equilibrium: start,
        cold_start: None,
    };
    // Bend leg: waypoints on the arc family, no farther apart than one continuation step.
    let settings = world.continuation_settings();
    let final_tolerance = world.newton_settings().tolerance;
    let path_tolerance = settings.path_tolerance.max(final_tolerance);
    let waypoints = (bend / settings.max_rotation).ceil() as usize;
    let legs = (waypoints + 1) as f64;
    for i in 1..=waypoints {
        let psi = bend * i as f64 / waypoints as f64;
        let to = arc_end(base, l, psi, &n);
        let leg = leg(world, &total.equilibrium, base, &to, path_tolerance)?;
        append(&mut total, leg, (i - 1) as f64 / legs, i as f64 / legs);
    }
    // Carry leg.
    let leg = leg(world, &total.equilibrium, base, tip, final_tolerance)?;
    append(&mut total, leg, waypoints as f64 / legs, 1.0);
    total.equilibrium.convergence.iterations = total.iterations;
    total.cold_start = Some(ColdStart::Continuation { bend });
    Ok((total, bend))
}

/// The cold start's path run on a coarse copy of `world` ([`COARSE_EDGES`] edges), then one
/// Newton solve at full resolution from the coarse equilibrium (module docs). Runs the path at
/// full resolution instead when `world` has at most `2·COARSE_EDGES` edges, or when the fine
/// solve fails or ends on a saddle.
pub(crate) fn coarse_then_fine(
    world: &World,
    base: &Pose,
    tip: &Pose,
) -> Result<(Motion, f64), SimError> {
    let n = world.rod().edges();
    if n <= 2 * COARSE_EDGES {
        return bend_and_carry(world, base, tip);
    }
    let coarse = world.with_edge_count(COARSE_EDGES)?;
    let (path, bend) = match bend_and_carry(&coarse, base, tip) {
        Ok(done) => done,
        Err(_) => return bend_and_carry(world, base, tip),
    };
    let guess = refine(&path.equilibrium, coarse.rod(), world.rod());
    match guess::solve(world, &guess, base, tip) {
        Ok(mut fine) if fine.stable_minimum => {
            let iterations = path.iterations + fine.convergence.iterations;
            fine.convergence.iterations = iterations;
            Ok((
                Motion {
                    steps: path.steps,
                    iterations,
                    snaps: path.snaps,
                    equilibrium: fine,
                    cold_start: Some(ColdStart::Continuation { bend }),
                },
                bend,
            ))
        }
        _ => bend_and_carry(world, base, tip),
    }
}

/// An initial guess for `fine` from an equilibrium of `coarse` (the same wire, fewer edges):
/// node positions interpolated linearly in arc length, material frames by slerp.
fn refine(eq: &Equilibrium, coarse: &DiscreteRod, fine: &DiscreteRod) -> InitialGuess {
    let points = eq.centreline();
    let frames: Vec<UnitQuaternion<f64>> = eq
        .state
        .material_frames()
        .iter()
        .map(UnitQuaternion::from_rotation_matrix)
        .collect();
    let h = coarse.edge_length();
    let (nodes, edges) = (points.len(), frames.len());
    InitialGuess::from_shape(fine, |s| {
        // Nodes sit at (k − ½)h, edges (frames) at j·h.
        let x = (s / h + 0.5).clamp(0.0, (nodes - 1) as f64);
        let k = (x.floor() as usize).min(nodes - 2);
        let p = points[k].coords.lerp(&points[k + 1].coords, x - k as f64);
        let y = (s / h).clamp(0.0, (edges - 1) as f64);
        let j = (y.floor() as usize).min(edges.saturating_sub(2));
        let r = if edges < 2 {
            frames[0]
        } else {
            frames[j]
                .try_slerp(&frames[j + 1], y - j as f64, 1e-12)
                .unwrap_or(frames[j])
        };
        Pose::from_parts(Translation3::from(p), r)
    })
}
