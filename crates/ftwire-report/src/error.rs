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
    /// A file of a report (a figure to embed, the page) could not be read or written.
    #[error("cannot read or write {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// A figure has nothing to draw, or only non-finite points.
    #[error("figure {name:?} has no finite point to draw")]
    Empty {
        /// The figure's title.
        name: String,
    },
}
