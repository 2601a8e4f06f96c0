//! The results folder of an experiment: `summary.json` (with the [`RunHeader`]), the default
//! `report.md` and `report.html` ([`crate::report`]) unless the run wrote its own, and other
//! files, written whole into a temporary sibling folder and renamed into place at the end, so
//! that an existing results folder is never left half-overwritten.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use serde::Serialize;

use crate::error::CliError;
use crate::output::RunHeader;

/// A results folder being written. Files go to a temporary sibling of the target; [`finish`]
/// writes `summary.json` and renames the folder into place. Dropped unfinished, the temporary
/// folder is removed and the target is untouched.
///
/// [`finish`]: ResultsFolder::finish
#[derive(Debug)]
pub struct ResultsFolder {
    target: PathBuf,
    staging: PathBuf,
    finished: bool,
}

/// `summary.json`: the run header, then the command's summary.
#[derive(Serialize)]
struct Summary<'a, S: Serialize> {
    header: &'a RunHeader,
    summary: &'a S,
}

/// A name no other writer uses at the same time: the process id and the clock.
fn unique_suffix() -> String {
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    format!("{}-{nanos}", std::process::id())
}

impl ResultsFolder {
    /// Starts writing `--out` when given, else `results/<id>` in the working folder
    /// (creating `results/` when it is missing); see [`ResultsFolder::create`].
    ///
    /// # Errors
    /// As [`ResultsFolder::create`]; [`CliError::Io`] when `results/` cannot be created.
    pub fn create_or_default(out: Option<&Path>, id: &str) -> Result<Self, CliError> {
        match out {
            Some(out) => Self::create(out),
            None => {
                fs::create_dir_all("results")
                    .map_err(|e| CliError::io("creating the folder results", e))?;
                Self::create(&PathBuf::from("results").join(id))
            }
        }
    }

    /// Starts writing the results folder `target` (`--out DIR`). Its parent must exist and be
    /// writable; `target` itself may exist (it is replaced by [`ResultsFolder::finish`]).
    ///
    /// # Errors
    /// Bad input (exit 2): a missing parent folder, a `target` that is a file, or a parent
    /// that cannot be written.
    pub fn create(target: &Path) -> Result<Self, CliError> {
        let name = target
            .file_name()
            .ok_or_else(|| {
                CliError::bad_input(format!("--out {} does not name a folder", target.display()))
            })?
            .to_string_lossy()
            .into_owned();
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if !parent.is_dir() {
            return Err(CliError::bad_input(format!(
                "--out {}: the folder {} does not exist; create it first",
                target.display(),
                parent.display()
            )));
        }
        if target.exists() && !target.is_dir() {
            return Err(CliError::bad_input(format!(
                "--out {} is a file, not a folder",
                target.display()
            )));
        }
        let staging = parent.join(format!(".{name}.partial-{}", unique_suffix()));
        fs::create_dir(&staging).map_err(|e| {
            CliError::bad_input(format!(
                "--out {}: cannot write in {}: {e}",
                target.display(),
                parent.display()
            ))
        })?;
        Ok(Self {
            target: target.to_path_buf(),
            staging,
            finished: false,
        })
    }

    /// The folder the results will end up in.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Writes a file `name` into the folder: a file name (`"samples.csv"`) or a relative path
    /// in a sub-folder (`"logs/trial0.jsonl"`), whose folders are created.
    ///
    /// # Errors
    /// Bad input if `name` is empty, absolute, leaves the folder (`..`), or is `summary.json`;
    /// [`CliError::Io`] if writing fails.
    pub fn write(&self, name: &str, contents: impl AsRef<[u8]>) -> Result<(), CliError> {
        let path = Path::new(name);
        let inside = !name.is_empty()
            && path
                .components()
                .all(|c| matches!(c, std::path::Component::Normal(_)));
        if !inside || name == "summary.json" {
            return Err(CliError::bad_input(format!(
                "results file name {name:?} must be a relative path inside the results folder, \
                 other than summary.json"
            )));
        }
        let file = self.staging.join(path);
        let context = || format!("writing {name} for {}", self.target.display());
        if let Some(parent) = file.parent() {
            fs::create_dir_all(parent).map_err(|e| CliError::io(context(), e))?;
        }
        fs::write(file, contents).map_err(|e| CliError::io(context(), e))
    }

