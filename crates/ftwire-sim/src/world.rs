//! The simulated world as data: one rod, its obstacles, and the solver settings. The solves
//! that take a world (`World::solve_cold` and the others) are in the `solve` module.

use ftwire_core::{Pose, ensure_finite, ensure_positive};

use crate::discrete_rod::{DiscreteRod, RodParams};
use crate::error::SimError;
use crate::obstacle::{BoxObstacle, Floor, Obstacle};
use crate::settings::{ContinuationParams, NewtonParams};

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
    rod: DiscreteRod,
    obstacles: Vec<Obstacle>,
    contact_stiffness: f64,
    newton: NewtonParams,
    continuation: ContinuationParams,
    samples_per_edge: usize,
}

impl World {
    /// A world with one rod and no obstacles.
    ///
    /// # Errors
    /// As [`DiscreteRod::new`].
    pub fn new(params: RodParams) -> Result<Self, SimError> {
        let mut world = Self {
            rod: DiscreteRod::new(params)?,
            obstacles: Vec::new(),
            contact_stiffness: DEFAULT_CONTACT_STIFFNESS,
            newton: NewtonParams::default(),
            continuation: ContinuationParams::default(),
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
    /// [`SimError::Core`] (non-finite) if the height is not finite.
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
    /// [`SimError::Core`] (not positive) unless `k` is finite and positive.
    pub fn with_contact_stiffness(mut self, k: f64) -> Result<Self, SimError> {
        ensure_positive("contact_stiffness", k)?;
        self.contact_stiffness = k;
        Ok(self)
    }

    /// Sets Newton's settings.
    #[must_use]
    pub fn with_newton(mut self, settings: NewtonParams) -> Self {
        self.newton = settings;
        self
    }

    /// Sets the continuation settings.
    #[must_use]
    pub fn with_continuation(mut self, settings: ContinuationParams) -> Self {
        self.continuation = settings;
        self
    }

    /// The same world (obstacles, settings) with its rod discretised into `edges` edges.
    pub(crate) fn with_edge_count(&self, edges: usize) -> Result<Self, SimError> {
        let mut world = Self {
            rod: DiscreteRod::new(self.rod.params().with_edges(edges))?,
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
    pub fn rod(&self) -> &DiscreteRod {
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
    pub fn newton_settings(&self) -> &NewtonParams {
        &self.newton
    }

    /// Continuation settings.
    pub fn continuation_settings(&self) -> &ContinuationParams {
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
}
