//! Quasi-static continuation: moving the grippers along a path of equilibria.
//!
//! A motion from the current clamp poses to target poses is cut into steps (translations
//! interpolated linearly, rotations by slerp). Each step starts from a predictor — the previous
//! equilibrium carried along by a blend of the two grippers' rigid motions, weighted by arc
//! length, which is exact when both grippers move together — and is corrected by Newton's
//! method ([`crate::newton`]). A step whose Newton solve fails is halved, up to
//! [`ContinuationParams::max_subdivisions`] times. A step whose corrector moves some node by
//! more than [`ContinuationParams::snap_distance`] is halved as well; if the jump persists at
//! `1/16` of the nominal step, the branch has ended: the wire snaps to another branch, as a real
//! wire does, and the jump is reported as a [`SnapEvent`].

use ftwire_core::Pose;
use nalgebra::{Isometry3, Translation3};

use crate::equilibrium::Equilibrium;
use crate::error::SimError;
use crate::motion::{Motion, SnapEvent};
use crate::newton;
use crate::state::RodState;
use crate::world::World;

fn interpolate(a: &Pose, b: &Pose, s: f64) -> Pose {
    let t = a.translation.vector.lerp(&b.translation.vector, s);
    let r = a
        .rotation
        .try_slerp(&b.rotation, s, 1e-12)
        .unwrap_or(if s < 0.5 { a.rotation } else { b.rotation });
    Isometry3::from_parts(Translation3::from(t), r)
}

/// Carries `state` from its clamp poses to `base` and `tip`: a blend of the two grippers'
/// rigid motions (exact when they move together), then the linear response of the free degrees
/// of freedom to the remaining clamp displacement, then a projection onto the edge lengths.
pub(crate) fn predict(world: &World, from: &Equilibrium, base: &Pose, tip: &Pose) -> RodState {
    let state = &from.state;
    let rod = world.rod();
    let n = rod.edges();
    let mut next = state.clone();
    // Rigid part: the motion both grippers share (that of the base), applied to everything.
    let db = base * state.base.inverse();
    for x in next.nodes.iter_mut() {
        *x = (db * nalgebra::Point3::from(*x)).coords;
    }
    for j in 0..n {
        next.ref_tangent[j] = db.rotation * next.ref_tangent[j];
        next.ref_d1[j] = db.rotation * next.ref_d1[j];
    }
    next.base = *base;
    next.tip = db * state.tip;
    // Linear response to the tip's remaining motion: δu = −H_uu⁻¹ H_uf δf. The Hessian of the
    // previous equilibrium is reused when the base (hence everything) did not move.
    let unmoved = db.translation.vector.norm() == 0.0 && db.rotation.angle() == 0.0;
    let hessian = if unmoved {
        Some(from.hessian.clone())
    } else {
        crate::energy::evaluate(world, &next, crate::energy::Order::Hessian).hess
    };
    let mut target = next.clone();
    target.apply_clamps(rod, base, tip);
    if let Some(mut hess) = hessian {
        let fixed = newton::fixed_dofs(n);
        let mut delta = vec![0.0; crate::energy::dof_count(n)];
        for k in [n - 1, n] {
            for c in 0..3 {
                delta[crate::energy::x_dof(k, c)] = target.nodes[k][c] - next.nodes[k][c];
            }
        }
        let turn = tip.rotation * next.tip.rotation.inverse();
        delta[crate::energy::theta_dof(n - 1)] = turn
            .scaled_axis()
            .dot(&(next.tip.rotation * nalgebra::Vector3::x()));
        let r = hess.mul_vec(&delta);
        for &i in &fixed {
            hess.pin(i);
        }
        if let Some(chol) = hess.cholesky() {
            let mut rhs: Vec<f64> = r.iter().map(|v| -v).collect();
            for &i in &fixed {
                rhs[i] = 0.0;
            }
            let du = chol.solve(&rhs);
            if du.iter().all(|v| v.is_finite()) {
                for (k, x) in next.nodes.iter_mut().enumerate() {
                    for c in 0..3 {
                        x[c] += du[crate::energy::x_dof(k, c)];
                    }
                }
                for (j, th) in next.theta.iter_mut().enumerate() {
                    *th += du[crate::energy::theta_dof(j)];
                }
            }
        }
    }
    next.apply_clamps(rod, base, tip);
    next.rebase();
    next.project_lengths(rod.edge_length());
    next
}