    /// The folder the files are written into until [`ResultsFolder::finish`] moves it into
    /// place: for writers that take a folder (figures). Write nothing named `summary.json`.
    pub fn dir(&self) -> &Path {
        &self.staging
    }

    /// Writes a figure with `draw`, which writes into the folder it is given (the
    /// `ftwire_report` charts' `write`); `stem` names the figure in the error.
    ///
    /// # Errors
    /// No answer when the figure cannot be drawn.
    pub fn write_figure(
        &self,
        stem: &str,
        draw: impl FnOnce(&Path) -> Result<Vec<PathBuf>, ftwire_report::ReportError>,
    ) -> Result<(), CliError> {
        draw(self.dir())
            .map(|_| ())
            .map_err(|e| CliError::no_answer(format!("figure {stem}: {e}")))
    }

    /// Writes the default `report.md` and `report.html` ([`crate::report`]) where the run did
    /// not write its own.
    fn write_default_reports(
        &self,
        header: &RunHeader,
        summary: &impl Serialize,
    ) -> Result<(), CliError> {
        let value = serde_json::to_value(summary)
            .map_err(|e| CliError::bad_input(format!("cannot serialise the summary: {e}")))?;
        let figures = crate::report::pngs(&self.staging);
        if !self.staging.join("report.md").exists() {
            let names: Vec<String> = figures
                .iter()
                .filter_map(|f| f.file_name().map(|n| n.to_string_lossy().into_owned()))
                .collect();
            self.write("report.md", crate::report::markdown(header, &value, &names))?;
        }
        if !self.staging.join("report.html").exists() {
            let page = crate::report::html(header, &value, &figures)
                .map_err(|e| CliError::no_answer(format!("report.html: {e}")))?;
            self.write("report.html", page)?;
        }
        Ok(())
    }

    /// Writes `value` as pretty JSON into the file `name`.
    ///
    /// # Errors
    /// As [`ResultsFolder::write`], and bad input if `value` cannot be serialised.
    pub fn write_json(&self, name: &str, value: &impl Serialize) -> Result<(), CliError> {
        let text = serde_json::to_vec_pretty(value)
            .map_err(|e| CliError::bad_input(format!("cannot serialise {name}: {e}")))?;
        self.write(name, text)
    }

    /// Writes `summary.json` (`{"header": ..., "summary": ...}`) and moves the folder into
    /// place: an existing target is first renamed aside and removed only once the new folder
    /// is in place. Returns the target.
    ///
    /// # Errors
    /// [`CliError::Io`] if a write or a rename fails; the target then still holds either the
    /// old results or the new ones, never a mix.
    pub fn finish(
        mut self,
        header: &RunHeader,
        summary: &impl Serialize,
    ) -> Result<PathBuf, CliError> {
        let text = serde_json::to_vec_pretty(&Summary { header, summary })
            .map_err(|e| CliError::bad_input(format!("cannot serialise summary.json: {e}")))?;
        let context = |what: &str| format!("{what} {}", self.target.display());
        fs::write(self.staging.join("summary.json"), text)
            .map_err(|e| CliError::io(context("writing summary.json of"), e))?;
        self.write_default_reports(header, summary)?;
        let old = if self.target.exists() {
            let name = self
                .target
                .file_name()
                .map(|n| n.to_string_lossy().into_owned());
            let aside = self.staging.with_file_name(format!(
                ".{}.old-{}",
                name.unwrap_or_default(),
                unique_suffix()
            ));
            fs::rename(&self.target, &aside)
                .map_err(|e| CliError::io(context("moving aside the old results in"), e))?;
            Some(aside)
        } else {
            None
        };
        if let Err(e) = fs::rename(&self.staging, &self.target) {
            if let Some(aside) = &old {
                // Put the old results back; the new ones stay in the staging folder.
                let _ = fs::rename(aside, &self.target);
            }
            return Err(CliError::io(context("moving the new results into"), e));
        }
        self.finished = true;
        if let Some(aside) = old {
            fs::remove_dir_all(&aside)
                .map_err(|e| CliError::io(format!("removing {}", aside.display()), e))?;
        }
        Ok(self.target.clone())
    }
}

