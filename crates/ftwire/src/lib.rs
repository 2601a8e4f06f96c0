//! The command-line side of ftwire: argument groups and value parsers, and `init`'s example
//! files. The commands' output conventions are `ftwire_app::output`. The experiments, tracking in the simulator and what they share live in
//! `ftwire-lab`.
//!
//! - [`args`]: the shared argument groups (wire, poses, seed, output) and the one value parser
//!   per type (vectors accept a leading minus; only finite numbers);
//! - [`init`]: the commented example files of `ftwire init`.

pub mod args;
pub mod init;

// The README's library example, compiled and run as a doctest (`cargo test -p ftwire --doc`).
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
struct ReadmeDoctests;
