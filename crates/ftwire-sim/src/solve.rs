//! The solves of a [`World`]: cold start, smooth guess, user guess, and moves by continuation.
//! The world itself is plain data (module `world`); these methods drive the solver modules
//! (`cold_start`, `guess`, `continuation`, `newton`).

use ftwire_core::Pose;

use crate::cold_start;
use crate::continuation;
use crate::equilibrium::Equilibrium;
use crate::error::SimError;
use crate::guess;
use crate::motion::{ColdStart, Motion};
use crate::state::{InitialGuess, RodState};
use crate::world::World;

impl World {
    /// Cold start: a straight wire bent into place by continuation.
    ///
    /// From the straight, untwisted wire (tip clamp `L` along the base tangent), the tip clamp
    /// first follows the ends of planar arcs bent towards the target (an exact path of
    /// equilibria of the weightless rod, regular from its first step, unlike a straight inward
    /// move, which starts on the taut wire's buckling bifurcation), then moves to `tip` by the
    /// ordinary continuation, which follows the branch and reports snaps (module
    /// `cold_start`). For more than 50 edges the path runs on a 25-edge copy of the world and
    /// its end starts one Newton solve at full resolution. The result reports the continuation
    /// steps, the total Newton iterations (also in [`crate::Convergence::iterations`]) and the
    /// route in [`Motion::cold_start`].
    ///
    /// If the continuation fails, or ends on a saddle, Newton from a smooth guess
    /// ([`World::solve_smooth_guess`]) is tried, and
    /// [`ColdStart::SmoothGuess`](crate::ColdStart::SmoothGuess) says so; if that fails too,
    /// the continuation's error is returned.
    ///
    /// # Errors
    /// [`SimError::Core`] (non-finite) for a non-finite pose, [`SimError::GrippersTooFarApart`],
    /// [`SimError::NewtonFailed`].
    pub fn solve_cold(&self, base: &Pose, tip: &Pose) -> Result<Motion, SimError> {
        self.check_poses(base, tip)?;
        let continuation_error = match cold_start::coarse_then_fine(self, base, tip) {
            Ok((motion, _)) if motion.equilibrium.stable_minimum => return Ok(motion),
            Ok((motion, _)) => {
                // A saddle: the smooth guess may find the minimum; otherwise keep the saddle.
                return Ok(match self.solve_smooth_guess(base, tip) {
                    Ok(mut smooth) if smooth.equilibrium.stable_minimum => {
                        smooth.cold_start = Some(ColdStart::SmoothGuess {
                            continuation_error: None,
                        });
                        smooth
                    }
                    _ => motion,
                });
            }
            Err(e) => e,
        };
        match self.solve_smooth_guess(base, tip) {
            Ok(mut smooth) => {
                smooth.cold_start = Some(ColdStart::SmoothGuess {
                    continuation_error: Some(continuation_error),
                });
                Ok(smooth)
            }
            Err(_) => Err(continuation_error),
        }
    }

    /// Newton's method from a smooth, length-exact guess between the clamps (a cubic Bézier
    /// curve with the clamp tangents, bulged to length `L`, its roll spread evenly), without
    /// continuation: the fallback of [`World::solve_cold`]. It is fast and usually lands on the
    /// least-bent branch, but which branch it lands on is not the end of a path of equilibria.
    /// The returned motion has no steps and [`Motion::cold_start`] `None`.
    ///
    /// # Errors
    /// [`SimError::Core`] (non-finite) for a non-finite pose, [`SimError::GrippersTooFarApart`],
    /// [`SimError::NewtonFailed`].
    pub fn solve_smooth_guess(&self, base: &Pose, tip: &Pose) -> Result<Motion, SimError> {
        self.check_poses(base, tip)?;
        let guess = RodState::hermite(self.rod(), base, tip);
        let equilibrium = Equilibrium::newton_from(self, guess, base, tip)?;
        let iterations = equilibrium.convergence.iterations;
        Ok(Motion {
            equilibrium,
            snaps: Vec::new(),
            steps: 0,
            iterations,
            cold_start: None,
        })
    }

    /// Solves from a user-given initial guess (e.g. the Kirchhoff model's shape), by Newton's
    /// method, so that the equilibrium found is the one near the guess. If the guess's end
    /// edges are not where the clamps are, it is first solved at the clamp poses it implies
    /// (midpoints of its end edges, end frames aligned with them) and then carried to `base`
    /// and `tip` by continuation.
    ///
    /// # Errors
    /// [`SimError::GuessSize`], [`SimError::DegenerateGuess`], [`SimError::Core`] (non-finite),
    /// [`SimError::GrippersTooFarApart`], [`SimError::NewtonFailed`].
    pub fn solve_with_guess(
        &self,
        guess: &InitialGuess,
        base: &Pose,
        tip: &Pose,
    ) -> Result<Equilibrium, SimError> {
        guess::solve(self, guess, base, tip)
    }

    /// Warm start: moves the grippers from the poses of `from` to `base` and `tip` by
    /// quasi-static continuation (see the crate guide, "Continuation").
    ///
    /// # Errors
    /// [`SimError::Core`] (non-finite), [`SimError::GrippersTooFarApart`], [`SimError::NewtonFailed`]
    /// (use [`crate::Simulator`] to keep the last good state on failure).
    pub fn move_grippers(
        &self,
        from: &Equilibrium,
        base: &Pose,
        tip: &Pose,
    ) -> Result<Motion, SimError> {
        let (motion, error) = continuation::run(self, from, base, tip);
        match error {
            None => Ok(motion),
            Some(e) => Err(e),
        }
    }
}
