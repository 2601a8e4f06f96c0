//! Arguments of `ftwire solve`.

use clap::Args;

/// Arguments of `ftwire solve`.
#[derive(Debug, Args)]
pub struct SolveArgs {}
