#![doc = include_str!("../README.md")]

mod error;
mod figure;
pub mod html;

pub use error::ReportError;
pub use figure::{Chart3d, Curve3, LineChart, Series, SeriesKind};
pub use html::{Box3, Gripper3, HtmlReport, IDENTITY, Polyline3, Rotation, Scene3d, Step3};
