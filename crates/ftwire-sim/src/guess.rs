//! Solving from a user-given initial guess (e.g. the Kirchhoff model's shape): Newton's method
//! near the guess, after a continuation from the clamp poses the guess implies when they differ
//! from the requested ones.

use ftwire_core::Pose;

use crate::continuation;
use crate::equilibrium::Equilibrium;
use crate::error::SimError;
use crate::state::{InitialGuess, RodState};
use crate::world::World;

/// Solves from `guess` with the clamps at `base` and `tip` (see [`World::solve_with_guess`]).
pub(crate) fn solve(
    world: &World,
    guess: &InitialGuess,
    base: &Pose,
    tip: &Pose,
) -> Result<Equilibrium, SimError> {
    world.check_poses(base, tip)?;
    let state = RodState::from_guess(world.rod(), guess, base, tip)?;
    // A guess that ends elsewhere than the clamps is first solved at the clamp poses it
    // implies, then carried to the requested ones by continuation.
    if let Some((b0, t0)) = implied_clamps(guess)
        && (!close(&b0, base, world.rod().edge_length())
            || !close(&t0, tip, world.rod().edge_length()))
        && world.check_poses(&b0, &t0).is_ok()
    {
        let own = RodState::from_guess(world.rod(), guess, &b0, &t0)?;
        let start = Equilibrium::newton_from(world, own, &b0, &t0)?;
        return match continuation::run(world, &start, base, tip) {
            (motion, None) => Ok(motion.equilibrium),
            (_, Some(e)) => Err(e),
        };
    }
    Equilibrium::newton_from(world, state, base, tip)
}

/// The clamp poses a guess implies: the midpoints of its end edges, with the end frames turned
/// so that their x axes follow those edges.
fn implied_clamps(guess: &InitialGuess) -> Option<(Pose, Pose)> {
    let (p, f) = (&guess.points, &guess.frames);
    let (n, m) = (p.len(), f.len());
    if n < 2 || m < 1 || n != m + 1 {
        return None;
    }
    let clamp = |a: usize, b: usize, frame: &nalgebra::UnitQuaternion<f64>| -> Option<Pose> {
        let e = p[b] - p[a];
        let t = e.try_normalize(1e-15)?;
        let turn =
            nalgebra::UnitQuaternion::rotation_between(&(frame * nalgebra::Vector3::x()), &t)?;
        Some(Pose::from_parts(
            nalgebra::Translation3::from(p[a].coords + e * 0.5),
            turn * frame,
        ))
    };
    Some((clamp(0, 1, &f[0])?, clamp(n - 2, n - 1, &f[m - 1])?))
}

/// Whether two clamp poses agree to 5 % of an edge and 0.05 rad: close enough for Newton to
/// absorb the difference when the clamps overwrite the guess's end edges.
fn close(a: &Pose, b: &Pose, edge: f64) -> bool {
    (a.translation.vector - b.translation.vector).norm() <= 0.05 * edge
        && a.rotation.angle_to(&b.rotation) <= 0.05
}
