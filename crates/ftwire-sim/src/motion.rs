//! The result of a gripper motion: the equilibrium reached, the snaps met on the way, and for a
//! cold start the route it took.

use ftwire_core::Wrench;

use crate::equilibrium::Equilibrium;
use crate::error::SimError;

/// The result of a gripper motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    /// The equilibrium at the target poses.
    pub equilibrium: Equilibrium,
    /// Snaps met on the way, in order.
    pub snaps: Vec<SnapEvent>,
    /// Continuation steps taken.
    pub steps: usize,
    /// Newton iterations summed over all steps (including rejected ones).
    pub iterations: usize,
    /// For a cold start ([`crate::World::solve_cold`]), the route it took; `None` for a move
    /// from a previous equilibrium.
    pub cold_start: Option<ColdStart>,
}

/// A sudden jump of the wire to another equilibrium branch.
#[derive(Debug, Clone, PartialEq)]
pub struct SnapEvent {
    /// Where along the motion the snap happened, from 0 (start) to 1 (target).
    pub progress: f64,
    /// Largest node jump \[m\] between the predicted and the new equilibrium.
    pub max_node_jump: f64,
    /// Total energy before \[J\].
    pub energy_before: f64,
    /// Total energy after \[J\].
    pub energy_after: f64,
    /// Base wrench before (base clamp frame).
    pub base_wrench_before: Wrench,
    /// Base wrench after (base clamp frame).
    pub base_wrench_after: Wrench,
}

/// How a cold start reached its equilibrium.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ColdStart {
    /// From the straight wire, bent by continuation along an arc and carried to the target
    /// (the default route).
    Continuation {
        /// Turning angle \[rad\] of the bend leg's final arc (`0` for a taut target).
        bend: f64,
    },
    /// The continuation failed or ended on a saddle; Newton from a smooth, length-exact guess
    /// between the clamps found the equilibrium instead.
    SmoothGuess {
        /// Why the continuation route was not used: its error, or `None` if it converged to a
        /// saddle.
        continuation_error: Option<SimError>,
    },
}
