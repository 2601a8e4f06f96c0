//! Line charts in 2-D and curves in 3-D.

use std::path::{Path, PathBuf};
use std::sync::Once;

use plotters::coord::Shift;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;

use crate::ReportError;

/// DejaVu Sans, registered once as the `sans-serif` family.
static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

fn register_font() {
    REGISTER.call_once(|| {
        // The embedded file is a valid TrueType font; a failure here would show as figures
        // without text, never as a crash.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Size of every figure \[px\].
const SIZE: (u32, u32) = (900, 600);

/// The colours of successive series (colour-blind friendly, Okabe–Ito).
const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Draws one figure twice, into `dir/stem.png` and `dir/stem.svg` (the two drawings are the
/// same generic code; plotters' backends are different types, hence two closures).
fn write_png_and_svg(
    dir: &Path,
    stem: &str,
    png_drawing: impl FnOnce(DrawingArea<BitMapBackend<'_>, Shift>) -> Result<(), String>,
    svg_drawing: impl FnOnce(DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), String>,
) -> Result<Vec<PathBuf>, ReportError> {
    register_font();
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    let failed = |path: &Path| {
        let path = path.to_path_buf();
        move |message| ReportError::Draw { path, message }
    };
    png_drawing(BitMapBackend::new(&png, SIZE).into_drawing_area()).map_err(failed(&png))?;
    svg_drawing(SVGBackend::new(&svg, SIZE).into_drawing_area()).map_err(failed(&svg))?;
    Ok(vec![png, svg])
}

/// A tick label: the value rounded to 7 significant digits, written as briefly as it reads
/// back (so a log axis shows `0.3`, not `0.30000000000000004`).
fn tick(value: &f64) -> String {
    format!("{:.6e}", value)
        .parse::<f64>()
        .map_or_else(|_| value.to_string(), |v| v.to_string())
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesKind {
    /// A polyline through the points.
    Line,
    /// Markers only.
    Points,
    /// A polyline with markers.
    LinePoints,
}

/// One named series of `(x, y)` points, optionally with symmetric error bars.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend name.
    pub name: String,
    /// The points.
    pub points: Vec<(f64, f64)>,
    /// How to draw them.
    pub kind: SeriesKind,
    /// Half-height of an error bar at each point (same length as `points`), if any.
    pub error_bars: Option<Vec<f64>>,
    /// Half-height of a shaded band `y ± h` at each point (same length as `points`), if any:
    /// a continuous error bar such as `±2σ(s)` along a wire.
    pub band: Option<Vec<f64>>,
}

impl Series {
    /// A polyline.
    pub fn line(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            name: name.into(),
            points,
            kind: SeriesKind::Line,
            error_bars: None,
            band: None,
        }
    }

    /// Markers only.
    pub fn points(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            kind: SeriesKind::Points,
            ..Self::line(name, points)
        }
    }

    /// A polyline with markers.
    pub fn line_points(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            kind: SeriesKind::LinePoints,
            ..Self::line(name, points)
        }
    }

    /// With error bars of these half-heights (ignored where the lengths differ).
    #[must_use]
    pub fn with_error_bars(mut self, half_heights: Vec<f64>) -> Self {
        self.error_bars = Some(half_heights);
        self
    }

    /// With a shaded band `y ± h` of these half-heights (ignored where the lengths differ).
    #[must_use]
    pub fn with_band(mut self, half_heights: Vec<f64>) -> Self {
        self.band = Some(half_heights);
        self
    }

    /// The half-heights of the error bars and the band at each point (0 where there are
    /// none): the larger of the two, for the axes' bounds.
    fn half_height(&self, i: usize) -> f64 {
        let at = |v: &Option<Vec<f64>>| {
            v.as_ref()
                .filter(|v| v.len() == self.points.len())
                .and_then(|v| v.get(i))
                .copied()
                .filter(|e| e.is_finite())
                .map_or(0.0, f64::abs)
        };
        at(&self.error_bars).max(at(&self.band))
    }

    fn finite_points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
    }
}

/// A 2-D chart of one or more series.
#[derive(Debug, Clone, PartialEq)]
pub struct LineChart {
    /// Title.
    pub title: String,
    /// Label of the x axis, with its unit.
    pub x_label: String,
    /// Label of the y axis, with its unit.
    pub y_label: String,
    /// Logarithmic y axis (non-positive values are left out).
    pub log_y: bool,
    /// The series.
    pub series: Vec<Series>,
}

impl LineChart {
    /// An empty chart.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            log_y: false,
            series: Vec::new(),
        }
    }

    /// Adds a series.
    #[must_use]
    pub fn with_series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// With a logarithmic y axis.
    #[must_use]
    pub fn with_log_y(mut self) -> Self {
        self.log_y = true;
        self
    }

    /// Writes `dir/stem.png` and `dir/stem.svg`; returns their paths.
    ///
    /// # Errors
    /// [`ReportError::Empty`] when no series has a drawable point; [`ReportError::Draw`] when a
    /// file cannot be written.
    pub fn write(&self, dir: &Path, stem: &str) -> Result<Vec<PathBuf>, ReportError> {
        let bounds = self.bounds().ok_or_else(|| ReportError::Empty {
            name: self.title.clone(),
        })?;
        write_png_and_svg(
            dir,
            stem,
            |area| self.draw(area, bounds),
            |area| self.draw(area, bounds),
        )
    }

    /// `(x_min, x_max, y_min, y_max)` over the drawable points, padded, or `None`.
    fn bounds(&self) -> Option<(f64, f64, f64, f64)> {
        let mut b = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for s in &self.series {
            for (i, (x, y)) in s.points.iter().copied().enumerate() {
                if !(x.is_finite() && y.is_finite()) || (self.log_y && y <= 0.0) {
                    continue;
                }
                let e = s.half_height(i);
                let low = if self.log_y && y - e <= 0.0 { y } else { y - e };
                b = (b.0.min(x), b.1.max(x), b.2.min(low), b.3.max(y + e));
            }
        }
        if !(b.0.is_finite() && b.2.is_finite()) {
            return None;
        }
        let pad = |lo: f64, hi: f64| {
            let span = hi - lo;
            let margin = if span > 0.0 {
                0.05 * span
            } else {
                0.5 * lo.abs().max(1.0)
            };
            (lo - margin, hi + margin)
        };
        let (x0, x1) = pad(b.0, b.1);
        let (y0, y1) = if self.log_y {
            let (lo, hi) = (b.2, b.3);
            if hi > lo {
                (lo / 1.2, hi * 1.2)
            } else {
                (lo / 2.0, hi * 2.0)
            }
        } else {
            pad(b.2, b.3)
        };
        Some((x0, x1, y0, y1))
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
        (x0, x1, y0, y1): (f64, f64, f64, f64),
    ) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(&self.title, ("sans-serif", 24))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(72);
        if self.log_y {
            let chart = builder
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .map_err(|e| e.to_string())?;
            self.draw_series(chart)?;
        } else {
            let chart = builder
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| e.to_string())?;
            self.draw_series(chart)?;
        }
        root.present().map_err(|e| e.to_string())
    }

    fn draw_series<'a, DB, Y>(
        &self,
        mut chart: ChartContext<'a, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, Y>>,
    ) -> Result<(), String>
    where
        DB: DrawingBackend + 'a,
        DB::ErrorType: 'static,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(|e| e.to_string())?;
        let positive = |(_, y): &(f64, f64)| !self.log_y || *y > 0.0;
        for (i, s) in self.series.iter().enumerate() {
            let c = colour(i);
            let points: Vec<(f64, f64)> = s.finite_points().filter(positive).collect();
            let legend = move |(x, y): (i32, i32)| {
                PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(3))
            };
            if let Some(band) = s.band.as_ref().filter(|b| b.len() == s.points.len()) {
                // The band's outline: up along y + h, back along y − h (finite points only;
                // on a log axis the lower edge stays above zero).
                let edge: Vec<(f64, f64, f64)> = s
                    .points
                    .iter()
                    .zip(band)
                    .filter(|((x, y), h)| x.is_finite() && y.is_finite() && h.is_finite())
                    .map(|(&(x, y), &h)| {
                        let low = if self.log_y && y - h.abs() <= 0.0 {
                            y
                        } else {
                            y - h.abs()
                        };
                        (x, low, y + h.abs())
                    })
                    .filter(|&(_, low, _)| positive(&(0.0, low)))
                    .collect();
                let outline: Vec<(f64, f64)> = edge
                    .iter()
                    .map(|&(x, _, high)| (x, high))
                    .chain(edge.iter().rev().map(|&(x, low, _)| (x, low)))
                    .collect();
                if outline.len() >= 4 {
                    chart
                        .draw_series(std::iter::once(Polygon::new(outline, c.mix(0.2).filled())))
                        .map_err(|e| e.to_string())?;
                }
            }
            if matches!(s.kind, SeriesKind::Line | SeriesKind::LinePoints) {
                chart
                    .draw_series(LineSeries::new(points.iter().copied(), c.stroke_width(2)))
                    .map_err(|e| e.to_string())?
                    .label(&s.name)
                    .legend(legend);
            }
            if matches!(s.kind, SeriesKind::Points | SeriesKind::LinePoints) {
                let drawn = chart
                    .draw_series(points.iter().map(|&p| Circle::new(p, 4, c.filled())))
                    .map_err(|e| e.to_string())?;
                if s.kind == SeriesKind::Points {
                    drawn.label(&s.name).legend(legend);
                }
            }
            if let Some(errors) = s.error_bars.as_ref().filter(|e| e.len() == s.points.len()) {
                let bars = s.points.iter().zip(errors).filter_map(|(&(x, y), &e)| {
                    let ok = x.is_finite() && y.is_finite() && e.is_finite();
                    let low = if self.log_y && y - e <= 0.0 {
                        y
                    } else {
                        y - e.abs()
                    };
                    (ok && positive(&(x, y))).then(|| {
                        PathElement::new(vec![(x, low), (x, y + e.abs())], c.stroke_width(1))
                    })
                });
                chart.draw_series(bars).map_err(|e| e.to_string())?;
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font(("sans-serif", 16))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())
    }
}

