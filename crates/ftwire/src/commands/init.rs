//! `ftwire init DIR`: writes the commented example files ([`ftwire::init`]).

use ftwire::error::CliError;

use crate::cli::init::InitArgs;

/// Writes the examples and names each file written.
pub fn run(args: &InitArgs) -> Result<(), CliError> {
    for path in ftwire::init::write_examples(&args.dir, args.force)? {
        println!("{}", path.display());
    }
    Ok(())
}
