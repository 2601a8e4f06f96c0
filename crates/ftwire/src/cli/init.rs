//! `ftwire init`.

use std::path::PathBuf;

use clap::Args;

/// `ftwire init DIR`: commented example configuration files.
#[derive(Debug, Clone, Args)]
#[command(
    after_help = "Writes wire.toml (--wire), sensor.toml (--sensor), rig.toml (--rig), \
    scene.toml (--scene, `ftwire scene check`) and mounting.toml (--mounting of the log \
    commands), each key commented with its unit, default and allowed range; the full schema is \
    docs/config.md.\n\n\
    Exit codes: 0 written, 2 bad input (a missing parent folder, an example that exists \
    already without --force, a folder that cannot be written)."
)]
pub struct InitArgs {
    /// The folder to write into; created when its parent exists.
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Overwrite example files that exist already.
    #[arg(long)]
    pub force: bool,
}
