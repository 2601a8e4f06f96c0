//! Figures of ftwire's experiments, as PNG and SVG, rendered on a headless machine, and the
//! self-contained `report.html` of a results folder ([`html`]: tables, the figures embedded,
//! interactive 3-D views of the wire drawn by a vendored three.js).
//!
//! Text is drawn by `ab_glyph` from DejaVu Sans, embedded in the binary (`assets/`, Bitstream
//! Vera license, beside the font), so no system font and no C library is needed.
//!
//! ```
//! use ftwire_report::{LineChart, Series};
//! let chart = LineChart::new("error against samples", "samples", "relative error [%]")
//!     .with_series(Series::line("c2", vec![(2.0, 1.5), (3.0, 0.4), (10.0, 0.1)]));
//! let dir = std::env::temp_dir().join(format!("ftwire-report-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! let files = chart.write(&dir, "error")?;
//! assert_eq!(files.len(), 2); // error.png and error.svg
//! assert!(std::fs::metadata(&files[0])?.len() > 1000);
//! std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod error;
mod figure;
pub mod html;

pub use error::ReportError;
pub use figure::{Chart3d, Curve3, LineChart, Series, SeriesKind};
pub use html::{Box3, Gripper3, HtmlReport, IDENTITY, Polyline3, Rotation, Scene3d, Step3};
