//! Arguments of `ftwire robot`.

use clap::Args;

/// Arguments of `ftwire robot`.
#[derive(Debug, Args)]
pub struct RobotArgs {}
