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
pub mod log;
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

pub use ftwire_app::{LabError, csv_table, header, provenance, report, results};
