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

use ftwire::bridge::kirchhoff_guess;
use ftwire::error::{CliError, from_rod, from_sim};
use ftwire::output::{self, Report};
use ftwire_core::Pose;
use ftwire_sim::{Equilibrium, RodParams, World};
use serde::Serialize;

use crate::cli::sim_equilibrium::SimEquilibriumArgs;

/// Runs `ftwire sim-equilibrium`.
pub fn run(args: SimEquilibriumArgs) -> Result<(), CliError> {
    let eq = solve(&args)?;
    output::print(&EquilibriumReport::from(&eq), args.output.json)
}

fn solve(args: &SimEquilibriumArgs) -> Result<Equilibrium, CliError> {
    let wire = args.wire.params()?;
    let params = RodParams {
        stiffness: wire.c(),
        length: wire.length(),
        radius: wire.radius(),
        density: args.density.density,
        gravity: args.gravity.to_vector(),
        // Bounded by clap to MIN_EDGES..=MAX_EDGES, far inside usize.
        edges: usize::try_from(args.edges).unwrap_or(usize::MAX),
        ..RodParams::default()
    };
    let world = World::new(params).map_err(|e| from_sim(e, "invalid wire parameters"))?;
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
