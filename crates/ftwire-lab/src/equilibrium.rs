//! One equilibrium of the ground-truth discrete elastic rod (`ftwire sim-equilibrium`).
//!
//! The base clamp is at the identity; the tip clamp at [`EquilibriumParams::tip`]. Wrenches
//! follow `ftwire_sim::Equilibrium`: the wrench the wire exerts on each gripper, in that
//! gripper's clamp frame, torque first. Without [`EquilibriumParams::initial_a`] the wire
//! starts straight and is bent into place by continuation (`World::solve_cold`); `iterations`
//! is then the total Newton iterations over all steps. The shape is the physical wire
//! (`Equilibrium::wire_centreline`): from the base clamp point to the tip clamp point,
//! without the ghost nodes. Every motion of the solve is limited in work ([`WORK_LIMIT`]), so
//! an input without a reachable equilibrium ends in seconds.
//!
//! Guarded by this module's tests and `crates/ftwire/tests/sim_equilibrium_cli.rs`.

use std::fmt;

use ftwire_core::{Pose, WireParams};
use ftwire_rod::to_normalised;
use ftwire_sim::{ContinuationParams, Equilibrium, RodParams, World};
use nalgebra::{Vector3, Vector6};
use serde::Serialize;

use crate::error::{LabError, from_rod, from_sim};
use crate::initial_guess::kirchhoff_guess;
use ftwire_app::input::CountRange;

/// The work limit of each motion of the solve, in Newton iterations times edges
/// (`ftwire_sim::ContinuationParams::work_limit`). An iteration's cost grows in proportion to
/// the edges, so the limit bounds the time of a motion whatever the edges are, at about a
/// second plus the Newton solve under way when it is reached, while a motion that reaches its
/// target spends a fraction of it even at 2000 edges.
pub const WORK_LIMIT: usize = 200_000;

/// The largest load [`EquilibriumParams::initial_a`] may ask for, in normalised units of the
/// wire (`|τ| L/c2`, `|f| L²/c2`, each component): a normalised torque of 100 bends the wire
/// through about 100 rad (16 turns), never a wire held between two clamps (the planners
/// sample stable configurations within 30), and beyond it the Kirchhoff model's integration
/// needs ever more steps and overflows.
pub const MAX_INITIAL_A_NORMALISED: f64 = 100.0;

/// `--edges`. The discretisation error of the clamp wrenches falls as `1/N²`; from 12 edges on
/// it is within a few percent of a fine discretisation's on bent and twisted configurations,
/// while fewer edges (the simulator accepts 3) give wrenches off by tens of percent, and by
/// orders of magnitude at 3, that Newton still reports as a converged stable minimum. Beyond
/// 2000 a solve takes minutes and the error is far below anything the model or a sensor
/// resolves.
pub const EDGES: CountRange = CountRange::new(12, 2000);

/// Default `--edges`: that of `RodParams::default()`.
pub fn default_edges() -> usize {
    RodParams::default().edges
}

/// One equilibrium to find.
#[derive(Debug, Clone, PartialEq)]
pub struct EquilibriumParams {
    /// The wire.
    pub wire: WireParams,
    /// Its density \[kg/m³\].
    pub density: f64,
    /// Gravity \[m/s²\] in the base clamp frame; zero switches it off.
    pub gravity: Vector3<f64>,
    /// Discretisation: edges, the nodes being one more and including the two ghost nodes
    /// inside the grippers.
    pub edges: usize,
    /// The tip clamp's pose in the base clamp frame.
    pub tip: Pose,
    /// Start Newton from the Kirchhoff shape of this configuration `a = (τ1, τ2, τ3, f1, f2,
    /// f3)` \[N·m, N\]; `None`: a smooth cold start.
    pub initial_a: Option<Vector6<f64>>,
}

impl EquilibriumParams {
    /// The simulator's world of this wire, with each motion's work limited to
    /// [`WORK_LIMIT`].
    ///
    /// # Errors
    /// Bad input for parameters the simulator refuses.
    pub fn world(&self) -> Result<World, LabError> {
        let params = RodParams {
            stiffness: self.wire.c(),
            length: self.wire.length(),
            radius: self.wire.radius(),
            density: self.density,
            gravity: self.gravity,
            edges: self.edges,
            ..RodParams::default()
        };
        let world = World::new(params).map_err(|e| from_sim(e, "invalid wire parameters"))?;
        let settings = ContinuationParams {
            work_limit: Some(WORK_LIMIT),
            ..*world.continuation_settings()
        };
        Ok(world.with_continuation(settings))
    }

