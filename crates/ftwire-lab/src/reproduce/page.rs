//! `report.html` of `ftwire reproduce`: `report.md`'s tables as HTML, then each experiment's
//! figures (its folder's PNGs, by name), embedded, so the page works alone and offline.

use std::path::Path;

use ftwire_report::HtmlReport;

use crate::error::LabError;
use crate::results::ResultsFolder;

/// Writes `report.html` beside `report.md`: `markdown` (the report), then the figures of the
/// experiments `ids` from their subfolders of `dir`.
pub(super) fn write(
    folder: &ResultsFolder,
    dir: &Path,
    markdown: &str,
    ids: &[&str],
) -> Result<(), LabError> {
    let mut report = HtmlReport::new("ftwire reproduce").with_markdown(markdown);
    for id in ids {
        let files = crate::report::pngs(&dir.join(id));
        if files.is_empty() {
            continue;
        }
        report = report.with_markdown(&format!("# Figures of `{id}`"));
        for file in files {
            let name = file
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            report = report
                .with_png_file(&format!("{id}/{name}"), &file)
                .map_err(|e| LabError::no_answer(format!("report.html: {e}")))?;
        }
    }
    folder.write("report.html", report.to_html())
}
