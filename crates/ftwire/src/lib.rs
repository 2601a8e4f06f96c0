//! The library side of the `ftwire` binary: what joins the Kirchhoff model (`ftwire-rod`) and
//! the ground-truth simulator (`ftwire-sim`), and the parts every subcommand shares.
//!
//! This crate is the only one allowed to see both sides of the wall (`ARCHITECTURE.md`); the
//! subcommands and the integration tests share these pieces through it:
//! - [`bridge`]: the Kirchhoff shape as the simulator's initial guess;
//! - [`args`]: the shared argument groups (wire, poses, seed, output) and the one value parser
//!   per type (vectors accept a leading minus; only finite numbers);
//! - [`error`]: the one error type and the exit-code rule (0 success, 1 valid input but no
//!   answer, 2 bad input);
//! - [`output`]: JSON / text / JSON Lines output and the run header;
//! - [`results`]: the results folder of an experiment, replaced whole or not at all;
//! - [`report`]: the default `report.md` and `report.html` of a results folder;
//! - [`csv_table`]: the one CSV writer of the results folders (quoting, formula guard);
//! - [`wire`]: wires by preset name or TOML file;
//! - [`setup`]: the simulated F/T sensor and rig, by preset or TOML file;
//! - [`scene`]: a planning scene's obstacles for the simulator (the same file the planner
//!   reads);
//! - [`init`]: the commented example files of `ftwire init`;
//! - [`experiment`]: what the experiments of paper §IV share (the simulated rig, taring,
//!   measuring).

pub mod args;
pub mod bridge;
pub mod csv_table;
pub mod error;
pub mod experiment;
pub mod init;
pub mod output;
pub mod report;
pub mod results;
pub mod scene;
pub mod setup;
pub mod wire;

// The README's library example, compiled and run as a doctest (`cargo test -p ftwire --doc`).
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
struct ReadmeDoctests;
