//! The command-line side of ftwire: the argument groups and value parsers of [`args`]. The
//! commands' output conventions are `ftwire_app::output`, `init`'s example files
//! `ftwire_app::init`; the experiments, tracking in the simulator and what they share live in
//! `ftwire-lab`.
//!
//! - [`args`]: the shared argument groups (wire, poses, seed, output) and the one value parser
//!   per type (vectors accept a leading minus; only finite numbers).

pub mod args;

// The README's library example, compiled and run as a doctest (`cargo test -p ftwire --doc`).
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
struct ReadmeDoctests;
