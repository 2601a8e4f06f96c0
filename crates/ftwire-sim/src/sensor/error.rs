use ftwire_core::CoreError;
use thiserror::Error;

/// Errors of the sensing and acting models: the F/T sensor, motion capture and robot execution
/// error.
///
/// A configuration error names the offending field and what is allowed; a sensor dropout is an
/// error too, so that a rig can report it the way a real driver would.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SensingError {
    /// A value that must be finite is NaN or infinite.
    #[error(transparent)]
    Core(#[from] CoreError),

    /// A configuration value lies outside its allowed range.
    #[error("{field}[{index}] = {value:?} is out of range; allowed is {}", allowed_range(*min, *max))]
    OutOfRange {
        /// Name of the offending field.
        field: &'static str,
        /// Index of the offending component (0 for scalars).
        index: usize,
        /// The offending value.
        value: f64,
        /// Smallest allowed value.
        min: f64,
        /// Largest allowed value.
        max: f64,
    },

    /// A time constant that is neither in `(0, max]` nor infinite.
    #[error(
        "{field} = {value:?} is out of range; allowed is > 0 and ≤ {max:e} s, or inf (no decay)"
    )]
    TimeConstant {
        /// Name of the offending field.
        field: &'static str,
        /// The offending value \[s\].
        value: f64,
        /// The largest finite value allowed \[s\].
        max: f64,
    },

    /// The gain and cross-talk matrix cannot be inverted reliably.
    #[error(
        "the gain matrix is singular or ill-conditioned (smallest singular value {min_singular_value}); \
         a gain near the identity is expected"
    )]
    SingularGain {
        /// Smallest singular value of the gain matrix.
        min_singular_value: f64,
    },

    /// The deterministic sensor response could not be inverted for one channel.
    #[error(
        "the sensor nonlinearity cannot be inverted on channel {channel} for the reading {value}; \
         the response is monotone only within the rated range"
    )]
    NotInvertible {
        /// Channel index, force first (0..3 force, 3..6 torque).
        channel: usize,
        /// The reading, bias removed, that could not be inverted.
        value: f64,
    },

    /// The F/T sensor missed a sample: the read failed, as a real sensor's does now and then.
    #[error("F/T sensor dropout: no sample at t = {time} s")]
    Dropout {
        /// Time of the missed clock tick \[s\].
        time: f64,
    },

    /// A centreline has too few nodes.
    #[error("the centreline has {nodes} nodes; at least {min} are needed")]
    TooFewNodes {
        /// Number of nodes given.
        nodes: usize,
        /// Smallest allowed number.
        min: usize,
    },

    /// The arc lengths given do not match the nodes one to one.
    #[error("{arc_lengths} arc lengths given for {nodes} centreline nodes; one per node is needed")]
    ArcLengthCount {
        /// Number of nodes.
        nodes: usize,
        /// Number of arc lengths.
        arc_lengths: usize,
    },

    /// The arc lengths of the centreline nodes do not strictly increase.
    #[error(
        "arc length {value} m at node {index} does not exceed {previous} m at the node before; \
         arc lengths must strictly increase"
    )]
    ArcLengthsNotIncreasing {
        /// Index of the offending node.
        index: usize,
        /// Arc length of the node before \[m\].
        previous: f64,
        /// Arc length of the offending node \[m\].
        value: f64,
    },

    /// The cross-section frames given do not match their arc lengths one to one, or there are
    /// none.
    #[error(
        "{frames} cross-section frames given with {arc_lengths} arc lengths; at least one frame \
         and one arc length per frame are needed"
    )]
    SectionFrames {
        /// Number of frames.
        frames: usize,
        /// Number of arc lengths.
        arc_lengths: usize,
    },

    /// Markers with a mounting offset observed without the wire's cross-section frames, which
    /// the offsets turn with.
    #[error(
        "the markers sit off the centreline (mount_offset = {mount_offset} m), so the \
         wire's cross-section frames are needed to place them (observe_mounted)"
    )]
    MountingWithoutFrames {
        /// The markers' mounting offset \[m\].
        mount_offset: f64,
    },

    /// A marker lies beyond the ends of the centreline given.
    #[error(
        "marker {marker} at arc length {arc_length} m lies outside the centreline, which covers \
         {min} ..= {max} m"
    )]
    MarkerOutsideCentreline {
        /// Marker index.
        marker: usize,
        /// Arc length of the marker \[m\].
        arc_length: f64,
        /// Arc length of the first node \[m\].
        min: f64,
        /// Arc length of the last node \[m\].
        max: f64,
    },
}

/// Checks `min <= value <= max` (and finiteness), naming the field in the error.
/// `min ..= max` as a reader wants it: an open end (`f64::MAX`, infinity) is left out, and the
/// smallest positive number reads as `> 0`.
fn allowed_range(min: f64, max: f64) -> String {
    let lower = if min == f64::MIN_POSITIVE {
        "> 0".to_owned()
    } else {
        format!("≥ {min}")
    };
    if max == f64::MAX {
        lower
    } else if max.is_infinite() {
        format!("{lower} (inf allowed)")
    } else {
        format!("{min} ..= {max}")
    }
}

pub(crate) fn in_range(
    field: &'static str,
    index: usize,
    value: f64,
    min: f64,
    max: f64,
) -> Result<(), SensingError> {
    if value.is_finite() && value >= min && value <= max {
        Ok(())
    } else {
        Err(SensingError::OutOfRange {
            field,
            index,
            value,
            min,
            max,
        })
    }
}

/// Checks every component of `values` with [`in_range`].
pub(crate) fn all_in_range(
    field: &'static str,
    values: &[f64],
    min: f64,
    max: f64,
) -> Result<(), SensingError> {
    values
        .iter()
        .enumerate()
        .try_for_each(|(index, &value)| in_range(field, index, value, min, max))
}
