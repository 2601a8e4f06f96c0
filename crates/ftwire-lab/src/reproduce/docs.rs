//! The results page of the documentation (`ftwire reproduce --docs DIR`): `DIR/results.md`
//! and its figures, `DIR/results/<experiment>/*.png`, written from a finished reproduction
//! with the commit, date and machine it was measured on.
//!
//! The page and its folder are ftwire's own: the page starts with [`MARKER`] and the folder
//! holds [`FOLDER_MARK`]. Anything else at those paths is a user's and is replaced only with
//! `--force`; that is checked before any experiment runs.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use crate::error::LabError;
use crate::provenance::Provenance;

/// The first line of a page this command wrote.
pub const MARKER: &str =
    "<!-- Written by `ftwire reproduce --docs`: run it again rather than edit this page. -->";

/// The file that marks the figures folder as written by this command.
pub const FOLDER_MARK: &str = ".ftwire-docs";

/// The page and the figures folder inside `dir`.
fn paths(dir: &Path) -> (PathBuf, PathBuf) {
    (dir.join("results.md"), dir.join("results"))
}

/// Checks that `--docs dir` may be written: `dir` is an existing folder, and its
/// `results.md` and `results/` are absent, ftwire's own, or `force` is given.
///
/// # Errors
/// Bad input naming the path and what would be lost.
pub fn check(dir: &Path, force: bool) -> Result<(), LabError> {
    if !dir.is_dir() {
        return Err(LabError::bad_input(format!(
            "--docs {}: not an existing folder (create it first)",
            dir.display()
        )));
    }
    let (page, figures) = paths(dir);
    if force {
        return Ok(());
    }
    if page.exists() {
        let text = fs::read_to_string(&page).unwrap_or_default();
        if text.lines().next() != Some(MARKER) {
            return Err(LabError::bad_input(format!(
                "--docs {}: {} was not written by ftwire reproduce; move it away or give \
                 --force to replace it",
                dir.display(),
                page.display()
            )));
        }
    }
    if let Ok(meta) = fs::symlink_metadata(&figures) {
        let ours = meta.is_dir()
            && (figures.join(FOLDER_MARK).is_file()
                || fs::read_dir(&figures).is_ok_and(|mut entries| entries.next().is_none()));
        if !ours {
            return Err(LabError::bad_input(format!(
                "--docs {}: {} was not written by ftwire reproduce; move it away or give \
                 --force to replace it",
                dir.display(),
                figures.display()
            )));
        }
    }
    Ok(())
}

/// Writes the page and its figures from the finished reproduction in `results` (one
/// subfolder per experiment `ids`); `report` is its `report.md` and `command` the command
/// line that measured it. Returns the page's path.
///
/// # Errors
/// I/O errors naming the path.
pub fn write(
    dir: &Path,
    results: &Path,
    report: &str,
    ids: &[&str],
    command: &str,
) -> Result<PathBuf, LabError> {
    let (page, figures) = paths(dir);
    let io = |what: &Path| {
        let what = what.display().to_string();
        move |e| LabError::io(format!("--docs: writing {what}"), e)
    };
    // A link is removed, never followed.
    match fs::symlink_metadata(&figures) {
        Ok(meta) if meta.is_dir() => fs::remove_dir_all(&figures).map_err(io(&figures))?,
        Ok(_) => fs::remove_file(&figures).map_err(io(&figures))?,
        Err(_) => {}
    }
    fs::create_dir(&figures).map_err(io(&figures))?;
    fs::write(
        figures.join(FOLDER_MARK),
        "written by ftwire reproduce --docs\n",
    )
    .map_err(io(&figures))?;
    let provenance = Provenance::here();
    let mut md = format!(
        "{MARKER}\n\n# Results\n\nMeasured by `{command}` with {}. Every number below comes \
         from that run; run the command again to measure them on your machine.\n\n",
        provenance.line()
    );
    // The report's own title becomes a section of this page.
    md.push_str(&report.replacen("# ", "## ", 1));
    for id in ids {
        let pngs = crate::report::pngs(&results.join(id));
        if pngs.is_empty() {
            continue;
        }
        let folder = figures.join(id);
        fs::create_dir(&folder).map_err(io(&folder))?;
        let _ = writeln!(md, "\n## Figures of `{id}`\n");
        for png in pngs {
            let Some(name) = png.file_name().map(|n| n.to_string_lossy().into_owned()) else {
                continue;
            };
            fs::copy(&png, folder.join(&name)).map_err(io(&folder.join(&name)))?;
            let _ = writeln!(md, "![{id}: {name}](results/{id}/{name})\n");
        }
    }
    fs::write(&page, md).map_err(io(&page))?;
    Ok(page)
}
