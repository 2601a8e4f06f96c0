//! The default `report.md` and `report.html` of a results folder: every run's folder gets both,
//! and a command with a report of its own (`demo`, `reproduce`) writes it before
//! [`crate::results::ResultsFolder::finish`], which then leaves it alone.
//!
//! The default report is the run header, the summary as a table of its values (nested keys
//! joined with dots; long lists shortened), and the folder's figures: linked from
//! `report.md`, embedded in `report.html`, which therefore works alone and offline. Like the
//! summary, both are the same for the same seed: the figures of wall-clock time
//! ([`TIMING_FIGURES`]) stay out of them.
//!
//! Text that can come from the user (a wire's name, a file's path, an error message) goes in
//! as literal text ([`escape_markdown`]): it cannot break a table row, open a heading or a
//! link, or put raw HTML into the page.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use ftwire_report::html::{code_span, escape_markdown};
use ftwire_report::{HtmlReport, ReportError};
use serde_json::Value;

use crate::header::RunHeader;

/// Most rows of the summary table (the rest is in `summary.json`).
pub const MAX_ROWS: usize = 400;

/// Longest list of numbers shown whole in a cell.
const MAX_LIST: usize = 8;

/// The stems of the figures that plot wall-clock time (`experiment identify`'s Fig. 4), drawn
/// from `timings.json`: they differ from run to run, so the reports leave them out.
pub const TIMING_FIGURES: [&str; 1] = ["time_vs_samples"];

/// The PNG files of `dir` but the [`TIMING_FIGURES`], sorted by name.
pub fn pngs(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .filter_map(Result::ok)
        .map(|entry| entry.path())
        .filter(|path| path.extension().is_some_and(|e| e == "png"))
        .filter(|path| {
            path.file_stem()
                .is_none_or(|stem| !TIMING_FIGURES.iter().any(|t| stem == *t))
        })
        .collect();
    files.sort();
    files
}

/// A cell's Markdown for a scalar or a short list (strings as literal text); `None` for what is
/// flattened further.
fn cell(value: &Value) -> Option<String> {
    match value {
        Value::Null => Some("–".to_owned()),
        Value::Bool(b) => Some(b.to_string()),
        Value::Number(n) => Some(match n.as_f64() {
            Some(x) if n.is_f64() => format!("{x:.6}")
                .trim_end_matches('0')
                .trim_end_matches('.')
                .to_owned(),
            _ => n.to_string(),
        }),
        Value::String(s) => Some(escape_markdown(s)),
        Value::Array(items) if items.iter().all(|v| !v.is_object() && !v.is_array()) => {
            if items.len() <= MAX_LIST {
                let parts: Vec<String> = items.iter().filter_map(cell).collect();
                Some(format!("[{}]", parts.join(", ")))
            } else {
                Some(format!("{} values (see summary.json)", items.len()))
            }
        }
        Value::Array(_) | Value::Object(_) => None,
    }
}

