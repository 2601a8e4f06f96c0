//! What a results folder does with names and with wall-clock time:
//! - a wire whose `name` holds a comma, a quote, a newline, a leading `=` and raw HTML keeps
//!   every row of `identify.csv` at the header's width, its name cell guarded against
//!   spreadsheet formulas (a leading `'`), and `report.md` free of raw HTML and broken table
//!   rows; `report.html` shows the name as text;
//! - the same seed gives a byte-identical `summary.json` (but for the `--out` folder the
//!   header records), `report.md` and `report.html`: every timing is in `timings.json`.

mod cli_support;

use std::fs;
use std::path::Path;

use cli_support::{TempDir, assert_success, ftwire, tiny_calibration};

/// A wire name that breaks naive CSV and Markdown: a formula, a comma, quotes, a newline and
/// raw HTML.
const EVIL_NAME: &str = "=1+2,\"evil\"\n<script>x</script>";

fn text(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

/// Writes a wire file named [`EVIL_NAME`] with the 2 mm nitinol wire's properties.
fn evil_wire(dir: &Path) -> std::path::PathBuf {
    let path = dir.join("evil.toml");
    let name = toml_string(EVIL_NAME);
    fs::write(
        &path,
        format!(
            "name = {name}\nc = [0.042, 0.055, 0.055]\nlength = 0.63\nradius = 0.001\n\
             density = 6450.0\n"
        ),
    )
    .expect("writes the wire file");
    path
}

/// `value` as a TOML basic string.
fn toml_string(value: &str) -> String {
    let escaped = value
        .replace('\\', "\\\\")
        .replace('"', "\\\"")
        .replace('\n', "\\n");
    format!("\"{escaped}\"")
}

/// `experiment identify` at its smallest (one trial, two samples, no gravity, no calibration)
/// into `out`, asserted to succeed.
fn identify(out: &Path, wire: &str, seed: &str) {
    let run = ftwire(&[
        "experiment",
        "identify",
        "--wire",
        wire,
        "--trials",
        "1",
        "--samples",
        "2",
        "--gravity",
        "off",
        "--sensor",
        "undistorted",
        "--pipeline",
        "mounting",
        "--seed",
        seed,
        "--out",
        text(out),
    ]);
    assert_success(&run, "experiment identify");
}

#[test]
fn a_hostile_wire_name_keeps_the_csv_and_the_report_whole() {
    let tmp = TempDir::new("names-evil");
    let wire = evil_wire(&tmp.0);
    let out = tmp.0.join("run");
    identify(&out, text(&wire), "3");

    // Every record of identify.csv has the header's width; the name survives the round trip
    // behind its formula guard.
    let mut reader = csv::ReaderBuilder::new()
        .flexible(true)
        .from_path(out.join("identify.csv"))
        .expect("identify.csv opens");
    let header = reader.headers().expect("a header").clone();
    let wire_column = header
        .iter()
        .position(|h| h == "wire")
        .expect("a wire column");
    let records: Vec<csv::StringRecord> = reader
        .records()
        .collect::<Result<_, _>>()
        .expect("identify.csv parses");
    assert_eq!(records.len(), 1, "one trial, one sample count: {records:?}");
    for record in &records {
        assert_eq!(record.len(), header.len(), "{record:?}");
        assert_eq!(&record[wire_column], format!("'{EVIL_NAME}"));
        // Numbers are not guarded, negative ones included.
        for column in ["rel_err_c1", "rel_err_c2", "rel_err_c3", "rel_err_L"] {
            let k = header.iter().position(|h| h == column).expect("a column");
            assert!(record[k].parse::<f64>().is_ok(), "{column}: {}", &record[k]);
        }
    }

    // report.md: no raw HTML, and the summary table stays one table of two columns.
    let md = fs::read_to_string(out.join("report.md")).expect("report.md");
    assert!(!md.contains("<script>"), "{md}");
    assert!(!md.contains("</script>"), "{md}");
    let table: Vec<&str> = md
        .lines()
        .skip_while(|l| !l.starts_with("| key |"))
        .take_while(|l| !l.is_empty())
        .collect();
    assert!(table.len() > 2, "a summary table in {md}");
    for line in &table {
        let unescaped_pipes = line
            .char_indices()
            .filter(|&(i, c)| c == '|' && !line[..i].ends_with('\\'))
            .count();
        assert_eq!(unescaped_pipes, 3, "a row of two cells: {line}");
    }
    let name_row = table
        .iter()
        .find(|l| l.starts_with("| `wire.name` |"))
        .expect("the wire's name in the table");
    assert!(name_row.contains("script"), "{name_row}");
    let headings: Vec<&str> = md.lines().filter(|l| l.starts_with('#')).collect();
    assert_eq!(
        headings,
        ["# ftwire experiment identify", "## Summary", "## Figures"],
        "no heading from the name"
    );

    // report.html: the name as text, without the Markdown escapes.
    let html = fs::read_to_string(out.join("report.html")).expect("report.html");
    assert!(!html.contains("<script>x"), "no raw HTML from the name");
    assert!(
        html.contains("=1+2,&quot;evil&quot; &lt;script&gt;x&lt;/script&gt;"),
        "the name shown as text"
    );
}

/// Every key of `value`, at any depth.
fn keys(value: &serde_json::Value, out: &mut Vec<String>) {
    match value {
        serde_json::Value::Object(map) => {
            for (key, item) in map {
                out.push(key.clone());
                keys(item, out);
            }
        }
        serde_json::Value::Array(items) => items.iter().for_each(|v| keys(v, out)),
        _ => {}
    }
}

/// Asserts that the summary of `folder` holds no wall-clock key (`*_ms`, `*_us`, `*_s`, with
/// or without `_median`).
fn assert_no_timing_keys(folder: &Path) {
    let summary: serde_json::Value =
        serde_json::from_slice(&fs::read(folder.join("summary.json")).expect("summary.json"))
            .expect("JSON");
    let mut all = Vec::new();
    keys(&summary["summary"], &mut all);
    for key in all {
        let base = key.strip_suffix("_median").unwrap_or(&key);
        assert!(
            !(base.ends_with("_ms") || base.ends_with("_us") || base.ends_with("_s")),
            "a timing in summary.json: {key}"
        );
    }
}

/// Asserts that `file` is byte-identical in the results folders `a` and `b`, once the
/// folder's own path is replaced by the other's.
fn assert_same(a: &Path, b: &Path, file: &str) {
    let first = fs::read_to_string(a.join(file)).expect("the first run's file");
    let second = fs::read_to_string(b.join(file)).expect("the second run's file");
    assert!(
        first.replace(text(a), text(b)) == second,
        "the same seed gives the same {file}:\n{first}\n---\n{second}"
    );
}

#[test]
fn the_same_seed_gives_the_same_identify_summary_and_report() {
    let tmp = TempDir::new("names-same-identify");
    let (a, b) = (tmp.0.join("a"), tmp.0.join("b"));
    identify(&a, "nitinol-2mm-630", "5");
    identify(&b, "nitinol-2mm-630", "5");
    for file in ["summary.json", "report.md", "report.html", "identify.csv"] {
        assert_same(&a, &b, file);
    }
    cli_support::assert_golden_summary("identify-nitinol-2mm-630-seed5", &a);
    assert_no_timing_keys(&a);
    // The timings are kept, apart.
    let timings: serde_json::Value =
        serde_json::from_slice(&fs::read(a.join("timings.json")).expect("timings.json"))
            .expect("JSON");
    let identifications = timings["identifications"]
        .as_array()
        .expect("every identification's time");
    assert_eq!(identifications.len(), 1);
    assert!(identifications[0]["compute_ms"].as_f64().is_some());
    assert!(a.join("time_vs_samples.svg").is_file());
    let md = fs::read_to_string(a.join("report.md")).expect("report.md");
    assert!(!md.contains("time_vs_samples"), "no timing figure in {md}");
}

#[test]
fn the_same_seed_gives_the_same_shape_summary_and_report() {
    let tmp = TempDir::new("names-same-shape");
    let weights = tiny_calibration(&tmp.0);
    let run = |out: &Path| {
        let output = ftwire(&[
            "experiment",
            "shape",
            "--wire",
            "nitinol-2mm-630",
            "--configs",
            "1",
            "--gravity",
            "off",
            "--calibration",
            text(&weights),
            "--seed",
            "2",
            "--out",
            text(out),
        ]);
        assert_success(&output, "experiment shape");
    };
    let (a, b) = (tmp.0.join("a"), tmp.0.join("b"));
    run(&a);
    run(&b);
    for file in ["summary.json", "report.md", "report.html"] {
        assert_same(&a, &b, file);
    }
    cli_support::assert_golden_summary("shape-nitinol-2mm-630-seed2", &a);
    assert_no_timing_keys(&a);
    let timings: serde_json::Value =
        serde_json::from_slice(&fs::read(a.join("timings.json")).expect("timings.json"))
            .expect("JSON");
    assert!(
        timings["estimate_us_median"][0][1].as_f64().is_some(),
        "{timings}"
    );
}
