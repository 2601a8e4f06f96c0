//! Arguments of `ftwire solve`.

use std::path::PathBuf;

use clap::Args;

/// Default wire radius \[m\] when `--radius` is not given (the 2 mm nitinol wire of the paper).
pub const DEFAULT_RADIUS: f64 = 0.001;

/// Arguments of `ftwire solve`: one configuration from flags, or a JSON Lines batch.
#[derive(Debug, Args)]
#[command(after_help = "Examples:\n  \
    ftwire solve --c 0.214,0.278,0.278 --length 0.82 --a 0,0.2,0.1,-0.5,0.3,0 --json\n  \
    echo '{\"c\":[0.042,0.055,0.055],\"length\":0.63,\"a\":[0,0,0.01,0,0,0]}' | ftwire solve --batch -")]
pub struct SolveArgs {
    /// Stiffnesses C1,C2,C3 [N·m²]: torsion, bending about body y, bending about body z.
    #[arg(
        long,
        value_name = "C1,C2,C3",
        value_delimiter = ',',
        allow_hyphen_values = true,
        required_unless_present = "batch",
        conflicts_with = "batch"
    )]
    pub c: Option<Vec<f64>>,

    /// Wire length L [m].
    #[arg(
        long,
        value_name = "L",
        allow_hyphen_values = true,
        required_unless_present = "batch",
        conflicts_with = "batch"
    )]
    pub length: Option<f64>,

    /// Configuration a = (τ1,τ2,τ3,f1,f2,f3): the wrench on the base gripper, torque [N·m]
    /// first, then force [N], in the base clamp frame.
    #[arg(
        long,
        value_name = "A1,..,A6",
        value_delimiter = ',',
        allow_hyphen_values = true,
        required_unless_present = "batch",
        conflicts_with = "batch"
    )]
    pub a: Option<Vec<f64>>,

    /// Wire radius [m], for self-intersection (default 0.001).
    #[arg(
        long,
        value_name = "R",
        allow_hyphen_values = true,
        conflicts_with = "batch"
    )]
    pub radius: Option<f64>,

    /// Number of shape nodes from t = 0 to t = L (default 64).
    #[arg(long, value_name = "N", conflicts_with = "batch")]
    pub nodes: Option<usize>,

    /// Print one JSON object instead of a human summary.
    #[arg(long)]
    pub json: bool,

    /// Solve a JSON Lines batch from FILE (or stdin for `-`), one object per line:
    /// {"c":[C1,C2,C3],"length":L,"a":[A1,..,A6]} with optional "radius" and "nodes".
    /// Prints one JSON object per line; a bad line prints {"error": "..."} and the batch
    /// goes on.
    #[arg(long, value_name = "FILE|-")]
    pub batch: Option<PathBuf>,
}
