//! Arguments of `ftwire sim-equilibrium`.

use clap::Args;
use ftwire::args::{
    Count, DensityArgs, JsonArgs, Numbers, TipPoseArgs, Vec3, Vec6, WireArgs, parse_numbers,
};
use ftwire_lab::equilibrium::{EDGES, default_edges};

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
    The clamp points must be at least the wire's diameter (2 · --radius) apart, or the wire's \
    two clamped ends would overlap, and at most its length. Every motion of the solve is \
    limited in work (Newton iterations times edges), so an input without a reachable \
    equilibrium ends in seconds.\n\n\
    Exit codes: 0 an equilibrium, 1 valid input but Newton found none (or spent the work \
    limit), 2 bad input."
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
        default_value_t = Numbers(ftwire_lab::wire::default_gravity()),
        allow_hyphen_values = true,
        value_parser = parse_numbers::<3>
    )]
    pub gravity: Vec3,
    /// Discretisation: N edges, N + 1 nodes including the two ghost nodes inside the grippers,
    /// 12 to 2000 (fewer give wrenches off by more than a few percent). `--nodes` is a hidden
    /// alias of this option, and means edges too (unlike `solve --nodes`, shape nodes).
    #[arg(
        long,
        value_name = "N",
        alias = "nodes",
        default_value_t = default_edges(),
        allow_hyphen_values = true,
        value_parser = Count(EDGES)
    )]
    pub edges: usize,
    /// Start Newton from the Kirchhoff shape of this configuration a = (τ1,τ2,τ3,f1,f2,f3)
    /// [N·m, N] instead of a smooth cold-start guess; each torque within ±100 c2/L and each
    /// force within ±100 c2/L² (100 in normalised units).
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
