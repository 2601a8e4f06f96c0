//! `ftwire sim-equilibrium`: one equilibrium of the ground-truth discrete elastic rod.
//!
//! The base clamp is at the identity; the tip clamp is at `--tip-position` with orientation
//! `--tip-rotation` (a rotation vector). Wrenches follow `ftwire_sim::Equilibrium`: the wrench
//! the wire exerts on each gripper, in that gripper's clamp frame, torque first. Without
//! `--initial-a` the wire starts straight and is bent into place by continuation
//! (`World::solve_cold`); `iterations` is then the total Newton iterations over all steps.
//! The shape is the physical wire (`Equilibrium::wire_centreline`): from the base clamp point to
//! the tip clamp point, without the ghost nodes. Exit codes: 1 when Newton finds no
//! equilibrium, 2 on bad input.

use std::io::{self, Write};

use ftwire::output::{self, Report};
use ftwire_core::Pose;
use ftwire_lab::error::{LabError, from_rod, from_sim};
use ftwire_lab::initial_guess::kirchhoff_guess;
use ftwire_rod::to_normalised;
use ftwire_sim::{ContinuationParams, Equilibrium, RodParams, World};
use nalgebra::Vector6;
use serde::Serialize;

use crate::cli::sim_equilibrium::{MAX_INITIAL_A_NORMALISED, SimEquilibriumArgs, WORK_LIMIT};

/// Runs `ftwire sim-equilibrium`.
pub fn run(args: SimEquilibriumArgs) -> Result<(), LabError> {
    let eq = solve(&args)?;
    output::print(&EquilibriumReport::from(&eq), args.output.json)
}

fn solve(args: &SimEquilibriumArgs) -> Result<Equilibrium, LabError> {
    let wire = args.wire.params()?;
    let params = RodParams {
        stiffness: wire.c(),
        length: wire.length(),
        radius: wire.radius(),
        density: args.density.density,
        gravity: args.gravity.to_vector(),
        edges: args.edges,
        ..RodParams::default()
    };
    let world = World::new(params).map_err(|e| from_sim(e, "invalid wire parameters"))?;
    let settings = ContinuationParams {
        work_limit: Some(WORK_LIMIT),
        ..*world.continuation_settings()
    };
    let world = world.with_continuation(settings);
    check_clamp_distance(args, &wire)?;
    if let Some(a) = &args.initial_a {
        check_initial_a(&wire, &a.to_vector())?;
    }
    let tip = args.tip.pose();
    let Some(a) = &args.initial_a else {
        let motion = world
            .solve_cold(&Pose::identity(), &tip)
            .map_err(|e| from_sim(e, "no equilibrium for this tip pose"))?;
        return Ok(motion.equilibrium);
    };
    let model = ftwire_rod::Rod::new(wire);
    let guess = kirchhoff_guess(&model, &a.to_vector(), world.rod())
        .map_err(|e| from_rod(e, "--initial-a is not a valid wire configuration"))?;
    world
        .solve_with_guess(&guess, &Pose::identity(), &tip)
        .map_err(|e| {
            from_sim(
                e,
                "no equilibrium for this tip pose from the Kirchhoff shape of --initial-a",
            )
        })
}

/// Bad input unless the clamp points are at least the wire's diameter apart (closer, its two
/// clamped ends would overlap); the simulator refuses them farther apart than the length.
fn check_clamp_distance(
    args: &SimEquilibriumArgs,
    wire: &ftwire_core::WireParams,
) -> Result<(), LabError> {
    let distance = args.tip.tip_position.to_vector().norm();
    let diameter = 2.0 * wire.radius();
    if distance < diameter {
        return Err(LabError::bad_input(format!(
            "--tip-position {}: the clamp points are {distance} m apart; give at least the \
             wire's diameter 2 · --radius = {diameter} m (closer, the wire's two clamped ends \
             would overlap) and at most its length {} m",
            args.tip.tip_position,
            wire.length()
        )));
    }
    Ok(())
}

/// Bad input unless every component of `a` is within [`MAX_INITIAL_A_NORMALISED`] in the
/// wire's normalised units; the message gives the range in N·m and N.
fn check_initial_a(wire: &ftwire_core::WireParams, a: &Vector6<f64>) -> Result<(), LabError> {
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

/// The JSON (and text) answer.
#[derive(Serialize)]
struct EquilibriumReport {
    converged: bool,
    iterations: usize,
    #[serde(skip)]
    residual: f64,
    base_wrench: [f64; 6],
    tip_wrench: [f64; 6],
    energy: f64,
    /// The physical wire from the base clamp point to the tip clamp point \[m\].
    shape: Vec<[f64; 3]>,
    stable_minimum: bool,
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

impl Report for EquilibriumReport {
    fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
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

fn fmt6(v: &[f64; 6]) -> String {
    v.iter()
        .map(|x| format!("{x:+.6e}"))
        .collect::<Vec<_>>()
        .join(" ")
}
