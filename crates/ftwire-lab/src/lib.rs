#![doc = include_str!("../README.md")]

pub mod beside;
pub mod calibrate;
pub mod demo;
pub mod equilibrium;
pub mod error;
pub mod experiment;
pub mod goal;
pub mod identify;
pub mod initial_guess;
pub mod paper;
pub mod passage;
pub mod plan;
pub mod reproduce;
pub mod robot;
pub mod scene;
pub mod setup;
pub mod shape;
pub mod solve;
pub mod track;
pub mod tracking;
pub mod wire;

/// The settings files a user gives (wires, mountings, sensor data sheets): `ftwire-app`'s.
pub use ftwire_app::config;
pub use ftwire_app::{LabError, csv_table, header, provenance, report, results};
/// A real rig's recording: `ftwire-logs`, which never sees the simulator.
pub use ftwire_logs as log;
