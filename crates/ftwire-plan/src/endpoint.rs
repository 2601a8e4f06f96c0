//! Named configurations of a scene turned into configurations `z = (a, base)`, and checked.
//!
//! A configuration given as the second gripper's pose needs an `a` with `Γ(a) = b`, the pose
//! relative to the base gripper: that is the wire's inverse problem, with several solutions.
//! [`configuration_for_tip`] samples `A_free` (seeded), starts Newton's method
//! (`δa = J(L)⁻¹ log(Γ(a)⁻¹ b)`, damped) from the closest samples, and returns the first
//! stable, self-intersection-free solution.

use ftwire_core::Pose;
use ftwire_rod::sampling::Sampler;
use ftwire_rod::{DEFAULT_NODES, Rod, from_normalised, se3};
use nalgebra::Vector6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::validity::{Checker, Sample};
use crate::{ConfigurationSpec, PlanError, Scene, ZPoint};

/// Candidates drawn from `A_free` for the inverse problem.
const CANDIDATES: usize = 400;
/// Newton starts tried, closest candidates first.
const STARTS: usize = 8;
/// Newton iterations per start.
const NEWTON_ITERATIONS: usize = 40;
/// Converged when the SE(3) log of the tip error is below this (rad and m mixed, ~1e-9).
const TOLERANCE: f64 = 1e-9;

/// An `a` in `A_free` with `Γ(a) = relative` (the second clamp in the base clamp frame), found
/// from a seeded set of samples of `A_free ∩ [−10, 10]⁶` (normalised).
///
/// # Errors
/// [`PlanError::NoConfigurationForTip`] with the smallest residual reached.
pub fn configuration_for_tip(
    rod: &Rod,
    relative: &Pose,
    name: &str,
    seed: u64,
) -> Result<Vector6<f64>, PlanError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let sampler = Sampler::new(10.0)?;
    let length = rod.wire().length();
    let residual = |a: &Vector6<f64>| -> Option<Vector6<f64>> {
        let tip = rod.tip(a).ok()?;
        let mut r = se3::log(&(tip.inverse() * relative));
        // Positions in wire lengths, so that both parts weigh alike.
        for i in 3..6 {
            r[i] /= length;
        }
        Some(r)
    };
    let mut candidates: Vec<(f64, Vector6<f64>)> = (0..CANDIDATES)
        .filter_map(|_| sampler.sample_stable(rod, &mut rng).ok())
        .filter_map(|a| residual(&a).map(|r| (r.norm(), a)))
        .collect();
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut closest = f64::INFINITY;
    for &(_, start) in candidates.iter().take(STARTS) {
        let mut a = start;
        for _ in 0..NEWTON_ITERATIONS {
            let (Some(r), Ok(j)) = (residual(&a), rod.jacobian(&a)) else {
                break;
            };
            let norm = r.norm();
            closest = closest.min(norm);
            if norm < TOLERANCE {
                let free = rod.solve(&a, DEFAULT_NODES).is_ok_and(|s| s.is_free());
                if free {
                    return Ok(a);
                }
                break;
            }
            let mut jac = j.jacobian;
            for i in 3..6 {
                for k in 0..6 {
                    jac[(i, k)] /= length;
                }
            }
            let Some(step) = jac.lu().solve(&r) else {
                break;
            };
            // Damping: at most a quarter of the wire's normalised scale per step.
            let scale = from_normalised(rod.wire(), &Vector6::repeat(1.0));
            let limit = (0..6).map(|i| step[i].abs() / scale[i]).fold(0.0, f64::max);
            a += if limit > 2.0 {
                step * (2.0 / limit)
            } else {
                step
            };
        }
    }
    Err(PlanError::NoConfigurationForTip {
        name: name.to_string(),
        residual: closest,
    })
}

/// The configuration a scene names, with the scene's base pose.
///
/// # Errors
/// [`PlanError::UnknownConfiguration`], or as [`configuration_for_tip`].
pub fn scene_configuration(scene: &Scene, rod: &Rod, name: &str) -> Result<ZPoint, PlanError> {
    let a = match *scene.configuration(name)? {
        ConfigurationSpec::A(a) => a,
        ConfigurationSpec::Normalised(n) => from_normalised(rod.wire(), &n),
        ConfigurationSpec::Tip(tip) => {
            configuration_for_tip(rod, &(scene.base.inverse() * tip), name, 0)?
        }
    };
    Ok(ZPoint {
        a,
        base: scene.base,
    })
}

/// The named configuration as a checked endpoint: in `Z_free`, with its joints.
///
/// # Errors
/// [`PlanError::InvalidEndpoint`] naming the configuration and why it is not in `Z_free`;
/// else as [`scene_configuration`].
pub fn scene_endpoint(
    scene: &Scene,
    checker: &Checker,
    name: &str,
    role: &'static str,
) -> Result<Sample, PlanError> {
    let config = scene_configuration(scene, checker.rod(), name)?;
    checker
        .endpoint(&config)
        .map_err(|reason| PlanError::InvalidEndpoint {
            role,
            name: name.to_string(),
            reason: reason.to_string(),
        })
}