/// One named curve in 3-D \[m\].
#[derive(Debug, Clone, PartialEq)]
pub struct Curve3 {
    /// Legend name.
    pub name: String,
    /// The points.
    pub points: Vec<[f64; 3]>,
    /// How to draw them.
    pub kind: SeriesKind,
    /// The radius of a tube around the curve at each point \[m\] (same length as `points`),
    /// if any: drawn as rings about the curve's tangent, such as `2σ(s)` along a wire.
    pub tube: Option<Vec<f64>>,
}

impl Curve3 {
    /// The rings of its tube ([`tube_rings`]); none without a tube.
    fn rings(&self) -> Vec<Vec<(f64, f64, f64)>> {
        self.tube
            .as_ref()
            .map_or_else(Vec::new, |radius| tube_rings(&self.points, radius))
    }
}

/// Rings of a tube drawn at most, spread evenly along the curve.
const TUBE_RINGS: usize = 40;

/// Segments of one ring of a tube.
const RING_SEGMENTS: usize = 24;

/// The rings of a tube of `radius` about the polyline `points` (same lengths): at most
/// [`TUBE_RINGS`] closed loops of [`RING_SEGMENTS`] segments, each about the local tangent
/// (central difference), skipping points that are not finite or have no tangent.
fn tube_rings(points: &[[f64; 3]], radius: &[f64]) -> Vec<Vec<(f64, f64, f64)>> {
    let n = points.len();
    if n < 2 || radius.len() != n {
        return Vec::new();
    }
    let every = n.div_ceil(TUBE_RINGS).max(1);
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let unit = |a: [f64; 3]| {
        let norm = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        (norm > 0.0 && norm.is_finite()).then(|| a.map(|v| v / norm))
    };
    (0..n)
        .step_by(every)
        .filter_map(|i| {
            let (p, r) = (points[i], radius[i]);
            let t = unit(sub(points[(i + 1).min(n - 1)], points[i.saturating_sub(1)]))?;
            if !(r.is_finite() && r > 0.0 && p.iter().all(|v| v.is_finite())) {
                return None;
            }
            // Any axis not along t gives the ring's two directions.
            let helper = if t[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            };
            let u = unit(cross(t, helper))?;
            let v = cross(t, u);
            Some(
                (0..=RING_SEGMENTS)
                    .map(|k| {
                        let phi = std::f64::consts::TAU * k as f64 / RING_SEGMENTS as f64;
                        let (sin, cos) = phi.sin_cos();
                        let at = |j: usize| p[j] + r * (cos * u[j] + sin * v[j]);
                        (at(0), at(1), at(2))
                    })
                    .collect(),
            )
        })
        .collect()
}

