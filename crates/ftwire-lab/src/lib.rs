//! ftwire's laboratory: the experiments of paper §IV run against the ground-truth simulator,
//! and what they share. This is the one library crate that sees both sides of the wall
//! (`ARCHITECTURE.md`): the Kirchhoff model and its estimators on one side, the simulator that
//! plays the robot on the other. The `ftwire` binary, the Python bindings and the ROS 2 bridge
//! call it; it has no command-line parsing and prints nothing.
//!
//! - [`error`]: the one error type, sorted by who must act (bad input, no answer, I/O), and
//!   the exit code of each kind;
//! - [`header`]: the run header of a results folder (version, revision, seed, configuration);
//! - [`results`]: the results folder of a run, replaced whole or not at all, never a folder
//!   ftwire did not write;
//! - [`report`]: the default `report.md` and `report.html` of a results folder;
//! - [`paper`]: the paper's published tables; [`beside`]: ours beside them, from a
//!   reproduction's summaries;
//! - [`csv_table`]: the one CSV writer of the results folders (quoting, formula guard);
//! - [`wire`]: wires by preset name or TOML file;
//! - [`setup`]: the simulated F/T sensor and rig, by preset or TOML file;
//! - [`scene`]: a planning scene's obstacles for the simulator (the same file the planner
//!   reads);
//! - [`initial_guess`]: the Kirchhoff shape as the simulator's initial guess;
//! - [`provenance`]: the commit, date and machine of a run, for results pages;
//! - [`experiment`]: what the experiments share (gravity, the estimators' model, the simulated
//!   rig, taring and measuring, the learnt calibration, summary statistics);
//! - [`calibrate`]: the calibration experiment (§IV-A);
//! - [`identify`]: the identification experiment (Table I, Figs. 3–4), and the one
//!   identification that `ftwire identify --log` and the demo share with it;
//! - [`shape`]: the shape experiment (Table II, Fig. 5);
//! - [`goal`]: the goal experiment (Table III, Figs. 6–7, collision detection);
//! - [`track`]: the tracking experiment (Table IV, Figs. 8–9);
//! - [`passage`]: the passage experiment (§IV-E, Figs. 11–13);
//! - [`tracking`]: tracking a plan in the simulator (the rig placed in a scene, the
//!   `ftwire_control::PathTracker` with the simulator's truth as its observer, open and closed
//!   loop, each attempt scored on that truth) and the roll-out settings, shared by the demo,
//!   [`track`] and [`passage`];

pub mod beside;
pub mod calibrate;
pub mod csv_table;
pub mod error;
pub mod experiment;
pub mod goal;
pub mod header;
pub mod identify;
pub mod initial_guess;
pub mod paper;
pub mod passage;
pub mod provenance;
pub mod report;
pub mod results;
pub mod scene;
pub mod setup;
pub mod shape;
pub mod track;
pub mod tracking;
pub mod wire;

pub use error::LabError;