/// `(key, value)` rows of `value`, nested keys joined with dots, at most [`MAX_ROWS`]; each value
/// is Markdown (see `cell`), each key as it is.
pub fn rows(value: &Value) -> Vec<(String, String)> {
    fn walk(prefix: &str, value: &Value, out: &mut Vec<(String, String)>) {
        if out.len() >= MAX_ROWS {
            return;
        }
        if let Some(text) = cell(value) {
            out.push((prefix.to_owned(), text));
            return;
        }
        let join = |key: &str| {
            if prefix.is_empty() {
                key.to_owned()
            } else {
                format!("{prefix}.{key}")
            }
        };
        match value {
            Value::Object(map) => {
                for (key, item) in map {
                    walk(&join(key), item, out);
                }
            }
            Value::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    walk(&join(&i.to_string()), item, out);
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk("", value, &mut out);
    out
}

/// Whether `byte` is kept as it is in a figure's link: an ASCII letter or digit, `-_.~`.
fn plain(byte: u8) -> bool {
    byte.is_ascii_alphanumeric() || matches!(byte, b'-' | b'_' | b'.' | b'~')
}

/// The Markdown image of the figure file `name`: `![name](name)`, with a name that holds more
/// than [`plain`] bytes escaped in the text and percent-encoded in the link, so that no space,
/// parenthesis or bracket can end either early.
fn image(name: &str) -> String {
    if name.bytes().all(plain) {
        return format!("![{name}]({name})");
    }
    let mut link = String::with_capacity(name.len());
    for byte in name.bytes() {
        if plain(byte) {
            link.push(char::from(byte));
        } else {
            let _ = write!(link, "%{byte:02X}");
        }
    }
    format!("![{}]({link})", escape_markdown(name))
}

/// `report.md`: the header, the summary's values, and links to `figures` (file names).
pub fn markdown(header: &RunHeader, summary: &Value, figures: &[String]) -> String {
    let mut md = format!(
        "# ftwire {}\n\nftwire {} (revision {}), seed {}. The values are `summary.json`'s, \
         where the run's configuration is recorded too.\n\n",
        header.command,
        header.ftwire_version,
        header.git_revision,
        header
            .seed
            .map_or_else(|| "none".to_owned(), |s| s.to_string()),
    );
    let table = rows(summary);
    md.push_str("## Summary\n\n| key | value |\n| --- | --- |\n");
    for (key, value) in &table {
        let _ = writeln!(md, "| {} | {value} |", code_span(key));
    }
    if table.len() >= MAX_ROWS {
        let _ = writeln!(
            md,
            "\n(The first {MAX_ROWS} values; the rest is in `summary.json`.)"
        );
    }
    if !figures.is_empty() {
        md.push_str("\n## Figures\n\n");
        for name in figures {
            let _ = writeln!(md, "{}\n", image(name));
        }
    }
    md
}

/// `report.html`: `report.md`'s text (without the image links) and the figures embedded.
///
/// # Errors
/// [`ReportError`] when a figure cannot be read.
pub fn html(
    header: &RunHeader,
    summary: &Value,
    figures: &[PathBuf],
) -> Result<String, ReportError> {
    // The page's title is the Markdown's first heading; the rest follows it.
    let md = markdown(header, summary, &[]);
    let body = md.split_once("\n\n").map_or(md.as_str(), |(_, rest)| rest);
    let mut report = HtmlReport::new(format!("ftwire {}", header.command)).with_markdown(body);
    for file in figures {
        let name = file
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        report = report.with_png_file(&name, file)?;
    }
    Ok(report.to_html())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> RunHeader {
        RunHeader::new("experiment passage", Some(3), &serde_json::json!({})).expect("header")
    }

    #[test]
    fn the_summary_table_flattens_nested_keys_and_shortens_long_lists() {
        let summary = serde_json::json!({
            "results": {"closed_loop": {"successes": 50, "attempts": 50}},
            "plan_ms": 1234.5,
            "few": [1, 2, 3],
            "many": (0..20).collect::<Vec<_>>(),
            "pairs": [{"a": 1}, {"a": 2}],
            "name": "a|b\n<b>",
        });
        let rows = rows(&summary);
        let get = |k: &str| {
            rows.iter()
                .find(|(key, _)| key == k)
                .map(|(_, v)| v.clone())
        };
        assert_eq!(get("results.closed_loop.successes").as_deref(), Some("50"));
        assert_eq!(get("plan_ms").as_deref(), Some("1234.5"));
        assert_eq!(get("few").as_deref(), Some("[1, 2, 3]"));
        assert_eq!(get("many").as_deref(), Some("20 values (see summary.json)"));
        assert_eq!(get("pairs.1.a").as_deref(), Some("2"));
        assert_eq!(
            get("name").as_deref(),
            Some("a\\|b \\<b\\>"),
            "no stray table column, line or HTML"
        );
    }

    #[test]
    fn the_table_stops_at_its_row_limit() {
        let big: serde_json::Map<String, Value> = (0..1000)
            .map(|i| (format!("k{i:04}"), Value::from(i)))
            .collect();
        assert_eq!(rows(&Value::Object(big)).len(), MAX_ROWS);
    }

    #[test]
    fn the_markdown_names_the_command_and_links_the_figures() {
        let md = markdown(
            &header(),
            &serde_json::json!({"x": 1}),
            &["a.png".to_owned()],
        );
        assert!(md.starts_with("# ftwire experiment passage"));
        assert!(md.contains("seed 3"));
        assert!(md.contains("| `x` | 1 |"));
        assert!(md.contains("![a.png](a.png)"));
        let md = markdown(
            &header(),
            &serde_json::json!({"outcomes": {"a|b`c": 1}}),
            &[],
        );
        assert!(md.contains("| outcomes.a\\|b\\`c | 1 |"), "{md}");
        assert_eq!(
            image("shape_a b(1)[x].png"),
            "![shape\\_a b(1)\\[x\\].png](shape_a%20b%281%29%5Bx%5D.png)"
        );
        let page = html(&header(), &serde_json::json!({"x": 1}), &[]).expect("a page");
        assert!(page.contains("experiment passage"));
        assert_eq!(page.matches("<h1").count(), 1, "one title");
        assert!(!page.contains("src=\"http"));
    }

    #[test]
    fn timing_figures_are_left_out() {
        let dir = std::env::temp_dir().join(format!("ftwire-report-pngs-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a folder");
        for name in ["time_vs_samples.png", "error.png", "time_vs_samples.svg"] {
            std::fs::write(dir.join(name), "x").expect("writes");
        }
        let names: Vec<PathBuf> = pngs(&dir);
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(names, [dir.join("error.png")]);
    }
}
