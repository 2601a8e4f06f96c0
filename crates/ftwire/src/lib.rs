//! The command-line side of ftwire: argument groups and value parsers, output, and `init`'s
//! example files. The experiments, tracking in the simulator and what they share live in
//! `ftwire-lab`.
//!
//! - [`args`]: the shared argument groups (wire, poses, seed, output) and the one value parser
//!   per type (vectors accept a leading minus; only finite numbers);
//! - [`output`]: JSON / text / JSON Lines output;
//! - [`init`]: the commented example files of `ftwire init`.

pub mod args;
pub mod init;
pub mod output;

// The README's library example, compiled and run as a doctest (`cargo test -p ftwire --doc`).
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
struct ReadmeDoctests;
