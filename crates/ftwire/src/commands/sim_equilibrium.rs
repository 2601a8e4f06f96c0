//! `ftwire sim-equilibrium`: one equilibrium of the ground-truth discrete elastic rod.
//!
//! The base clamp is at the identity; the tip clamp is at `--tip-position` with orientation
//! `--tip-rotation` (a rotation vector). Wrenches follow `ftwire_sim::Equilibrium`: the wrench
//! the wire exerts on each gripper, in that gripper's clamp frame, torque first. Without
//! `--initial-a` the wire starts straight and is bent into place by continuation
//! (`World::solve_cold`); `iterations` is then the total Newton iterations over all steps.
//! Errors print a message and exit with code 2.

use std::process::ExitCode;

use anyhow::{Context, bail};
use ftwire::bridge::kirchhoff_guess;
use ftwire_core::WireParams;
use ftwire_sim::{Equilibrium, RodParams, World};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3, Vector6};

use crate::cli::sim_equilibrium::SimEquilibriumArgs;

/// Runs `ftwire sim-equilibrium`.
pub fn run(args: SimEquilibriumArgs) -> anyhow::Result<ExitCode> {
    match solve(&args) {
        Ok(eq) => {
            print(&args, &eq)?;
            Ok(ExitCode::SUCCESS)
        }
        Err(error) => {
            eprintln!("error: {error:#}");
            Ok(ExitCode::from(2))
        }
    }
}

fn triple(name: &str, v: &[f64]) -> anyhow::Result<[f64; 3]> {
    match v {
        [a, b, c] => Ok([*a, *b, *c]),
        _ => bail!(
            "--{name} needs exactly 3 comma-separated numbers, got {}",
            v.len()
        ),
    }
}

fn solve(args: &SimEquilibriumArgs) -> anyhow::Result<Equilibrium> {
    let c = triple("c", &args.c)?;
    let position = triple("tip-position", &args.tip_position)?;
    let rotation = triple("tip-rotation", &args.tip_rotation)?;
    let gravity = triple("gravity", &args.gravity)?;
    let params = RodParams {
        stiffness: c,
        length: args.length,
        radius: args.radius,
        density: args.density,
        gravity: Vector3::from(gravity),
        edges: args.nodes,
        ..RodParams::default()
    };
    let world = World::new(params).context("invalid wire parameters")?;
    let tip = Isometry3::from_parts(
        Translation3::from(Vector3::from(position)),
        UnitQuaternion::from_scaled_axis(Vector3::from(rotation)),
    );
    let Some(a) = &args.initial_a else {
        let motion = world
            .solve_cold(&Isometry3::identity(), &tip)
            .context("no equilibrium for this tip pose")?;
        return Ok(motion.equilibrium);
    };
    let a: [f64; 6] = a.as_slice().try_into().map_err(|_| {
        anyhow::anyhow!(
            "--initial-a needs exactly 6 comma-separated numbers (τ1,τ2,τ3,f1,f2,f3), got {}",
            a.len()
        )
    })?;
    let wire = WireParams::new(c, args.length, args.radius).context("invalid wire parameters")?;
    let model = ftwire_rod::Rod::new(wire);
    let guess = kirchhoff_guess(&model, &Vector6::from(a), world.rod())
        .context("--initial-a is not a valid wire configuration")?;
    world
        .solve_with_guess(&guess, &Isometry3::identity(), &tip)
        .context("no equilibrium for this tip pose from the Kirchhoff shape of --initial-a")
}

fn print(args: &SimEquilibriumArgs, eq: &Equilibrium) -> anyhow::Result<()> {
    let base = eq.base_wrench.to_vector();
    let tip = eq.tip_wrench.to_vector();
    let shape: Vec<[f64; 3]> = eq.centreline().iter().map(|p| [p.x, p.y, p.z]).collect();
    if args.json {
        let value = serde_json::json!({
            "converged": eq.convergence.converged,
            "iterations": eq.convergence.iterations,
            "base_wrench": base.as_slice(),
            "tip_wrench": tip.as_slice(),
            "energy": eq.energy(),
            "shape": shape,
            "stable_minimum": eq.stable_minimum,
        });
        println!("{}", serde_json::to_string(&value)?);
    } else {
        println!(
            "converged: {} after {} Newton iterations (residual {:.2e})",
            eq.convergence.converged, eq.convergence.iterations, eq.convergence.residual
        );
        println!("stable minimum: {}", eq.stable_minimum);
        println!(
            "base wrench (τ1 τ2 τ3 [N·m], f1 f2 f3 [N], base clamp frame): {}",
            fmt6(&base)
        );
        println!(
            "tip wrench  (τ1 τ2 τ3 [N·m], f1 f2 f3 [N], tip clamp frame):  {}",
            fmt6(&tip)
        );
        println!("energy: {:.6e} J", eq.energy());
        println!(
            "shape: {} nodes (use --json for the coordinates)",
            shape.len()
        );
    }
    Ok(())
}

fn fmt6(v: &nalgebra::Vector6<f64>) -> String {
    v.iter()
        .map(|x| format!("{x:+.6e}"))
        .collect::<Vec<_>>()
        .join(" ")
}
