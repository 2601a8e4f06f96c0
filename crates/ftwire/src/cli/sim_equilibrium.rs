//! Arguments of `ftwire sim-equilibrium`.

use clap::Args;
use ftwire::args::{
    DensityArgs, JsonArgs, TipPoseArgs, Vec3, Vec6, WireArgs, default_gravity, parse_numbers,
};

/// Smallest `--edges`: the simulator's own minimum.
pub const MIN_EDGES: u64 = ftwire_sim::DiscreteRod::MIN_EDGES as u64;
/// Largest `--edges`: beyond it a solve takes minutes and the discretisation error (O(1/N²))
/// is far below anything the model or a sensor resolves.
pub const MAX_EDGES: u64 = 2000;

/// Default `--edges`: that of `ftwire_sim::RodParams::default()`.
pub fn default_edges() -> u64 {
    ftwire_sim::RodParams::default().edges as u64
}

/// Arguments of `ftwire sim-equilibrium`: one equilibrium of the ground-truth discrete elastic
/// rod, with the base clamp at the identity and the tip clamp at the given pose.
#[derive(Debug, Args)]
#[command(
    mut_arg("c", |a| a.required(true)),
    mut_arg("length", |a| a.required(true)),
    after_help = "With --json, one object: converged, iterations, base_wrench and tip_wrench \
    (τ1,τ2,τ3,f1,f2,f3, each in its own clamp frame), energy [J], stable_minimum, and shape: \
    the physical centreline [m], N + 1 points from the base clamp point (the origin) through \
    the N − 1 interior nodes to the tip clamp point (--tip-position), without the two ghost \
    nodes inside the grippers.\n\n\
    Exit codes: 0 an equilibrium, 1 valid input but Newton found none, 2 bad input."
)]
pub struct SimEquilibriumArgs {
    /// The wire.
    #[command(flatten)]
    pub wire: WireArgs,
    /// Its density.
    #[command(flatten)]
    pub density: DensityArgs,
    /// Where the tip clamp is.
    #[command(flatten)]
    pub tip: TipPoseArgs,
    /// Gravity GX,GY,GZ [m/s²] in the base clamp frame; 0,0,0 switches it off.
    #[arg(
        long,
        value_name = "GX,GY,GZ",
        default_value_t = default_gravity(),
        allow_hyphen_values = true,
        value_parser = parse_numbers::<3>
    )]
    pub gravity: Vec3,
    /// Discretisation: N edges, N + 1 nodes including the two ghost nodes inside the grippers.
    /// `--nodes` is a hidden old name of this option, and means edges too (unlike `solve
    /// --nodes`, shape nodes).
    #[arg(
        long,
        value_name = "N",
        alias = "nodes",
        default_value_t = default_edges(),
        allow_hyphen_values = true,
        value_parser = clap::value_parser!(u64).range(MIN_EDGES..=MAX_EDGES)
    )]
    pub edges: u64,
    /// Start Newton from the Kirchhoff shape of this configuration a = (τ1,τ2,τ3,f1,f2,f3)
    /// instead of a smooth cold-start guess.
    #[arg(
        long,
        value_name = "A1,..,A6",
        allow_hyphen_values = true,
        value_parser = parse_numbers::<6>
    )]
    pub initial_a: Option<Vec6>,
    /// Output format (the JSON keys are listed after the options).
    #[command(flatten)]
    pub output: JsonArgs,
}
