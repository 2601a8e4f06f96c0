//! The error type of `ftwire-estimate`.

use ftwire_core::CoreError;
use ftwire_rod::RodError;
use thiserror::Error;

use crate::identify::unidentified::Unidentified;

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
    // Shape fitting and shape estimation (`shape/`).
    /// A marker frame gave a different number of positions than there are marker fractions.
    #[error(
        "{positions} marker positions were given for {fractions} marker fractions; give one \
         position (or None for a dropout) per fraction"
    )]
    MarkerCountMismatch {
        /// Number of marker fractions `s_k / L`.
        fractions: usize,
        /// Number of positions given.
        positions: usize,
    },
    /// A marker's arc-length fraction is not a finite number in `[0, 1]`.
    #[error("marker {marker} has arc-length fraction {fraction}; it must be finite and in [0, 1]")]
    BadMarkerFraction {
        /// Index of the marker.
        marker: usize,
        /// The offending fraction `s_k / L`.
        fraction: f64,
    },
    /// A marker position has a non-finite coordinate.
    #[error(
        "marker {marker} has coordinate {axis} = {value}, which is not finite; leave a marker \
         that was not seen out (None) instead"
    )]
    NonFiniteMarker {
        /// Index of the marker.
        marker: usize,
        /// The coordinate (0 = x, 1 = y, 2 = z).
        axis: usize,
        /// The offending value \[m\].
        value: f64,
    },
    /// Too few markers were observed to fit a shape.
    #[error("only {observed} markers were observed; a shape fit needs at least {min}")]
    TooFewMarkers {
        /// Markers present in the frame.
        observed: usize,
        /// The fewest accepted.
        min: usize,
    },
    /// A shape fitting or estimation setting is out of its range.
    #[error("shape setting {name} = {} is invalid; allowed: {allowed}", ftwire_core::text::Number(*value))]
    BadShapeSetting {
        /// The setting's name.
        name: &'static str,
        /// The offending value.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A polyline given to a shape metric has too few points.
    #[error("polyline {name} has {points} points; at least {min} are needed")]
    TooFewPolylinePoints {
        /// Which polyline.
        name: &'static str,
        /// Its number of points.
        points: usize,
        /// The fewest accepted.
        min: usize,
    },
    /// A point given to a shape metric is not finite.
    #[error("{name}[{index}] has coordinate {axis} = {value}, which is not finite")]
    NonFinitePoint {
        /// Which list of points.
        name: &'static str,
        /// Index of the point.
        index: usize,
        /// The coordinate (0 = x, 1 = y, 2 = z).
        axis: usize,
        /// The offending value \[m\].
        value: f64,
    },
    /// No start of the shape fit could be evaluated (every candidate diverged or was unstable).
    #[error(
        "the shape fit found no usable start in {attempts} attempts (every candidate diverged \
         or was unstable)"
    )]
    NoFitStart {
        /// Candidates tried.
        attempts: usize,
    },

    // Identification of η = (c, L) (`identify`).
    /// A sample given to the identification is not finite.
    #[error(
        "identification sample {index}: {field}[{component}] = {value} is not finite; every \
         component of ã and of b̃ must be a finite number"
    )]
    NonFiniteSample {
        /// Index of the sample (0-based, in the order pushed).
        index: usize,
        /// `"a"` (the measured configuration) or `"b"` (the second gripper's pose).
        field: &'static str,
        /// Component index: `0..6` for `a` (torque first); for `b` `0..3` translation, `3..7`
        /// the quaternion `(i, j, k, w)`.
        component: usize,
        /// The offending value.
        value: f64,
    },
    /// The time of an identification sample is not a time since the tare.
    #[error(
        "identification sample {index}: time = {value} s is not allowed; a sample's time is \
         the seconds since the sensor was tared, finite and >= 0"
    )]
    BadSampleTime {
        /// Index of the sample.
        index: usize,
        /// The offending time \[s\].
        value: f64,
    },
    /// A measured configuration of an identification sample lies outside `A`.
    #[error(
        "identification sample {index}: ã = {a:?} is outside A (a2 = a3 = a5 = a6 = 0, eq. 2); \
         a held, bent wire loads the base gripper with a non-zero bending torque or shear force"
    )]
    SampleOutsideA {
        /// Index of the sample.
        index: usize,
        /// The offending configuration `(τ1, τ2, τ3, f1, f2, f3)`.
        a: [f64; 6],
    },
    /// The grippers of a sample are farther apart than the longest wire searched for.
    #[error(
        "identification sample {index}: the grippers are {chord} m apart, but the search box \
         holds wires of length at most {max_length} m"
    )]
    ChordTooLong {
        /// Index of the sample.
        index: usize,
        /// Distance between the clamp points `|p(b̃)|` \[m\].
        chord: f64,
        /// The longest wire searched for \[m\].
        max_length: f64,
    },
    /// Fewer samples than the identification needs.
    #[error(
        "identification needs at least {required} samples for {unknowns} unknown parameters \
         with the {form} residual, got {samples}"
    )]
    TooFewSamples {
        /// Samples given.
        samples: usize,
        /// Samples needed.
        required: usize,
        /// Free parameters.
        unknowns: usize,
        /// The residual form's name.
        form: &'static str,
    },
    /// More samples than a fit whose samples share the sensor's bias or gain can take
    /// ([`crate::identify::identifier::MAX_SHARED_SAMPLES`]).
    #[error(
        "{samples} samples share the sensor's bias or gain: every pair is correlated, so the fit \
         needs a dense {n}×{n} covariance and time growing as N³; at most {max} samples are \
         allowed (identify --log: --samples {max}, or the sensor's error left out)",
        n = 6 * samples
    )]
    TooManySharedSamples {
        /// Samples given.
        samples: usize,
        /// The most allowed.
        max: usize,
    },
    /// The second gripper did not move enough for the data to tell wires apart.
    #[error(
        "degenerate motion: the second gripper's poses span {spread} noise standard deviations, \
         at least {required} are needed; move the second gripper (see identify::MotionPlan)"
    )]
    DegenerateMotion {
        /// Largest pose change between the first sample and any other, in noise standard
        /// deviations (per component, largest component).
        spread: f64,
        /// The smallest spread accepted.
        required: f64,
    },
    /// An identification setting is out of its range.
    #[error("identification setting {field} = {value} is invalid; allowed: {allowed}")]
    BadIdentifySetting {
        /// The setting's name.
        field: &'static str,
        /// The offending value.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// The data do not identify η; the estimate would not be trustworthy.
    #[error("the data do not identify the wire: {reason}")]
    NotIdentified {
        /// Why.
        reason: Unidentified,
    },

    // F/T calibration network (`calibration/`).
    /// A calibration sample (raw reading or label) has a non-finite component.
    #[error(
        "calibration sample {index}: {field}[{component}] = {value} is not finite; every \
         component must be a finite number"
    )]
    NonFiniteCalibrationSample {
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
    TooFewCalibrationSamples {
        /// Number of samples in the data set.
        samples: usize,
        /// The split that is too small: `"training"` or `"validation"`.
        split: &'static str,
        /// Samples that split received.
        got: usize,
        /// Samples that split needs.
        needed: usize,
    },
    /// A raw reading without gravity, under a mounting whose tool weighs on the sensor.
    #[error(
        "gravity is needed: the mounting's tool (tool_mass = {tool_mass} kg) weighs on the \
         sensor, and its weight is taken out of each raw reading with gravity [m/s², sensor \
         frame]"
    )]
    NoGravity {
        /// The tool's mass \[kg\].
        tool_mass: f64,
    },
    /// A calibration training setting is out of its allowed range.
    #[error(
        "calibration setting {field} = {} is out of range; allowed: {allowed}",
        ftwire_core::text::Number(*value)
    )]
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
    #[error(
        "calibration file: {what}[{index}] = {} is invalid; allowed: {allowed}",
        ftwire_core::text::Number(*.value)
    )]
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

    // The F/T pipeline (`ft/`) and logs (`log`).
    /// A setting is outside its allowed range.
    #[error("{name} = {value} is not allowed: {allowed}")]
    BadSetting {
        /// The setting.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
    /// Too few F/T samples survived screening to average.
    #[error(
        "only {good} good F/T samples of {offered} (needed {needed}): {dropouts} dropouts, \
         {non_finite} non-finite, {saturated} saturated",
        offered = report.offered(),
        dropouts = report.dropouts,
        non_finite = report.non_finite,
        saturated = report.saturated
    )]
    TooFewGoodSamples {
        /// Samples kept.
        good: usize,
        /// Samples needed.
        needed: usize,
        /// What was skipped and why.
        report: Box<crate::ft::report::ScreenReport>,
    },
    /// A calibration produced a non-finite configuration.
    #[error("the calibration produced a non-finite configuration: a[{index}] = {value}")]
    NonFiniteConfiguration {
        /// The component (torque first).
        index: usize,
        /// Its value.
        value: f64,
    },
    /// A line of a log could not be used.
    #[error("log line {line}: {message}")]
    BadLogLine {
        /// The line, 1-based.
        line: usize,
        /// What is wrong, naming the key and the value.
        message: String,
    },
    /// A log holds no record.
    #[error("the log holds no record: nothing to estimate from")]
    EmptyLog,
    /// Reading or writing failed.
    #[error("cannot read {what}: {message}")]
    Io {
        /// What was being read or written.
        what: String,
        /// The system's message.
        message: String,
    },
}