/// The error of a motion that has spent more than its work limit after `iterations` Newton
/// iterations, if it has.
fn exhausted(
    settings: &crate::ContinuationParams,
    iterations: usize,
    world: &World,
) -> Option<SimError> {
    let edges = world.rod().edges();
    let limit = settings.work_limit?;
    (iterations.saturating_mul(edges) > limit).then_some(SimError::WorkExhausted {
        iterations,
        edges,
        limit,
    })
}

/// Runs a motion; returns the furthest equilibrium reached and the error that stopped it, if any.
pub(crate) fn run(
    world: &World,
    from: &Equilibrium,
    base: &Pose,
    tip: &Pose,
) -> (Motion, Option<SimError>) {
    run_to(world, from, base, tip, world.newton_settings().tolerance)
}

/// As [`run`], with the last step solved to the scaled residual `last_tolerance` (the path
/// tolerance for a motion that is itself one leg of a longer path).
pub(crate) fn run_to(
    world: &World,
    from: &Equilibrium,
    base: &Pose,
    tip: &Pose,
    last_tolerance: f64,
) -> (Motion, Option<SimError>) {
    let mut motion = Motion {
        equilibrium: from.clone(),
        snaps: Vec::new(),
        steps: 0,
        iterations: 0,
        cold_start: None,
    };
    if let Err(e) = world.check_poses(base, tip) {
        return (motion, Some(e));
    }
    let settings = *world.continuation_settings();
    let l = world.rod().params().length;
    let (b0, t0) = (from.state.base, from.state.tip);
    let trans = (base.translation.vector - b0.translation.vector)
        .norm()
        .max((tip.translation.vector - t0.translation.vector).norm());
    let rot = b0
        .rotation
        .angle_to(&base.rotation)
        .max(t0.rotation.angle_to(&tip.rotation));
    let steps = (trans / (settings.max_translation_fraction * l))
        .max(rot / settings.max_rotation)
        .ceil()
        .max(1.0);
    let nominal = 1.0 / steps;
    let smallest = nominal / f64::powi(2.0, settings.max_subdivisions as i32);
    let snap_confirm = nominal / 16.0;
    let snap_distance = settings.snap_distance_fraction * l;
    let contact_limit = world.contact_step_limit();
    let mut progress = 0.0;
    let mut step = nominal;
    let mut subdivisions = 0;
    while progress < 1.0 {
        if let Some(error) = exhausted(&settings, motion.iterations, world) {
            motion.equilibrium.convergence.iterations = motion.iterations;
            return (motion, Some(error));
        }
        let next = (progress + step).min(1.0);
        let (bp, tp) = (interpolate(&b0, base, next), interpolate(&t0, tip, next));
        let current = &motion.equilibrium;
        let guess = predict(world, current, &bp, &tp);
        let too_far = contact_limit.is_some_and(|lim| guess.max_distance(&current.state) > lim);
        let halve = |step: f64, subdivisions: &mut usize| {
            *subdivisions += 1;
            step * 0.5
        };
        if too_far && step > smallest {
            step = halve(step, &mut subdivisions);
            continue;
        }
        let tolerance = if next < 1.0 {
            settings
                .path_tolerance
                .max(world.newton_settings().tolerance)
        } else {
            last_tolerance
        };
        match newton::solve_to(world, guess.clone(), tolerance) {
            Ok(result) => {
                motion.iterations += result.iterations;
                let jump = result.state.max_distance(&guess);
                if jump > snap_distance && step > snap_confirm.max(smallest) {
                    step = halve(step, &mut subdivisions);
                    continue;
                }
                let eq = Equilibrium::from_newton(result);
                if jump > snap_distance {
                    motion.snaps.push(SnapEvent {
                        progress: next,
                        max_node_jump: jump,
                        energy_before: current.energy(),
                        energy_after: eq.energy(),
                        base_wrench_before: current.base_wrench,
                        base_wrench_after: eq.base_wrench,
                    });
                }
                motion.equilibrium = eq;
                motion.steps += 1;
                progress = next;
                step = (step * 2.0).min(nominal);
            }
            Err(failure) => {
                motion.iterations += failure.iterations;
                if step <= smallest {
                    let error = SimError::NewtonFailed {
                        iterations: failure.iterations,
                        residual: failure.residual,
                        subdivisions,
                    };
                    motion.equilibrium.convergence.iterations = motion.iterations;
                    return (motion, Some(error));
                }
                step = halve(step, &mut subdivisions);
            }
        }
    }
    motion.equilibrium.convergence.iterations = motion.iterations;
    (motion, None)
}
