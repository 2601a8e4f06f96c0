//! The error type of `ftwire-estimate`.

use ftwire_core::CoreError;
use ftwire_rod::RodError;
use thiserror::Error;

/// Errors of the estimators.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum EstimateError {
    /// Invalid shared data (for example non-finite or non-positive wire parameters).
    #[error(transparent)]
    Core(#[from] CoreError),
    /// The wire model could not be solved.
    #[error(transparent)]
    Model(#[from] RodError),
    /// A calibration sample (raw reading or label) has a non-finite component.
    #[error(
        "calibration sample {index}: {field}[{component}] = {value} is not finite; every \
         component must be a finite number"
    )]
    NonFiniteSample {
        /// Index of the offending sample in the data set.
        index: usize,
        /// `"raw"` (the F/T reading) or `"label"` (the configuration `a`).
        field: &'static str,
        /// Index of the offending component (0–5).
        component: usize,
        /// The offending value.
        value: f64,
    },
    /// The raw readings and the labels of a calibration data set do not pair one to one.
    #[error(
        "calibration data has {raw} raw readings but {labels} labels; there must be one label \
         per reading (the first unpaired sample is index {first_unpaired})"
    )]
    SampleCountMismatch {
        /// Number of raw readings.
        raw: usize,
        /// Number of labels.
        labels: usize,
        /// Index of the first sample that has no partner (`min(raw, labels)`).
        first_unpaired: usize,
    },
    /// A calibration data set is too small for the requested split.
    #[error(
        "calibration data has {samples} samples, which gives the {split} split {got}; it needs \
         at least {needed}"
    )]
    TooFewSamples {
        /// Number of samples in the data set.
        samples: usize,
        /// The split that is too small: `"training"` or `"validation"`.
        split: &'static str,
        /// Samples that split received.
        got: usize,
        /// Samples that split needs.
        needed: usize,
    },
    /// A calibration training setting is out of its allowed range.
    #[error("calibration setting {field} = {value} is out of range; allowed: {allowed}")]
    InvalidSetting {
        /// Name of the setting.
        field: &'static str,
        /// The offending value.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A calibration weights file could not be read or written.
    #[error("calibration file {path}: {kind}: {message}")]
    CalibrationIo {
        /// The file.
        path: std::path::PathBuf,
        /// What kind of I/O failure.
        kind: std::io::ErrorKind,
        /// The operating system's message.
        message: String,
    },
    /// A calibration weights file is not valid JSON of the documented format.
    #[error(
        "calibration file is not a valid calibration (line {line}, column {column}): {message}"
    )]
    CalibrationSyntax {
        /// Line of the error (1-based; 0 when unknown).
        line: usize,
        /// Column of the error (1-based; 0 when unknown).
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// A calibration weights file has a format version this build cannot read.
    #[error("calibration file has format version {found}; this build reads version {supported}")]
    CalibrationVersion {
        /// The version in the file.
        found: u32,
        /// The version this build reads.
        supported: u32,
    },
    /// A calibration weights file's arrays disagree with its declared architecture.
    #[error("calibration file: {what} has {found} entries, but the architecture needs {expected}")]
    CalibrationShape {
        /// Which array (for example `layers[1].weights[3]`).
        what: String,
        /// Entries the architecture needs.
        expected: usize,
        /// Entries found.
        found: usize,
    },
    /// A calibration weights file holds a non-finite or out-of-range number.
    #[error("calibration file: {what}[{index}] = {value} is invalid; allowed: {allowed}")]
    CalibrationValue {
        /// Which array (for example `input_normaliser.std`).
        what: String,
        /// Index within that array.
        index: usize,
        /// The offending value.
        value: f64,
        /// What is allowed, in words.
        allowed: &'static str,
    },
}
