#![doc = include_str!("../README.md")]
//!
//! # The one path of a reading
//!
//! ```text
//! Reading (time, raw | ã, gravity)
//!   └─ Stream::push: tare, window ──► RawMap::a_tilde: tool weight, calibration | mounting ──► ã
//!        └─ Measurement::solve(ã, Σ_ã): shape at the points, stability, σ(s)   (pure, parallel)
//!             └─ Stream::flag: confident | not_stable | jump | no_shape          (in order)
//!                  └─ ShapeRecord: the one record every front end prints, writes, publishes
//! ```

pub mod datasheet;
pub mod error;
pub mod map;
pub mod model;
pub mod reading;
pub mod record;
pub mod shape;
pub mod stream;

pub use datasheet::DataSheet;
pub use error::RigError;
pub use map::RawMap;
pub use model::{ModelKind, WireBody, WireModelChoice};
pub use reading::Reading;
pub use record::ShapeRecord;
pub use shape::{Measurement, MeasurementParams, ShapeConfidence, Solved};
pub use stream::{Stream, StreamParams};
