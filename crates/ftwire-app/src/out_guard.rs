//! The guard of a results folder: what a run may do with an existing `--out` folder (replace
//! it only when ftwire wrote it, or it is empty, or with `--force`), and the run's inputs,
//! which are never inside the folder it replaces (see [`crate::results`]).

use std::fs;
use std::path::{Path, PathBuf};

use crate::error::LabError;

/// The file that marks a folder as written by ftwire: a run may replace a folder that holds
/// it. It holds the run header of the run that wrote the folder (JSON).
pub const MARK: &str = ".ftwire-results";

/// What a run may do with an existing `--out` folder: whether `--force` was given, and the
/// files the run reads (which must not be inside the folder it replaces).
#[derive(Debug, Clone, Default)]
pub struct OutGuard {
    force: bool,
    inputs: Vec<(String, PathBuf)>,
}

impl OutGuard {
    /// The same guard with `--force` as given: replace a folder ftwire did not write.
    #[must_use]
    pub fn with_force(mut self, force: bool) -> Self {
        self.force = force;
        self
    }

    /// Adds an input file of the run, given with `option` (e.g. `"--wire"`). A value that
    /// names no existing file (a preset name) is not a file, and is left out.
    #[must_use]
    pub fn input(mut self, option: &str, path: impl AsRef<Path>) -> Self {
        let path = path.as_ref();
        if fs::symlink_metadata(path).is_ok() {
            self.inputs.push((option.to_owned(), path.to_path_buf()));
        }
        self
    }

    /// Adds every path named on the command line `args` (the program's arguments, without its
    /// name) as an input, under the option it follows (`--wire FILE`, `--wire=FILE`; a bare
    /// argument is `an argument`), but for `--out`'s own value: one place that registers every
    /// file a command reads, so that an option added later cannot be forgotten. A value that
    /// names nothing on disk (a preset, a number) is left out, as in [`OutGuard::input`].
    #[must_use]
    pub fn command_line(mut self, args: impl IntoIterator<Item = std::ffi::OsString>) -> Self {
        let mut option: Option<String> = None;
        for arg in args {
            let text = arg.to_string_lossy();
            if let Some(flag) = text.strip_prefix("--").filter(|f| !f.is_empty()) {
                match flag.split_once('=') {
                    Some((name, value)) => {
                        if name != "out" {
                            self = self.input(&format!("--{name}"), value);
                        }
                        option = None;
                    }
                    None => option = Some(format!("--{flag}")),
                }
                continue;
            }
            match option.take() {
                Some(name) if name == "--out" => {}
                Some(name) => self = self.input(&name, &arg),
                None => self = self.input("an argument", &arg),
            }
        }
        self
    }

    /// Adds an optional input (see [`OutGuard::input`]).
    #[must_use]
    pub fn input_opt(self, option: &str, path: Option<impl AsRef<Path>>) -> Self {
        match path {
            Some(path) => self.input(option, path),
            None => self,
        }
    }

    /// Checks that `target`, an existing folder, may be replaced.
    pub(crate) fn check(&self, target: &Path) -> Result<(), LabError> {
        let shown = target.display();
        let Ok(inside) = target.canonicalize() else {
            return Err(LabError::bad_input(format!(
                "--out {shown}: cannot resolve the folder"
            )));
        };
        // A path is inside when it resolves inside, or when the link it names is: a symbolic
        // link the user put in the folder goes with the folder, wherever it points.
        let holds = |path: &Path| {
            let resolved = path
                .canonicalize()
                .or_else(|_| std::path::absolute(path))
                .is_ok_and(|p| p.starts_with(&inside));
            let named = match (path.parent(), path.file_name()) {
                (Some(parent), Some(name)) => {
                    let parent = if parent.as_os_str().is_empty() {
                        Path::new(".")
                    } else {
                        parent
                    };
                    parent
                        .canonicalize()
                        .is_ok_and(|p| p.join(name).starts_with(&inside))
                }
                _ => false,
            };
            resolved || named
        };
        for (option, path) in &self.inputs {
            if holds(path) {
                return Err(LabError::bad_input(format!(
                    "--out {shown} holds the run's input {option} {}; a run replaces its \
                     results folder whole, so write the results to another folder",
                    path.display()
                )));
            }
        }
        if std::env::current_dir().is_ok_and(|cwd| holds(&cwd)) {
            return Err(LabError::bad_input(format!(
                "--out {shown} holds the working folder; a run replaces its results folder \
                 whole, so write the results to another folder"
            )));
        }
        if self.force || target.join(MARK).is_file() {
            return Ok(());
        }
        let empty = fs::read_dir(target)
            .map_err(|e| LabError::bad_input(format!("--out {shown}: cannot read it: {e}")))?
            .next()
            .is_none();
        if empty {
            return Ok(());
        }
        Err(LabError::bad_input(format!(
            "--out {shown} exists and is not a results folder of ftwire (it has no {MARK}); a \
             run replaces its results folder whole, so it leaves this one alone: name a new \
             or empty folder, or give --force to replace {shown} and everything in it"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A temporary folder, removed on drop.
    struct TempDir(PathBuf);

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = fs::remove_dir_all(&self.0);
        }
    }

    /// Every path on a command line is an input, under the option it follows, but `--out`'s
    /// own value and what names nothing on disk.
    #[test]
    fn every_path_on_the_command_line_is_an_input() {
        let dir = TempDir(
            std::env::temp_dir().join(format!("ftwire-guard-command-line-{}", std::process::id())),
        );
        fs::create_dir_all(&dir.0).expect("creates a temporary folder");
        let file = |name: &str| {
            let path = dir.0.join(name);
            fs::write(&path, "x").expect("writes");
            path.display().to_string()
        };
        let (wire, log, sensor) = (file("wire.toml"), file("log.jsonl"), file("sensor.toml"));
        let out = dir.0.display().to_string();
        let args = [
            "shape",
            "--log",
            &log,
            "--wire",
            &wire,
            &format!("--sensor={sensor}"),
            "--points",
            "64",
            "--calibration",
            "nitinol-2mm-630",
            "--out",
            &out,
        ];
        let guard = OutGuard::default().command_line(args.iter().map(std::ffi::OsString::from));
        let named: Vec<&str> = guard.inputs.iter().map(|(o, _)| o.as_str()).collect();
        assert_eq!(named, ["--log", "--wire", "--sensor"]);
        let refused = guard
            .check(&dir.0)
            .expect_err("the folder holds the inputs");
        assert!(
            refused.to_string().contains("holds the run's input --log"),
            "{refused}"
        );
    }

    /// A symbolic link inside the folder is an input inside it, wherever it points: replacing
    /// the folder would remove the user's link.
    #[cfg(unix)]
    #[test]
    fn a_link_inside_the_folder_to_a_file_outside_is_inside() {
        let dir =
            TempDir(std::env::temp_dir().join(format!("ftwire-guard-link-{}", std::process::id())));
        let out = dir.0.join("out");
        fs::create_dir_all(&out).expect("creates a temporary folder");
        fs::write(out.join(MARK), "").expect("an earlier run's folder");
        let target = dir.0.join("wire.toml");
        fs::write(&target, "x").expect("writes");
        let link = out.join("wlink.toml");
        std::os::unix::fs::symlink(&target, &link).expect("a link");
        let refused = OutGuard::default()
            .input("--wire", &link)
            .check(&out)
            .expect_err("the link is inside");
        assert!(refused.to_string().contains("--wire"), "{refused}");
        assert!(
            OutGuard::default()
                .input("--wire", &target)
                .check(&out)
                .is_ok()
        );
    }
}
