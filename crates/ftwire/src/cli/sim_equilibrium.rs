//! Arguments of `ftwire sim-equilibrium`.

use clap::Args;

/// Arguments of `ftwire sim-equilibrium`: one equilibrium of the ground-truth discrete elastic
/// rod, with the base clamp at the identity and the tip clamp at the given pose.
#[derive(Debug, Args)]
pub struct SimEquilibriumArgs {
    /// Stiffnesses c1,c2,c3 [N·m²]: torsion, bending about body y, bending about body z.
    #[arg(
        long = "c",
        value_delimiter = ',',
        required = true,
        allow_negative_numbers = true
    )]
    pub c: Vec<f64>,
    /// Wire length L between the clamp points [m].
    #[arg(long, allow_negative_numbers = true)]
    pub length: f64,
    /// Tip clamp position X,Y,Z [m] in the base clamp frame.
    #[arg(
        long,
        value_delimiter = ',',
        required = true,
        allow_negative_numbers = true
    )]
    pub tip_position: Vec<f64>,
    /// Tip clamp orientation as a rotation vector RX,RY,RZ [rad] (axis × angle) in the base clamp
    /// frame.
    #[arg(
        long,
        value_delimiter = ',',
        required = true,
        allow_negative_numbers = true
    )]
    pub tip_rotation: Vec<f64>,
    /// Wire radius [m].
    #[arg(long, default_value_t = 0.001, allow_negative_numbers = true)]
    pub radius: f64,
    /// Material density [kg/m³] (nitinol: 6450).
    #[arg(long, default_value_t = 6450.0, allow_negative_numbers = true)]
    pub density: f64,
    /// Gravity GX,GY,GZ [m/s²] in the base clamp frame; 0,0,0 switches it off.
    #[arg(
        long,
        value_delimiter = ',',
        default_values_t = [0.0, 0.0, -9.81],
        allow_negative_numbers = true
    )]
    pub gravity: Vec<f64>,
    /// Discretisation N: N edges and N + 1 nodes (at least 3).
    #[arg(long, default_value_t = 100)]
    pub nodes: usize,
    /// Start Newton from the Kirchhoff shape of this configuration a = (τ1,τ2,τ3,f1,f2,f3)
    /// instead of a smooth cold-start guess.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub initial_a: Option<Vec<f64>>,
    /// Print one JSON object instead of a human-readable summary.
    #[arg(long)]
    pub json: bool,
}
