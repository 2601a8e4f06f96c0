//! The results folder of an experiment: `summary.json` (with the [`RunHeader`]), the default
//! `report.md` and `report.html` ([`crate::report`]) unless the run wrote its own, and other
//! files, written whole into a temporary sibling folder and renamed into place at the end, so
//! that an existing results folder is replaced whole or not at all.
//!
//! A results folder carries the mark [`MARK`] (a file holding its run header). A run replaces
//! an existing `--out` folder only when it carries the mark or is empty; any other folder is
//! the user's, and is replaced only with `--force` ([`OutGuard`]). A folder that holds one of
//! the run's own inputs, or the working folder, is never replaced, `--force` or not.
//!
//! The temporary folders (`.NAME.partial-PID-NS` while a run writes, `.NAME.old-PID-NS` while
//! the old results make way) are removed when the run ends, is interrupted (SIGINT, SIGTERM,
//! SIGHUP: [`abandon_all_and_exit`]) or loses its parent process; after a SIGKILL the next run
//! into the same `--out` removes those of a process that is gone. Guarded by
//! `crates/ftwire/tests/out_safety_cli.rs`.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus};
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use serde::Serialize;

use crate::error::LabError;
use crate::header::RunHeader;
pub use crate::out_guard::{MARK, OutGuard};

/// The temporary folders this process is writing: removed by [`abandon_all_and_exit`].
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The list of live temporary folders, held while a results folder moves into place so that
/// an interrupt waits for the move to end.
fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// The child processes writing into this process's results folders ([`run_child`]).
static CHILDREN: Mutex<Vec<Child>> = Mutex::new(Vec::new());

