//! `ftwire import <format>`.

use ftwire_lab::error::LabError;

use crate::cli::import::{ImportArgs, ImportFormat};

/// Converts the recording to ftwire's JSON Lines log.
pub fn run(args: ImportArgs) -> Result<(), LabError> {
    match args.format {
        ImportFormat::Mcap => Err(LabError::bad_input("not built yet")),
    }
}
