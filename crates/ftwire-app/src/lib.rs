#![doc = include_str!("../README.md")]

pub mod config;
pub mod csv_table;
pub mod error;
pub mod header;
pub mod init;
pub mod input;
pub mod out_file;
pub mod out_guard;
pub mod output;
pub mod provenance;
pub mod report;
pub mod results;

pub use error::LabError;

/// Where a run reports its progress (one line of text per call: a phase started, a count
/// reached). The `ftwire` binary prints it on stderr; a library user may log it or drop it
/// (`&mut |_| {}`).
pub type Progress<'a> = &'a mut dyn FnMut(&str);
