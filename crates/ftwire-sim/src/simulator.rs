//! A stateful simulator: the world plus its current equilibrium, which survives failures.

use ftwire_core::Pose;

use crate::continuation;
use crate::equilibrium::Equilibrium;
use crate::error::SimError;
use crate::motion::{Motion, SnapEvent};
use crate::state::InitialGuess;
use crate::world::World;

/// The world and the wire's current equilibrium.
///
/// Every motion warm-starts from the current equilibrium; if a motion fails, the simulator keeps
/// the last good equilibrium it reached on the way (and the error says so).
///
/// # Example
/// ```
/// use ftwire_sim::{RodParams, Simulator, World};
/// use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
///
/// let world = World::new(RodParams::nitinol_2mm_630().with_edges(40))?;
/// let base = Isometry3::identity();
/// let tip = Isometry3::from_parts(Translation3::new(0.5, 0.1, 0.0), UnitQuaternion::identity());
/// let mut sim = Simulator::new(world, &base, &tip)?;
/// let closer = Isometry3::from_parts(Translation3::new(0.45, 0.1, 0.0), UnitQuaternion::identity());
/// sim.move_grippers(&base, &closer)?;
/// assert!(sim.equilibrium().stable_minimum);
/// assert!((sim.equilibrium().state.tip().translation.x - 0.45).abs() < 1e-12);
/// # Ok::<(), ftwire_sim::SimError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Simulator {
    world: World,
    current: Equilibrium,
    snaps: Vec<SnapEvent>,
    last_motion: Option<Motion>,
}

impl Simulator {
    /// Cold start: a straight wire bent into place by continuation ([`World::solve_cold`]).
    ///
    /// # Errors
    /// As [`World::solve_cold`].
    pub fn new(world: World, base: &Pose, tip: &Pose) -> Result<Self, SimError> {
        let motion = world.solve_cold(base, tip)?;
        Ok(Self {
            world,
            current: motion.equilibrium,
            snaps: motion.snaps,
            last_motion: None,
        })
    }

    /// Starts from a user-given initial guess ([`World::solve_with_guess`]).
    ///
    /// # Errors
    /// As [`World::solve_with_guess`].
    pub fn with_guess(
        world: World,
        guess: &InitialGuess,
        base: &Pose,
        tip: &Pose,
    ) -> Result<Self, SimError> {
        let current = world.solve_with_guess(guess, base, tip)?;
        Ok(Self {
            world,
            current,
            snaps: Vec::new(),
            last_motion: None,
        })
    }

    /// Starts from a known equilibrium of this world.
    pub fn from_equilibrium(world: World, current: Equilibrium) -> Self {
        Self {
            world,
            current,
            snaps: Vec::new(),
            last_motion: None,
        }
    }

    /// Moves the grippers quasi-statically to `base` and `tip` (world frame), following the
    /// current branch of equilibria. Snaps met on the way are returned in the motion and
    /// appended to [`Simulator::snaps`].
    ///
    /// # Errors
    /// [`SimError::Core`] (non-finite) or [`SimError::GrippersTooFarApart`] (nothing moves), or
    /// [`SimError::NewtonFailed`]: the simulator then holds the last equilibrium reached.
    pub fn move_grippers(&mut self, base: &Pose, tip: &Pose) -> Result<&Motion, SimError> {
        let (motion, error) = continuation::run(&self.world, &self.current, base, tip);
        self.current = motion.equilibrium.clone();
        self.snaps.extend(motion.snaps.iter().cloned());
        self.last_motion = Some(motion);
        match error {
            Some(e) => Err(e),
            None => self.last_motion.as_ref().ok_or(SimError::NotSolved),
        }
    }

    /// The clamp poses `(base, tip)` of the current equilibrium, world frame (the ground truth;
    /// a robot model adds its execution error on top).
    pub fn gripper_poses(&self) -> (Pose, Pose) {
        (*self.current.state.base(), *self.current.state.tip())
    }

    /// The motion of the last [`Simulator::move_grippers`], a failed one up to where it stopped
    /// (`None` before the first).
    pub fn last_motion(&self) -> Option<&Motion> {
        self.last_motion.as_ref()
    }

    /// The current equilibrium.
    pub fn equilibrium(&self) -> &Equilibrium {
        &self.current
    }

    /// The world.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// All snaps since the simulator was created.
    pub fn snaps(&self) -> &[SnapEvent] {
        &self.snaps
    }
}
