//! The simulated world: one rod, its obstacles, and the solver settings.

use ftwire_core::Pose;

use crate::cold_start::{self, ColdStart};
use crate::continuation::{self, ContinuationSettings, Motion};
use crate::equilibrium::Equilibrium;
use crate::error::{SimError, ensure_finite, ensure_positive};
use crate::newton::{self, NewtonSettings};
use crate::obstacle::{BoxObstacle, Floor, Obstacle};
use crate::rod::{Rod, RodParams};
use crate::state::{InitialGuess, RodState};

/// The default contact stiffness \[N/m³\].
pub const DEFAULT_CONTACT_STIFFNESS: f64 = 1e12;

/// A rod with obstacles and solver settings: everything needed to compute equilibria.
///
/// # Example
/// ```
/// use ftwire_sim::{RodParams, World};
/// use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
///
/// let params = RodParams::default().with_edges(40).without_gravity();
/// let c3 = params.stiffness[2];
/// let world = World::new(params)?;
/// // Tip on a circle of radius 0.4 m through the base, turned with the tangent: a pure arc
/// // bending towards +y, which loads the base with the moment c3/R about its z axis.
/// let (r, phi): (f64, f64) = (0.4, 0.63 / 0.4);
/// let tip = Isometry3::from_parts(
///     Translation3::new(r * phi.sin(), r * (1.0 - phi.cos()), 0.0),
///     UnitQuaternion::from_axis_angle(&Vector3::z_axis(), phi),
/// );
/// let eq = world.solve_cold(&Isometry3::identity(), &tip)?.equilibrium;
/// assert!(eq.stable_minimum);
/// assert!((eq.base_wrench.torque.z - c3 / r).abs() < 0.01 * c3 / r);
/// # Ok::<(), ftwire_sim::SimError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct World {
    rod: Rod,
    obstacles: Vec<Obstacle>,
    contact_stiffness: f64,
    newton: NewtonSettings,
    continuation: ContinuationSettings,
    samples_per_edge: usize,
}

impl World {
    /// A world with one rod and no obstacles.
    ///
    /// # Errors
    /// As [`Rod::new`].
    pub fn new(params: RodParams) -> Result<Self, SimError> {
        let mut world = Self {
            rod: Rod::new(params)?,
            obstacles: Vec::new(),
            contact_stiffness: DEFAULT_CONTACT_STIFFNESS,
            newton: NewtonSettings::default(),
            continuation: ContinuationSettings::default(),
            samples_per_edge: 2,
        };
        world.update_sampling();
        Ok(world)
    }

    /// Adds a box obstacle.
    #[must_use]
    pub fn with_box(mut self, obstacle: BoxObstacle) -> Self {
        self.obstacles.push(Obstacle::Box(obstacle));
        self.update_sampling();
        self
    }

    /// Adds a floor.
    ///
    /// # Errors
    /// [`SimError::NonFinite`] if the height is not finite.
    pub fn with_floor(mut self, floor: Floor) -> Result<Self, SimError> {
        ensure_finite("floor height", &[floor.height])?;
        self.obstacles.push(Obstacle::Floor(floor));
        self.update_sampling();
        Ok(self)
    }

    /// Sets the contact stiffness `k` \[N/m³\] (default [`DEFAULT_CONTACT_STIFFNESS`]): a
    /// penetration `δ` costs `k·δ³/3` per metre of wire.
    ///
    /// # Errors
    /// [`SimError::NotPositive`] unless `k` is finite and positive.
    pub fn with_contact_stiffness(mut self, k: f64) -> Result<Self, SimError> {
        ensure_positive("contact_stiffness", k)?;
        self.contact_stiffness = k;
        Ok(self)
    }

    /// Sets Newton's settings.
    #[must_use]
    pub fn with_newton(mut self, settings: NewtonSettings) -> Self {
        self.newton = settings;
        self
    }

    /// Sets the continuation settings.
    #[must_use]
    pub fn with_continuation(mut self, settings: ContinuationSettings) -> Self {
        self.continuation = settings;
        self
    }

    /// The same world (obstacles, settings) with its rod discretised into `edges` edges.
    pub(crate) fn with_edge_count(&self, edges: usize) -> Result<Self, SimError> {
        let mut world = Self {
            rod: Rod::new(self.rod.params().with_edges(edges))?,
            ..self.clone()
        };
        world.update_sampling();
        Ok(world)
    }

    fn update_sampling(&mut self) {
        let r = self.rod.params().radius;
        let thinnest = self.thinnest_obstacle();
        let spacing = r.min(2.0 * r + thinnest);
        let count = (self.rod.edge_length() / spacing).ceil() as usize + 1;
        self.samples_per_edge = count.clamp(2, 64);
    }

    fn thinnest_obstacle(&self) -> f64 {
        self.obstacles
            .iter()
            .map(Obstacle::thickness)
            .fold(f64::INFINITY, f64::min)
    }

    /// The rod.
    pub fn rod(&self) -> &Rod {
        &self.rod
    }

