//! Writes a `report.html` from synthetic data (an arc that bends step by step past a box, with
//! its grippers, and a line chart as an embedded PNG): the page that `.ci/browser-test` opens
//! in headless Chromium when it is not given one.
//!
//! `cargo run --release -p ftwire-report --example html_report -- OUT_DIR`

use std::error::Error;
use std::path::PathBuf;

use ftwire_report::{HtmlReport, IDENTITY, LineChart, Scene3d, Series, Step3};

/// Points of an arc of length 0.4 m from the origin along x, bent by `bend` \[rad\] about y.
fn arc(bend: f64, lift: f64) -> Vec<[f64; 3]> {
    (0..=40)
        .map(|i| {
            let s = 0.4 * f64::from(i) / 40.0;
            if bend.abs() < 1e-9 {
                return [s, 0.0, lift * s];
            }
            let r = 0.4 / bend;
            let phi = s / r;
            [r * phi.sin(), 0.0, r * (1.0 - phi.cos()) + lift * s]
        })
        .collect()
}

fn main() -> Result<(), Box<dyn Error>> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .ok_or("usage: html_report OUT_DIR (an existing folder)")?,
    );
    let chart = LineChart::new("tip height against step", "step", "height [m]").with_series(
        Series::line_points(
            "truth",
            (0..8)
                .map(|k| (f64::from(k), 0.05 * f64::from(k)))
                .collect(),
        ),
    );
    let files = chart.write(&out, "synthetic")?;
    let mut view = Scene3d::new("synthetic wire past a box").with_box(
        "box",
        [0.25, 0.0, 0.0],
        [0.03, 0.1, 0.05],
        IDENTITY,
    );
    for k in 0..8 {
        let bend = 0.25 * f64::from(k);
        let truth = arc(bend, 0.0);
        let estimate = arc(bend * 1.05, 0.02);
        let tip = truth.last().copied().unwrap_or([0.0; 3]);
        view = view.with_step(
            Step3::new(format!("bend {bend:.2} rad"))
                .with_polyline("truth", truth)
                .with_polyline("estimate", estimate)
                .with_gripper("base", [0.0; 3], Some(IDENTITY))
                .with_gripper("tip", tip, None),
        );
    }
    let mut report = HtmlReport::new("ftwire-report: synthetic report").with_markdown(
        "## Numbers\n\n| step | bend [rad] |\n| --- | --- |\n| 1 | 0.00 |\n| 8 | 1.75 |\n",
    );
    if let Some(png) = files.first() {
        report = report.with_png_file("tip height (synthetic)", png)?;
    }
    let page = out.join("report.html");
    report.with_scene(view).write(&page)?;
    println!("{}", page.display());
    Ok(())
}
