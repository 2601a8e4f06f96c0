//! Arguments of `ftwire solve`.

use std::path::PathBuf;

use clap::{ArgGroup, Args};
use ftwire::args::{Count, DensityArgs, JsonArgs, Vec3, Vec6, WireArgs, parse_numbers};
use ftwire_lab::solve::NODES;
use ftwire_rod::DEFAULT_NODES;

/// Arguments of `ftwire solve`: one configuration from flags, or a JSON Lines batch.
#[derive(Debug, Args)]
#[command(
    group(
        ArgGroup::new("single")
            .args([
                "c",
                "length",
                "a",
                "radius",
                "nodes",
                "gravity",
                "density",
                "natural_curvature",
            ])
            .multiple(true)
            .conflicts_with("batch")
    ),
    mut_arg("c", |a| a.required_unless_present("batch")),
    mut_arg("length", |a| a.required_unless_present("batch")),
    after_help = "Examples:\n  \
    ftwire solve --c 0.214,0.278,0.278 --length 0.82 --a 0,0.2,0.1,-0.5,0.3,0 --json\n  \
    ftwire solve --c 0.042,0.055,0.055 --length 0.63 --a 0,0.02,0,0,0.1,0 --gravity 0,0,-9.81\n  \
    echo '{\"c\":[0.042,0.055,0.055],\"length\":0.63,\"a\":[0,0,0.01,0,0,0]}' | ftwire solve --batch -\n\n\
    Exit codes: 0 solved, 1 no answer (the integration diverged), 2 bad input.")]
pub struct SolveArgs {
    /// The wire.
    #[command(flatten)]
    pub wire: WireArgs,

    /// Configuration a = (τ1,τ2,τ3,f1,f2,f3): the wrench on the base gripper, torque [N·m]
    /// first, then force [N], in the base clamp frame.
    #[arg(
        long,
        value_name = "A1,..,A6",
        allow_hyphen_values = true,
        value_parser = parse_numbers::<6>,
        required_unless_present = "batch"
    )]
    pub a: Option<Vec6>,

    /// Gravity [m/s²] in the base clamp frame: GX,GY,GZ. Solves the loaded model with the
    /// wire's weight per length density · π · radius² · gravity (default: no weight).
    #[arg(
        long,
        value_name = "GX,GY,GZ",
        allow_hyphen_values = true,
        value_parser = parse_numbers::<3>
    )]
    pub gravity: Option<Vec3>,

    /// The wire's density, for its weight under --gravity (unused without it).
    #[command(flatten)]
    pub density: DensityArgs,

    /// Natural (rest) strains K1,K2,K3 [1/m] in the body frame: twist rate, then the rest
    /// curvatures about body y and z (default: a straight, untwisted wire).
    #[arg(
        long,
        value_name = "K1,K2,K3",
        allow_hyphen_values = true,
        value_parser = parse_numbers::<3>
    )]
    pub natural_curvature: Option<Vec3>,

    /// Number of shape nodes from t = 0 to t = L, both ends included, 2 to 1000000.
    #[arg(
        long,
        value_name = "N",
        default_value_t = DEFAULT_NODES,
        allow_hyphen_values = true,
        value_parser = Count(NODES)
    )]
    pub nodes: usize,

    /// Output format.
    #[command(flatten)]
    pub output: JsonArgs,

    /// Solve JSON Lines from FILE, or from stdin for `-`, one request per line:
    /// {"c":[C1,C2,C3],"length":L,"a":[A1,..,A6]} with optional "radius" and "nodes". Each line
    /// is answered as soon as it is read, on one flushed line of stdout, so a process can drive
    /// `ftwire solve --batch -` as a service. A bad line gets {"error": ..., "kind": ...,
    /// "line": N} and the batch goes on. Exit code at the end of the input: 0 if every line was
    /// answered, 2 if any line was bad input, else 1 if any had no answer.
    #[arg(long, value_name = "FILE|-")]
    pub batch: Option<PathBuf>,
}