    /// The obstacles, in the order they were added.
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.obstacles
    }

    /// Contact stiffness \[N/m³\].
    pub fn contact_stiffness(&self) -> f64 {
        self.contact_stiffness
    }

    /// Newton's settings.
    pub fn newton_settings(&self) -> &NewtonSettings {
        &self.newton
    }

    /// Continuation settings.
    pub fn continuation_settings(&self) -> &ContinuationSettings {
        &self.continuation
    }

    /// Contact samples per edge.
    pub fn samples_per_edge(&self) -> usize {
        self.samples_per_edge
    }

    /// The largest node displacement \[m\] allowed in one Newton iteration or one continuation
    /// step when there are box obstacles: half of `r + t/2`, so that no contact sample can cross
    /// the mid-plane of the thinnest obstacle (thickness `t`) in one move. `None` without boxes.
    pub fn contact_step_limit(&self) -> Option<f64> {
        let t = self.thinnest_obstacle();
        t.is_finite()
            .then(|| 0.5 * (self.rod.params().radius + 0.5 * t))
    }

    /// Checks that the clamp poses are finite and not farther apart than the wire is long.
    pub(crate) fn check_poses(&self, base: &Pose, tip: &Pose) -> Result<(), SimError> {
        ensure_finite("base position", base.translation.vector.as_slice())?;
        ensure_finite("base rotation", base.rotation.coords.as_slice())?;
        ensure_finite("tip position", tip.translation.vector.as_slice())?;
        ensure_finite("tip rotation", tip.rotation.coords.as_slice())?;
        let distance = (tip.translation.vector - base.translation.vector).norm();
        let length = self.rod.params().length;
        if distance > length * (1.0 + 1e-12) {
            return Err(SimError::GrippersTooFarApart { distance, length });
        }
        Ok(())
    }

    /// Solves by Newton's method directly from `state`, with the clamps placed at `base` and
    /// `tip` (no continuation).
    pub(crate) fn newton_from(
        &self,
        mut state: RodState,
        base: &Pose,
        tip: &Pose,
    ) -> Result<Equilibrium, SimError> {
        state.apply_clamps(&self.rod, base, tip);
        state.rebase();
        newton::solve(self, state)
            .map(Equilibrium::from_newton)
            .map_err(|f| SimError::NewtonFailed {
                iterations: f.iterations,
                residual: f.residual,
                subdivisions: 0,
            })
    }

    /// Cold start: a straight wire bent into place by continuation.
    ///
    /// From the straight, untwisted wire (tip clamp `L` along the base tangent), the tip clamp
    /// first follows the ends of planar arcs bent towards the target (an exact path of
    /// equilibria of the weightless rod, regular from its first step, unlike a straight inward
    /// move, which starts on the taut wire's buckling bifurcation), then moves to `tip` by the
    /// ordinary continuation, which follows the branch and reports snaps (module
    /// `cold_start`). For more than 50 edges the path runs on a 25-edge copy of the world and
    /// its end starts one Newton solve at full resolution. The result reports the continuation steps, the total Newton iterations
    /// (also in [`crate::Convergence::iterations`]) and the route in [`Motion::cold_start`].
    ///
    /// If the continuation fails, or ends on a saddle, Newton from a smooth guess
    /// ([`World::solve_smooth_guess`]) is tried, and
    /// [`ColdStart::SmoothGuess`](crate::ColdStart::SmoothGuess) says so; if that fails too,
    /// the continuation's error is returned.
    ///
    /// # Errors
    /// [`SimError::NonFinite`] for a non-finite pose, [`SimError::GrippersTooFarApart`],
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
    /// [`SimError::NonFinite`] for a non-finite pose, [`SimError::GrippersTooFarApart`],
    /// [`SimError::NewtonFailed`].
    pub fn solve_smooth_guess(&self, base: &Pose, tip: &Pose) -> Result<Motion, SimError> {
        self.check_poses(base, tip)?;
        let guess = RodState::hermite(&self.rod, base, tip);
        let equilibrium = self.newton_from(guess, base, tip)?;
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
    /// [`SimError::GuessSize`], [`SimError::DegenerateGuess`], [`SimError::NonFinite`],
    /// [`SimError::GrippersTooFarApart`], [`SimError::NewtonFailed`].
    pub fn solve_with_guess(
        &self,
        guess: &InitialGuess,
        base: &Pose,
        tip: &Pose,
    ) -> Result<Equilibrium, SimError> {
        self.check_poses(base, tip)?;
        let state = RodState::from_guess(&self.rod, guess, base, tip)?;
        // A guess that ends elsewhere than the clamps is first solved at the clamp poses it
        // implies, then carried to the requested ones by continuation.
        if let Some((b0, t0)) = implied_clamps(guess)
            && (!close(&b0, base, self.rod.edge_length())
                || !close(&t0, tip, self.rod.edge_length()))
            && self.check_poses(&b0, &t0).is_ok()
        {
            let own = RodState::from_guess(&self.rod, guess, &b0, &t0)?;
            let start = self.newton_from(own, &b0, &t0)?;
            return Ok(self.move_grippers(&start, base, tip)?.equilibrium);
        }
        self.newton_from(state, base, tip)
    }

    /// Warm start: moves the grippers from the poses of `from` to `base` and `tip` by
    /// quasi-static continuation (see the crate guide, "Continuation").
    ///
    /// # Errors
    /// [`SimError::NonFinite`], [`SimError::GrippersTooFarApart`], [`SimError::NewtonFailed`]
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
