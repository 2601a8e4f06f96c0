//! `ftwire init DIR`: writes the commented example files ([`ftwire_app::init`]).

use ftwire_lab::error::LabError;

use crate::cli::init::InitArgs;

/// Writes the examples and names each file written.
pub fn run(args: &InitArgs) -> Result<(), LabError> {
    for path in ftwire_app::init::write_examples(&args.dir, args.force, "--force")? {
        outln!("{}", path.display());
    }
    Ok(())
}