fn children() -> MutexGuard<'static, Vec<Child>> {
    CHILDREN
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Runs `command` to its end as a child process that writes into this run's results folder
/// (`ftwire reproduce`'s experiments): an interrupt of this process ends the child first
/// ([`abandon_all_and_exit`]), so that none is left running.
///
/// # Errors
/// The child cannot be started or waited for.
pub fn run_child(command: &mut Command) -> std::io::Result<ExitStatus> {
    // Spawned under the lock that an interrupt holds to the end: every child is either
    // registered, and ended by it, or never started.
    let id = {
        let mut list = children();
        let child = command.spawn()?;
        let id = child.id();
        list.push(child);
        id
    };
    loop {
        {
            let mut list = children();
            let Some(i) = list.iter().position(|c| c.id() == id) else {
                return Err(std::io::Error::other("ended by an interrupt"));
            };
            if list[i].try_wait()?.is_some() {
                // Ended: `wait` returns the status `try_wait` saw.
                return list.swap_remove(i).wait();
            }
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Ends the child processes ([`run_child`]), removes every temporary results folder this
/// process is writing, then ends the process with `code`: what an interrupt (SIGINT, SIGTERM,
/// SIGHUP) or the loss of the parent process does. A results folder that is moving into place
/// finishes its move first, so the `--out` folder holds either the old results or the new
/// ones.
pub fn abandon_all_and_exit(code: i32) -> ! {
    let mut running = children();
    for child in running.iter_mut() {
        let _ = child.kill();
        let _ = child.wait();
    }
    let live = live();
    for dir in live.iter() {
        // A file being created while the folder is walked can make one pass fail.
        for _ in 0..5 {
            if fs::remove_dir_all(dir).is_ok() || !dir.exists() {
                break;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }
    std::process::exit(code)
}

/// Removes the temporary folders `.NAME.partial-PID-NS` and `.NAME.old-PID-NS` beside
/// `target` that a process now gone left behind (a SIGKILL), where they are ftwire's: marked
/// with [`MARK`], or empty. Only where the process table can be read (`/proc`).
fn remove_stale(parent: &Path, name: &str) {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return;
    }
    let Ok(entries) = fs::read_dir(parent) else {
        return;
    };
    let prefixes = [format!(".{name}.partial-"), format!(".{name}.old-")];
    for entry in entries.flatten() {
        let file_name = entry.file_name().to_string_lossy().into_owned();
        let Some(rest) = prefixes
            .iter()
            .find_map(|p| file_name.strip_prefix(p.as_str()))
        else {
            continue;
        };
        let Some((pid, nanos)) = rest.split_once('-') else {
            continue;
        };
        let (Ok(pid), true) = (
            pid.parse::<u32>(),
            nanos.bytes().all(|b| b.is_ascii_digit()),
        ) else {
            continue;
        };
        let path = entry.path();
        let is_dir = fs::symlink_metadata(&path).is_ok_and(|m| m.is_dir());
        if !is_dir || pid == std::process::id() || proc.join(pid.to_string()).exists() {
            continue;
        }
        let ours =
            path.join(MARK).is_file() || fs::read_dir(&path).is_ok_and(|mut d| d.next().is_none());
        if ours {
            let _ = fs::remove_dir_all(&path);
        }
    }
}

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
    /// The rule `target` was checked by at the start, checked again at the rename: a folder
    /// made there during the run is replaced only where the rule allows it.
    guard: OutGuard,
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
    /// As [`ResultsFolder::create`]; bad input when `results` is a file, [`LabError::Io`] when
    /// `results/` cannot be created.
    pub fn create_or_default(
        out: Option<&Path>,
        id: &str,
        guard: &OutGuard,
    ) -> Result<Self, LabError> {
        match out {
            Some(out) => Self::create(out, guard),
            None => Self::create(&default_folder(id)?, guard),
        }
    }

    /// Starts writing the results folder `target` (`--out DIR`). Its parent must exist and be
    /// writable; `target` itself may exist where `guard` allows it to be replaced (see the
    /// module docs); it is replaced by [`ResultsFolder::finish`].
    ///
    /// # Errors
    /// Bad input (exit 2): a missing parent folder, a parent or `target` that is a file or a
    /// symbolic link, a `target` that `guard` refuses to replace, or a parent that cannot be
    /// written.
    pub fn create(target: &Path, guard: &OutGuard) -> Result<Self, LabError> {
        let name = target
            .file_name()
            .ok_or_else(|| {
                LabError::bad_input(format!("--out {} does not name a folder", target.display()))
            })?
            .to_string_lossy()
            .into_owned();
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if !parent.is_dir() {
            let why = if parent.exists() {
                "is a file, not a folder"
            } else {
                "does not exist; create it first"
            };
            return Err(LabError::bad_input(format!(
                "--out {}: {} {why}",
                target.display(),
                parent.display()
            )));
        }
        match fs::symlink_metadata(target) {
            Ok(meta) if meta.file_type().is_symlink() => {
                return Err(LabError::bad_input(format!(
                    "--out {} is a symbolic link; name the folder itself",
                    target.display()
                )));
            }
            Ok(meta) if !meta.is_dir() => {
                return Err(LabError::bad_input(format!(
                    "--out {} is a file, not a folder",
                    target.display()
                )));
            }
            Ok(_) => guard.check(target)?,
            Err(_) => {}
        }
        remove_stale(&parent, &name);
        let staging = parent.join(format!(".{name}.partial-{}", unique_suffix()));
        let cannot_write = |e: std::io::Error| {
            LabError::bad_input(format!(
                "--out {}: cannot write in {}: {e}",
                target.display(),
                parent.display()
            ))
        };
        let mut live = live();
        fs::create_dir(&staging).map_err(cannot_write)?;
        live.push(staging.clone());
        drop(live);
        let folder = Self {
            target: target.to_path_buf(),
            staging,
            finished: false,
            guard: guard.clone(),
        };
        fs::write(
            folder.staging.join(MARK),
            "a results folder being written by ftwire\n",
        )
        .map_err(cannot_write)?;
        Ok(folder)
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
    /// [`LabError::Io`] if writing fails.
    pub fn write(&self, name: &str, contents: impl AsRef<[u8]>) -> Result<(), LabError> {
        let path = Path::new(name);
        let inside = !name.is_empty()
            && path
                .components()
                .all(|c| matches!(c, std::path::Component::Normal(_)));
        if !inside || name == "summary.json" {
            return Err(LabError::bad_input(format!(
                "results file name {name:?} must be a relative path inside the results folder, \
                 other than summary.json"
            )));
        }
        let file = self.staging.join(path);
        let context = || format!("writing {name} for {}", self.target.display());
        // Sub-folders only: a temporary folder removed by an interrupt is not made again.
        if let Some(parent) = file.parent().filter(|_| self.staging.is_dir()) {
            fs::create_dir_all(parent).map_err(|e| LabError::io(context(), e))?;
        }
        fs::write(file, contents).map_err(|e| LabError::io(context(), e))
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
    ) -> Result<(), LabError> {
        draw(self.dir())
            .map(|_| ())
            .map_err(|e| LabError::no_answer(format!("figure {stem}: {e}")))
    }

    /// Writes the default `report.md` and `report.html` ([`crate::report`]) where the run did
    /// not write its own.
    fn write_default_reports(
        &self,
        header: &RunHeader,
        summary: &impl Serialize,
    ) -> Result<(), LabError> {
        let value = serde_json::to_value(summary)
            .map_err(|e| LabError::bad_input(format!("cannot serialise the summary: {e}")))?;
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
                .map_err(|e| LabError::no_answer(format!("report.html: {e}")))?;
            self.write("report.html", page)?;
        }
        Ok(())
    }

    /// Writes `value` as pretty JSON into the file `name`.
    ///
    /// # Errors
    /// As [`ResultsFolder::write`], and bad input if `value` cannot be serialised.
    pub fn write_json(&self, name: &str, value: &impl Serialize) -> Result<(), LabError> {
        let text = serde_json::to_vec_pretty(value)
            .map_err(|e| LabError::bad_input(format!("cannot serialise {name}: {e}")))?;
        self.write(name, text)
    }

    /// Ends a run: `timings.json` (the wall times, kept out of `summary.json` so that the same
    /// seed gives the same summary), then [`ResultsFolder::finish`]. Every command ends so.
    ///
    /// # Errors
    /// As [`ResultsFolder::write_json`] and [`ResultsFolder::finish`].
    pub fn finish_run(
        self,
        header: &RunHeader,
        summary: &impl Serialize,
        timings: &impl Serialize,
    ) -> Result<PathBuf, LabError> {
        self.write_json("timings.json", timings)?;
        self.finish(header, summary)
    }

    /// Writes `summary.json` (`{"header": ..., "summary": ...}`) and moves the folder into
    /// place: an existing target is first renamed aside and removed only once the new folder
    /// is in place. Returns the target.
    ///
    /// # Errors
    /// [`LabError::Io`] if a write or a rename fails; the target then still holds either the
    /// old results or the new ones, never a mix.
    pub fn finish(
        mut self,
        header: &RunHeader,
        summary: &impl Serialize,
    ) -> Result<PathBuf, LabError> {
        let text = serde_json::to_vec_pretty(&Summary { header, summary })
            .map_err(|e| LabError::bad_input(format!("cannot serialise summary.json: {e}")))?;
        let context = |what: &str| format!("{what} {}", self.target.display());
        fs::write(self.staging.join("summary.json"), text)
            .map_err(|e| LabError::io(context("writing summary.json of"), e))?;
        self.write_default_reports(header, summary)?;
        let mark = serde_json::to_vec_pretty(header)
            .map_err(|e| LabError::bad_input(format!("cannot serialise {MARK}: {e}")))?;
        fs::write(self.staging.join(MARK), mark)
            .map_err(|e| LabError::io(context(&format!("writing {MARK} of")), e))?;
        // An interrupt waits for the moves below: `--out` ends with the old results or the new.
        let mut live = live();
        if let Err(refused) = self.recheck() {
            // The new results are kept beside the folder, never over it.
            let kept = self.staging.with_file_name(format!(
                "{}.new-{}",
                self.target
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                unique_suffix()
            ));
            if fs::rename(&self.staging, &kept).is_ok() {
                self.finished = true;
                live.retain(|dir| dir != &self.staging);
                return Err(LabError::bad_input(format!(
                    "{refused} (it appeared during the run); the new results are in {}",
                    kept.display()
                )));
            }
            return Err(refused);
        }
        let old = if fs::symlink_metadata(&self.target).is_ok() {
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
                .map_err(|e| LabError::io(context("moving aside the old results in"), e))?;
            Some(aside)
        } else {
            None
        };
        if let Err(e) = fs::rename(&self.staging, &self.target) {
            if let Some(aside) = &old {
                // Put the old results back; the new ones stay in the staging folder.
                let _ = fs::rename(aside, &self.target);
            }
            return Err(LabError::io(context("moving the new results into"), e));
        }
        self.finished = true;
        live.retain(|dir| dir != &self.staging);
        if let Some(aside) = old {
            fs::remove_dir_all(&aside)
                .map_err(|e| LabError::io(format!("removing {}", aside.display()), e))?;
        }
        Ok(self.target.clone())
    }
}

impl ResultsFolder {
    /// The start's check of the target, again: a symbolic link, a file, or a folder the guard
    /// refuses is left alone.
    fn recheck(&self) -> Result<(), LabError> {
        match fs::symlink_metadata(&self.target) {
            Err(_) => Ok(()),
            Ok(meta) if meta.file_type().is_symlink() || !meta.is_dir() => {
                Err(LabError::bad_input(format!(
                    "--out {} is now a file or a symbolic link",
                    self.target.display()
                )))
            }
            Ok(_) => self.guard.check(&self.target),
        }
    }
}

/// `results/<id>` in the working folder, creating `results/` when it is missing.
///
/// # Errors
/// Bad input when `results` is a file; [`LabError::Io`] when it cannot be created.
pub fn default_folder(id: &str) -> Result<PathBuf, LabError> {
    let results = Path::new("results");
    if fs::symlink_metadata(results).is_ok() && !results.is_dir() {
        return Err(LabError::bad_input(
            "results is a file, not a folder: the default results folder is results/<run>; \
             move the file or give --out DIR",
        ));
    }
    fs::create_dir_all(results).map_err(|e| LabError::io("creating the folder results", e))?;
    Ok(results.join(id))
}

impl Drop for ResultsFolder {
    fn drop(&mut self) {
        if !self.finished {
            let mut live = live();
            let _ = fs::remove_dir_all(&self.staging);
            live.retain(|dir| dir != &self.staging);
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

    /// A folder a user makes at `--out` during the run is checked at the rename by the same
    /// rule as at the start: never replaced, the new results kept beside it.
    #[test]
    fn a_folder_made_at_out_during_the_run_is_left_alone() {
        let tmp = TempDir::new("late");
        let target = tmp.0.join("late");
        let header = RunHeader::new("test", Some(3), &serde_json::json!({"k": 1})).expect("header");
        let folder = ResultsFolder::create(&target, &OutGuard::default()).expect("creates");
        folder.write("samples.csv", "a,b\n1,2\n").expect("writes");
        fs::create_dir(&target).expect("the user's folder");
        fs::write(target.join("important.txt"), "mine\n").expect("the user's file");
        let error = folder
            .finish(&header, &serde_json::json!({"n": 1}))
            .expect_err("refused");
        assert_eq!(error.kind(), "bad_input");
        assert!(
            error.to_string().contains("appeared during the run"),
            "{error}"
        );
        assert_eq!(
            fs::read_to_string(target.join("important.txt")).expect("still there"),
            "mine\n"
        );
        let kept: Vec<String> = entries(&tmp.0)
            .into_iter()
            .filter(|n| n.starts_with("late.new-"))
            .collect();
        assert_eq!(kept.len(), 1, "{:?}", entries(&tmp.0));
        assert!(tmp.0.join(&kept[0]).join("samples.csv").is_file());
    }

    #[test]
    fn writes_summary_and_files_then_replaces_old_results_whole() {
        let tmp = TempDir::new("replace");
        let target = tmp.0.join("run");
        let header = RunHeader::new("test", Some(3), &serde_json::json!({"k": 1})).expect("header");
        let folder = ResultsFolder::create(&target, &OutGuard::default()).expect("creates");
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
            MARK,
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
        let folder = ResultsFolder::create(&target, &OutGuard::default()).expect("creates");
        folder.write_json("other.json", &[1, 2]).expect("writes");
        assert_eq!(entries(&target), finished);
        folder.finish(&header, &2).expect("finishes");
        assert_eq!(
            entries(&target),
            [
                MARK,
                "other.json",
                "report.html",
                "report.md",
                "summary.json"
            ]
        );
        let unfinished = ResultsFolder::create(&target, &OutGuard::default()).expect("creates");
        unfinished.write("x.csv", "1").expect("writes");
        drop(unfinished);
        assert_eq!(
            entries(&target),
            [
                MARK,
                "other.json",
                "report.html",
                "report.md",
                "summary.json"
            ]
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
        let e = ResultsFolder::create(&missing, &OutGuard::default()).expect_err("missing parent");
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("does not exist"), "{e}");
        let file = tmp.0.join("file");
        fs::write(&file, "x").expect("writes");
        let e = ResultsFolder::create(&file, &OutGuard::default()).expect_err("a file");
        assert_eq!(e.exit_code(), 2);
        let e = ResultsFolder::create(&file.join("run"), &OutGuard::default())
            .expect_err("parent is a file");
        assert_eq!(e.exit_code(), 2);
        let folder =
            ResultsFolder::create(&tmp.0.join("ok"), &OutGuard::default()).expect("creates");
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
