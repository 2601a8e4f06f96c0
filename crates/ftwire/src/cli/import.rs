//! Arguments of `ftwire import <format>`: recordings made elsewhere to ftwire's log.

use clap::{Args, Subcommand};

/// `ftwire import <format>`.
#[derive(Debug, Clone, Args)]
pub struct ImportArgs {
    /// The format of the recording.
    #[command(subcommand)]
    pub format: ImportFormat,
}

/// The formats.
#[derive(Debug, Clone, Subcommand)]
pub enum ImportFormat {
    /// A ROS 2 bag in MCAP storage.
    Mcap,
}
