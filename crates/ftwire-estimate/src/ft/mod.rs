//! From raw F/T samples to a configuration `ã ∈ A` (paper §III-A, §IV-A).
//!
//! A raw sample is **force first**, in the sensor frame, about the sensor origin, in the
//! sensor's units, as a real sensor reports it. A configuration is **torque first**, in the base
//! clamp frame, about the clamp point: the wrench the wire exerts on the base gripper. The
//! pipeline ([`FtPipeline`]) runs these stages, in this order:
//!
//! | stage | type | what it does | lag | noise |
//! | --- | --- | --- | --- | --- |
//! | screening | [`Screen`] | drops dropouts, non-finite and saturated samples, and counts them | none | unchanged |
//! | averaging at rest | [`RestAverage`] | the mean of `K` good samples taken while the rig is at rest | `(K − 1) / (2 r)` at rate `r`, plus the `K / r` it takes to collect them | `σ / √K` per channel (white noise) |
//! | taring | [`Tare`] | subtracts the offset measured under a known load | none | adds the tare's own `σ / √K_tare` as a constant offset |
//! | calibration | [`Mounting`] or a learnt [`FtCalibration`] | sensor frame, force first → clamp frame, torque first | none | the map's gain on the noise |
//!
//! The paper's rig is quasi-static: the robot moves, stops, and the wire is at rest while the
//! sensor is read, so a block average over the rest period is an unbiased filter with no lag on
//! the configuration (the configuration does not change while it is averaged). At the
//! simulator's default rate (1 kHz) and noise (0.05 N, 0.002 N·m), 100 samples take 0.1 s and
//! leave 0.005 N and 0.0002 N·m: about 4 % and 0.2 % of the 2 mm nitinol wire's force and
//! torque scales `c/L²` and `c/L`. The measured noise of every average is reported
//! ([`Averaged::std_error`]), so a user sees what the estimate is worth.
//!
//! Samples that cannot be trusted never enter an average silently: a dropout, a non-finite
//! channel or a clipped (saturated) channel is skipped and counted in a [`ScreenReport`], and an
//! average with too few good samples is an error.

mod average;
mod mounting;
mod mounting_spec;
mod pipeline;
pub mod report;
mod screen;
mod tare;

pub use average::{Averaged, RestAverage};
pub use mounting::Mounting;
pub use mounting_spec::{MAX_TOOL_MASS, MountingSpec};
pub use pipeline::{FtCalibration, FtPipeline, Measurement};
pub use report::{ScreenReport, SkipReason};
pub use screen::Screen;
pub use tare::Tare;