/// A 3-D view of curves (e.g. an estimated and a true wire), with equal scales on every axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart3d {
    /// Title.
    pub title: String,
    /// The curves.
    pub curves: Vec<Curve3>,
}

impl Chart3d {
    /// An empty 3-D chart.
    pub fn new(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            curves: Vec::new(),
        }
    }

    /// Adds a curve.
    #[must_use]
    pub fn with_curve(
        mut self,
        name: impl Into<String>,
        points: Vec<[f64; 3]>,
        kind: SeriesKind,
    ) -> Self {
        self.curves.push(Curve3 {
            name: name.into(),
            points,
            kind,
            tube: None,
        });
        self
    }

    /// Adds a curve with a tube of `radius` \[m\] at each point (ignored where the lengths
    /// differ), e.g. an estimated wire with its `2σ(s)`.
    ///
    /// ```
    /// use ftwire_report::{Chart3d, SeriesKind};
    /// let wire = vec![[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.2, 0.0, 0.01]];
    /// let chart = Chart3d::new("a wire").with_tube("estimate ± 2σ", wire, vec![0.0, 0.002, 0.004], SeriesKind::Line);
    /// assert_eq!(chart.curves[0].tube.as_ref().map(Vec::len), Some(3));
    /// ```
    #[must_use]
    pub fn with_tube(
        mut self,
        name: impl Into<String>,
        points: Vec<[f64; 3]>,
        radius: Vec<f64>,
        kind: SeriesKind,
    ) -> Self {
        self.curves.push(Curve3 {
            name: name.into(),
            points,
            kind,
            tube: Some(radius),
        });
        self
    }

    /// Writes `dir/stem.png` and `dir/stem.svg`; returns their paths.
    ///
    /// # Errors
    /// As [`LineChart::write`].
    pub fn write(&self, dir: &Path, stem: &str) -> Result<Vec<PathBuf>, ReportError> {
        let cube = self.cube().ok_or_else(|| ReportError::Empty {
            name: self.title.clone(),
        })?;
        write_png_and_svg(
            dir,
            stem,
            |area| self.draw(area, cube),
            |area| self.draw(area, cube),
        )
    }

    /// A cube `(centre, half side)` around every finite point, so the axes share one scale.
    fn cube(&self) -> Option<([f64; 3], f64)> {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let ring_points: Vec<[f64; 3]> = self
            .curves
            .iter()
            .flat_map(Curve3::rings)
            .flatten()
            .map(|(x, y, z)| [x, y, z])
            .collect();
        for p in self
            .curves
            .iter()
            .flat_map(|c| &c.points)
            .chain(&ring_points)
        {
            if p.iter().all(|v| v.is_finite()) {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        if !lo[0].is_finite() {
            return None;
        }
        let centre = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
        let half = (0..3).map(|k| 0.5 * (hi[k] - lo[k])).fold(0.0, f64::max);
        Some((centre, 1.05 * half.max(1e-3)))
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
        (c, h): ([f64; 3], f64),
    ) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let range = |k: usize| (c[k] - h)..(c[k] + h);
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, ("sans-serif", 24))
            .margin(16)
            .build_cartesian_3d(range(0), range(1), range(2))
            .map_err(|e| e.to_string())?;
        chart.with_projection(|mut p| {
            p.yaw = 0.6;
            p.pitch = 0.35;
            p.scale = 0.85;
            p.into_matrix()
        });
        chart
            .configure_axes()
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| e.to_string())?;
        for (i, curve) in self.curves.iter().enumerate() {
            let col = colour(i);
            let points: Vec<(f64, f64, f64)> = curve
                .points
                .iter()
                .filter(|p| p.iter().all(|v| v.is_finite()))
                .map(|p| (p[0], p[1], p[2]))
                .collect();
            let legend = move |(x, y): (i32, i32)| {
                PathElement::new(vec![(x, y), (x + 24, y)], col.stroke_width(3))
            };
            for ring in curve.rings() {
                chart
                    .draw_series(LineSeries::new(ring, col.mix(0.35).stroke_width(1)))
                    .map_err(|e| e.to_string())?;
            }
            if matches!(curve.kind, SeriesKind::Line | SeriesKind::LinePoints) {
                chart
                    .draw_series(LineSeries::new(points.iter().copied(), col.stroke_width(2)))
                    .map_err(|e| e.to_string())?
                    .label(&curve.name)
                    .legend(legend);
            }
            if matches!(curve.kind, SeriesKind::Points | SeriesKind::LinePoints) {
                let drawn = chart
                    .draw_series(points.iter().map(|&p| Circle::new(p, 4, col.filled())))
                    .map_err(|e| e.to_string())?;
                if curve.kind == SeriesKind::Points {
                    drawn.label(&curve.name).legend(legend);
                }
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font(("sans-serif", 16))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::tick;

    #[test]
    fn tick_labels_drop_float_noise_and_keep_real_digits() {
        assert_eq!(tick(&0.300_000_000_000_000_04), "0.3");
        assert_eq!(tick(&1234.5), "1234.5");
        assert_eq!(tick(&-0.0125), "-0.0125");
        assert_eq!(tick(&1e-9), "0.000000001");
    }
}
