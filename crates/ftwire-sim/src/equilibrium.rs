//! A solved equilibrium and its outputs: clamp wrenches, shape, energy, contact forces.

use ftwire_core::{Pose, Wrench};
use nalgebra::{Point3, Rotation3, Vector3};

use crate::banded::BandedSym;
use crate::energy::{Energies, Evaluation, theta_dof, x_dof};
use crate::error::SimError;
use crate::newton::{self, Convergence, NewtonResult};
use crate::state::RodState;
use crate::world::World;

/// An equilibrium of the rod between its two clamps.
///
/// Conventions (as the configuration `a` of DESIGN.md):
/// - [`Equilibrium::base_wrench`] is the wrench the wire exerts **on the base gripper**,
///   expressed in the base clamp frame, about the base clamp point, torque first when
///   flattened. For a planar arc bending towards the base's +y with curvature κ it is
///   `(0, 0, c3·κ, 0, 0, 0)`; for a straight wire whose tip is turned by φ about its own x axis
///   (a positive twist) it is `(c1·φ/L, 0, 0, 0, 0, 0)`.
/// - [`Equilibrium::tip_wrench`] is the wrench the wire exerts on the second gripper, expressed
///   in the tip clamp frame, about the tip clamp point (for the arc: `(0, 0, −c3·κ, 0, 0, 0)`).
#[derive(Debug, Clone, PartialEq)]
pub struct Equilibrium {
    /// The rod's configuration (use it to warm-start the next solve).
    pub state: RodState,
    /// Wrench of the wire on the base gripper \[N·m, N\], base clamp frame, about its origin.
    pub base_wrench: Wrench,
    /// Wrench of the wire on the second gripper \[N·m, N\], tip clamp frame, about its origin.
    pub tip_wrench: Wrench,
    /// Energies \[J\].
    pub energies: Energies,
    /// Force \[N\] each obstacle exerts on the wire, world frame, in the order the obstacles
    /// were added to the world.
    pub contact_forces: Vec<Vector3<f64>>,
    /// Convergence data.
    pub convergence: Convergence,
    /// Whether the unregularised Hessian is positive definite on the free degrees of freedom,
    /// i.e. the equilibrium is a stable minimum and not a saddle.
    pub stable_minimum: bool,
    /// The Hessian at the equilibrium, kept for the next continuation predictor.
    pub(crate) hessian: BandedSym,
}

impl Equilibrium {
    /// Solves by Newton's method directly from `state`, with the clamps placed at `base` and
    /// `tip` (no continuation).
    pub(crate) fn newton_from(
        world: &World,
        mut state: RodState,
        base: &Pose,
        tip: &Pose,
    ) -> Result<Self, SimError> {
        state.apply_clamps(world.rod(), base, tip);
        state.rebase();
        newton::solve(world, state)
            .map(Self::from_newton)
            .map_err(|f| SimError::NewtonFailed {
                iterations: f.iterations,
                residual: f.residual,
                subdivisions: 0,
            })
    }

    pub(crate) fn from_newton(result: NewtonResult) -> Self {
        let NewtonResult {
            state,
            eval,
            hessian,
            iterations,
            residual,
            stable,
        } = result;
        let n = state.edges();
        let base_wrench = clamp_wrench(&state, &eval, &state.base, [0, 1], 0);
        let tip_wrench = clamp_wrench(&state, &eval, &state.tip, [n - 1, n], n - 1);
        Self {
            base_wrench,
            tip_wrench,
            energies: eval.energies,
            contact_forces: eval.contact_forces,
            convergence: Convergence {
                converged: true,
                iterations,
                residual,
            },
            stable_minimum: stable,
            hessian,
            state,
        }
    }

    /// The total potential energy \[J\].
    pub fn energy(&self) -> f64 {
        self.energies.total()
    }

    /// The centreline \[m\], world frame (see [`RodState::centreline`]).
    pub fn centreline(&self) -> Vec<Point3<f64>> {
        self.state.centreline()
    }

    /// The physical wire from the base clamp point to the tip clamp point \[m\], world frame,
    /// without the ghost nodes (see [`RodState::wire_centreline`]).
    pub fn wire_centreline(&self) -> Vec<Point3<f64>> {
        self.state.wire_centreline()
    }

    /// The edge material frames, world from body (see [`RodState::material_frames`]).
    pub fn material_frames(&self) -> Vec<Rotation3<f64>> {
        self.state.material_frames()
    }
}

/// The wrench the wire exerts on a clamp holding `nodes` and the material angle of `edge`.
///
/// The clamp applies constraint forces `∂E/∂x_k` and a moment `∂E/∂θ` about the clamped edge's
/// tangent; by virtual work under a rigid rotation `ω` of the clamp (nodes move by
/// `ω × (x_k − p)`, the clamped angle by `ω·t`, the reference director being time-parallel
/// transported from the current tangent), the wire's wrench on the clamp about its point `p` is
/// `f = −Σ ∂E/∂x_k`, `τ = −Σ (x_k − p) × ∂E/∂x_k − (∂E/∂θ)·t`.
fn clamp_wrench(
    state: &RodState,
    eval: &Evaluation,
    pose: &Pose,
    nodes: [usize; 2],
    edge: usize,
) -> Wrench {
    let p = pose.translation.vector;
    let t = pose.rotation * Vector3::x();
    let mut force = Vector3::zeros();
    let mut torque = Vector3::zeros();
    for k in nodes {
        let g = Vector3::new(
            eval.grad[x_dof(k, 0)],
            eval.grad[x_dof(k, 1)],
            eval.grad[x_dof(k, 2)],
        );
        force -= g;
        torque -= (state.nodes[k] - p).cross(&g);
    }
    torque -= t * eval.grad[theta_dof(edge)];
    let inv = pose.rotation.inverse();
    Wrench::new(inv * torque, inv * force)
}