    /// Bad input refused before solving: clamp points closer than the wire's diameter (its
    /// two clamped ends would overlap; the simulator refuses them farther apart than the
    /// length), or an [`Self::initial_a`] beyond [`MAX_INITIAL_A_NORMALISED`].
    ///
    /// # Errors
    /// Bad input naming the option and the range allowed.
    pub fn check(&self) -> Result<(), LabError> {
        self.check_clamp_distance()?;
        match &self.initial_a {
            Some(a) => check_initial_a(&self.wire, a),
            None => Ok(()),
        }
    }

    fn check_clamp_distance(&self) -> Result<(), LabError> {
        let position = self.tip.translation.vector;
        let distance = position.norm();
        let diameter = 2.0 * self.wire.radius();
        if distance < diameter {
            return Err(LabError::bad_input(format!(
                "--tip-position {},{},{}: the clamp points are {distance} m apart; give at least \
                 the wire's diameter 2 · --radius = {diameter} m (closer, the wire's two clamped \
                 ends would overlap) and at most its length {} m",
                position.x,
                position.y,
                position.z,
                self.wire.length()
            )));
        }
        Ok(())
    }
}

/// Bad input unless every component of `a` is within [`MAX_INITIAL_A_NORMALISED`] in the
/// wire's normalised units; the message gives the range in N·m and N.
fn check_initial_a(wire: &WireParams, a: &Vector6<f64>) -> Result<(), LabError> {
    let normalised = to_normalised(wire, a);
    let Some(k) = (0..6).find(|&k| normalised[k].abs() > MAX_INITIAL_A_NORMALISED) else {
        return Ok(());
    };
    let c2 = wire.c()[1];
    let l = wire.length();
    let (torque, force) = (
        MAX_INITIAL_A_NORMALISED * c2 / l,
        MAX_INITIAL_A_NORMALISED * c2 / (l * l),
    );
    let name = ["τ1", "τ2", "τ3", "f1", "f2", "f3"][k];
    let unit = if k < 3 { "N·m" } else { "N" };
    // Plain digits for ordinary magnitudes, an exponent for the rest (1e300, not 301 digits).
    let value = if (1e-4..1e6).contains(&a[k].abs()) {
        format!("{}", a[k])
    } else {
        format!("{:e}", a[k])
    };
    Err(LabError::bad_input(format!(
        "--initial-a: {name} = {value} {unit} is too large for this wire: give each torque \
         within ±{torque:.4} N·m and each force within ±{force:.4} N \
         ({MAX_INITIAL_A_NORMALISED} in units of c2/L and c2/L²)"
    )))
}

/// The equilibrium with the tip clamp at [`EquilibriumParams::tip`]: from a cold start, or
/// from the Kirchhoff shape of [`EquilibriumParams::initial_a`].
///
/// # Errors
/// Bad input as [`EquilibriumParams::world`] and [`EquilibriumParams::check`], or for an
/// `initial_a` the Kirchhoff model cannot shape; no answer when Newton finds no equilibrium
/// (or spends the work limit).
pub fn solve(params: &EquilibriumParams) -> Result<EquilibriumReport, LabError> {
    let world = params.world()?;
    params.check()?;
    let equilibrium = match &params.initial_a {
        None => {
            world
                .solve_cold(&Pose::identity(), &params.tip)
                .map_err(|e| from_sim(e, "no equilibrium for this tip pose"))?
                .equilibrium
        }
        Some(a) => {
            let model = ftwire_rod::Rod::new(params.wire);
            let guess = kirchhoff_guess(&model, a, world.rod())
                .map_err(|e| from_rod(e, "--initial-a is not a valid wire configuration"))?;
            world
                .solve_with_guess(&guess, &Pose::identity(), &params.tip)
                .map_err(|e| {
                    from_sim(
                        e,
                        "no equilibrium for this tip pose from the Kirchhoff shape of --initial-a",
                    )
                })?
        }
    };
    Ok(EquilibriumReport::from(&equilibrium))
}

