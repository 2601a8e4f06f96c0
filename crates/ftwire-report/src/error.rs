//! The error type of `ftwire-report`.

use std::path::PathBuf;

use thiserror::Error;

/// Errors while writing figures and reports.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ReportError {
    /// A figure could not be drawn or written.
    #[error("cannot draw {path}: {message}")]
    Draw {
        /// The file being written.
        path: PathBuf,
        /// What the drawing library said.
        message: String,
    },
    /// A figure has nothing to draw, or only non-finite points.
    #[error("figure {name:?} has no finite point to draw")]
    Empty {
        /// The figure's title.
        name: String,
    },
}
