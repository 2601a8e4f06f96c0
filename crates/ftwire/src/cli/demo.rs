//! `ftwire demo`.

use clap::Args;
use serde::Serialize;

use ftwire::args::{ResultsArgs, SeedArgs, SimSetupArgs};

/// `ftwire demo`: the whole system at work in the simulator.
#[derive(Debug, Clone, Args, Serialize)]
#[command(
    after_help = "Phases: 1 calibrate the F/T sensor on a known wire; 2 pick up a wire \
    whose stiffness and length are not given and identify them; 3 estimate its shape from F/T \
    against the simulator's truth; 4 plan through the scene's passage; 5 track the plan closed \
    loop with collision detection armed, then once open loop.\n\n\
    Exit codes: 0 done (the summary says how each phase went), 1 a phase found no answer, 2 bad \
    input."
)]
pub struct DemoArgs {
    /// The seed of every random choice.
    #[command(flatten)]
    pub seed: SeedArgs,
    /// The wire to pick up, identify and steer: a preset or a wire file (TOML). The demo is
    /// not told its stiffness, length or weight; only the simulator knows them.
    #[arg(long, value_name = "PRESET|FILE.toml", default_value = ftwire_lab::demo::DEFAULT_WIRE)]
    pub wire: String,
    /// The scene to plan through (`--scene`).
    #[command(flatten)]
    #[serde(flatten)]
    pub scene: crate::cli::groups::SceneArgs,
    /// Execution noise on the second gripper while tracking (`--noise-model`).
    #[command(flatten)]
    #[serde(flatten)]
    pub noise: crate::cli::groups::NoiseModelArgs,
    /// The results folder (`--out`, `--force`) [default: results/demo].
    #[command(flatten)]
    #[serde(flatten)]
    pub results: ResultsArgs,
    /// The simulated F/T sensor and rig (`--sensor`, `--rig`).
    #[command(flatten)]
    #[serde(flatten)]
    pub setup: SimSetupArgs,
}