/// The answer as `ftwire sim-equilibrium` prints it: with `--json` one object of these fields
/// (but the residual); the text is its [`fmt::Display`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EquilibriumReport {
    /// Whether Newton converged.
    pub converged: bool,
    /// Newton iterations (over all steps of a cold start).
    pub iterations: usize,
    /// The final residual (text only).
    #[serde(skip)]
    pub residual: f64,
    /// The wrench on the base gripper, torque \[N·m\] first then force \[N\], base clamp frame.
    pub base_wrench: [f64; 6],
    /// The wrench on the tip gripper, torque \[N·m\] first then force \[N\], tip clamp frame.
    pub tip_wrench: [f64; 6],
    /// The elastic and gravitational energy \[J\].
    pub energy: f64,
    /// The physical wire from the base clamp point to the tip clamp point \[m\].
    pub shape: Vec<[f64; 3]>,
    /// Whether the equilibrium is a stable minimum of the energy.
    pub stable_minimum: bool,
}

impl From<&Equilibrium> for EquilibriumReport {
    fn from(eq: &Equilibrium) -> Self {
        Self {
            converged: eq.convergence.converged,
            iterations: eq.convergence.iterations,
            residual: eq.convergence.residual,
            base_wrench: eq.base_wrench.to_vector().into(),
            tip_wrench: eq.tip_wrench.to_vector().into(),
            energy: eq.energy(),
            shape: eq
                .wire_centreline()
                .iter()
                .map(|p| [p.x, p.y, p.z])
                .collect(),
            stable_minimum: eq.stable_minimum,
        }
    }
}

/// The human text: convergence, stability, both wrenches, the energy and the shape's size.
impl fmt::Display for EquilibriumReport {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        let fmt6 = |v: &[f64; 6]| {
            v.iter()
                .map(|x| format!("{x:+.6e}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        writeln!(
            out,
            "converged: {} after {} Newton iterations (residual {:.2e})",
            self.converged, self.iterations, self.residual
        )?;
        writeln!(out, "stable minimum: {}", self.stable_minimum)?;
        writeln!(
            out,
            "base wrench (τ1 τ2 τ3 [N·m], f1 f2 f3 [N], base clamp frame): {}",
            fmt6(&self.base_wrench)
        )?;
        writeln!(
            out,
            "tip wrench  (τ1 τ2 τ3 [N·m], f1 f2 f3 [N], tip clamp frame):  {}",
            fmt6(&self.tip_wrench)
        )?;
        writeln!(out, "energy: {:.6e} J", self.energy)?;
        writeln!(
            out,
            "shape: {} points from the base to the tip clamp point (use --json for them)",
            self.shape.len()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    fn params(tip: [f64; 3]) -> EquilibriumParams {
        EquilibriumParams {
            wire: WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("a wire"),
            density: 6450.0,
            gravity: Vector3::zeros(),
            edges: 24,
            tip: Pose::from_parts(
                Translation3::from(Vector3::from(tip)),
                UnitQuaternion::identity(),
            ),
            initial_a: None,
        }
    }

    #[test]
    fn clamps_closer_than_the_diameter_and_a_huge_initial_a_are_bad_input() {
        let error = params([0.001, 0.0, 0.0]).check().expect_err("too close");
        assert!(
            error.to_string().starts_with("--tip-position 0.001,0,0: "),
            "{error}"
        );
        let mut far = params([0.6, 0.0, 0.0]);
        far.initial_a = Some(Vector6::new(0.0, 0.0, 1e300, 0.0, 0.0, 0.0));
        let error = far.check().expect_err("τ3 far beyond 100 c2/L");
        assert!(
            error
                .to_string()
                .starts_with("--initial-a: τ3 = 1e300 N·m "),
            "{error}"
        );
        assert_eq!(error.kind(), "bad_input");
    }

    #[test]
    fn the_shape_runs_from_the_base_to_the_tip_clamp_point() {
        let report = solve(&params([0.6, 0.0, 0.0])).expect("an equilibrium");
        assert!(report.converged);
        assert!(
            report.energy.is_finite() && report.energy > 0.0,
            "a bent wire"
        );
        let first = report.shape.first().copied().unwrap_or([1.0; 3]);
        let last = report.shape.last().copied().unwrap_or_default();
        assert!(first.iter().all(|v| v.abs() < 1e-12), "{first:?}");
        assert!(
            (last[0] - 0.6).abs() < 1e-9 && last[1].abs() < 1e-9,
            "{last:?}"
        );
        assert!(report.to_string().starts_with("converged: true after "));
    }
}
