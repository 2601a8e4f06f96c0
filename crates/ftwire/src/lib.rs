//! The command-line side of ftwire: argument groups and value parsers, output, `init`'s
//! example files, and tracking in the simulator. The experiments and what they share live in
//! `ftwire-lab`.
//!
//! - [`args`]: the shared argument groups (wire, poses, seed, output) and the one value parser
//!   per type (vectors accept a leading minus; only finite numbers);
//! - [`output`]: JSON / text / JSON Lines output;
//! - [`init`]: the commented example files of `ftwire init`;
//! - [`experiment`]: planning in a scene and tracking the plan in the simulator.

pub mod args;
pub mod experiment;
pub mod init;
pub mod output;

// The README's library example, compiled and run as a doctest (`cargo test -p ftwire --doc`).
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
struct ReadmeDoctests;
