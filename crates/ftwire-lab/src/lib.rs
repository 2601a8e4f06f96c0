#![doc = include_str!("../README.md")]

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
pub mod plan;
pub mod provenance;
pub mod report;
pub mod reproduce;
pub mod results;
pub mod scene;
pub mod setup;
pub mod shape;
pub mod track;
pub mod tracking;
pub mod wire;

pub use error::LabError;