impl Drop for ResultsFolder {
    fn drop(&mut self) {
        if !self.finished {
            let _ = fs::remove_dir_all(&self.staging);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unique empty folder under the system's temporary folder, removed on drop.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(tag: &str) -> Self {
            let path =
                std::env::temp_dir().join(format!("ftwire-results-{tag}-{}", unique_suffix()));
            fs::create_dir_all(&path).expect("creates a temporary folder");
            Self(path)
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = fs::remove_dir_all(&self.0);
        }
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .expect("lists")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_summary_and_files_then_replaces_old_results_whole() {
        let tmp = TempDir::new("replace");
        let target = tmp.0.join("run");
        let header = RunHeader::new("test", Some(3), &serde_json::json!({"k": 1})).expect("header");
        let folder = ResultsFolder::create(&target).expect("creates");
        folder.write("samples.csv", "a,b\n1,2\n").expect("writes");
        folder
            .write("logs/trial0.jsonl", "{}\n")
            .expect("writes in a sub-folder");
        fs::write(folder.dir().join("figure.svg"), "<svg/>").expect("writes into dir()");
        assert!(!target.exists(), "nothing appears before finish");
        folder
            .finish(&header, &serde_json::json!({"ok": true}))
            .expect("finishes");
        let finished = [
            "figure.svg",
            "logs",
            "report.html",
            "report.md",
            "samples.csv",
            "summary.json",
        ];
        assert_eq!(entries(&target), finished);
        assert_eq!(
            fs::read_to_string(target.join("logs/trial0.jsonl")).expect("reads"),
            "{}\n"
        );
        let summary: serde_json::Value =
            serde_json::from_slice(&fs::read(target.join("summary.json")).expect("reads"))
                .expect("json");
        assert_eq!(summary["header"]["seed"], 3);
        assert_eq!(summary["header"]["configuration"]["k"], 1);
        assert_eq!(summary["summary"]["ok"], true);

        // A second run replaces the folder; an unfinished third leaves it as it was.
        let folder = ResultsFolder::create(&target).expect("creates");
        folder.write_json("other.json", &[1, 2]).expect("writes");
        assert_eq!(entries(&target), finished);
        folder.finish(&header, &2).expect("finishes");
        assert_eq!(
            entries(&target),
            ["other.json", "report.html", "report.md", "summary.json"]
        );
        let unfinished = ResultsFolder::create(&target).expect("creates");
        unfinished.write("x.csv", "1").expect("writes");
        drop(unfinished);
        assert_eq!(
            entries(&target),
            ["other.json", "report.html", "report.md", "summary.json"]
        );
        assert_eq!(
            entries(&tmp.0),
            ["run"],
            "no temporary folder is left behind"
        );
    }

    #[test]
    fn a_missing_or_unusable_out_is_bad_input() {
        let tmp = TempDir::new("bad");
        let missing = tmp.0.join("no").join("such").join("run");
        let e = ResultsFolder::create(&missing).expect_err("missing parent");
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("does not exist"), "{e}");
        let file = tmp.0.join("file");
        fs::write(&file, "x").expect("writes");
        let e = ResultsFolder::create(&file).expect_err("a file");
        assert_eq!(e.exit_code(), 2);
        let e = ResultsFolder::create(&file.join("run")).expect_err("parent is a file");
        assert_eq!(e.exit_code(), 2);
        let folder = ResultsFolder::create(&tmp.0.join("ok")).expect("creates");
        for bad in [
            "../escape.csv",
            "summary.json",
            "a/../../b.csv",
            "/abs.csv",
            "",
        ] {
            assert_eq!(folder.write(bad, "x").map_err(|e| e.exit_code()), Err(2));
        }
    }
}
