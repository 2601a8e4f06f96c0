//! Figures render to real PNG and SVG files, text included, on a machine without fonts.

use ftwire_report::{Chart3d, LineChart, ReportError, Series, SeriesKind};

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("ftwire-report-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temporary directory");
    dir
}

#[test]
fn a_line_chart_writes_a_png_and_an_svg_with_its_text() -> Result<(), Box<dyn std::error::Error>> {
    let dir = scratch("line");
    let chart = LineChart::new("relative error against samples", "samples", "error [%]")
        .with_log_y()
        .with_series(
            Series::line_points("c1", vec![(2.0, 3.0), (3.0, 0.5), (10.0, 0.2)])
                .with_error_bars(vec![1.0, 0.2, 0.05]),
        )
        .with_series(Series::points(
            "L",
            vec![(2.0, 0.8), (3.0, f64::NAN), (10.0, 0.01)],
        ));
    let files = chart.write(&dir, "error")?;
    let png = std::fs::read(&files[0])?;
    assert_eq!(&png[1..4], b"PNG");
    let svg = std::fs::read_to_string(&files[1])?;
    assert!(svg.contains("<svg"));
    // The text is drawn: the SVG backend writes it as text elements.
    assert!(
        svg.contains("relative error against samples"),
        "title missing"
    );
    if std::env::var_os("FTWIRE_KEEP_FIGURES").is_none() {
        std::fs::remove_dir_all(&dir)?;
    }
    Ok(())
}

#[test]
fn a_3d_chart_writes_both_files() -> Result<(), Box<dyn std::error::Error>> {
    let dir = scratch("3d");
    let helix: Vec<[f64; 3]> = (0..60)
        .map(|i| {
            let t = i as f64 / 10.0;
            [0.1 * t.cos(), 0.1 * t.sin(), 0.02 * t]
        })
        .collect();
    let shifted: Vec<[f64; 3]> = helix.iter().map(|p| [p[0] + 0.01, p[1], p[2]]).collect();
    let files = Chart3d::new("estimated and true wire")
        .with_curve("estimate", helix, SeriesKind::Line)
        .with_curve("truth", shifted, SeriesKind::LinePoints)
        .write(&dir, "shape")?;
    assert!(std::fs::metadata(&files[0])?.len() > 5_000);
    assert!(std::fs::read_to_string(&files[1])?.contains("estimate"));
    if std::env::var_os("FTWIRE_KEEP_FIGURES").is_none() {
        std::fs::remove_dir_all(&dir)?;
    }
    Ok(())
}

#[test]
fn a_chart_with_nothing_finite_is_an_error_not_a_blank_file() {
    let dir = scratch("empty");
    let chart =
        LineChart::new("nothing", "x", "y").with_series(Series::line("nan", vec![(f64::NAN, 1.0)]));
    assert!(matches!(
        chart.write(&dir, "nothing"),
        Err(ReportError::Empty { .. })
    ));
    assert!(!dir.join("nothing.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
