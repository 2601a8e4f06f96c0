//! A command's one output file (a converted log), beside the results folders of
//! [`crate::results`]: checked before any work, and written whole.

use std::io::Write;
use std::path::Path;

use crate::error::LabError;

/// The one file a command writes, with the options that name it and allow replacing it as the
/// caller's front end spells them (`--out`, `--force` on the command line), for its errors.
#[derive(Debug, Clone, Copy)]
pub struct OutFile<'a> {
    /// The file to write.
    pub path: &'a Path,
    /// The option that names it (`--out`).
    pub option: &'a str,
    /// The option that allows replacing an existing file (`--force`).
    pub force_option: &'a str,
    /// Whether an existing file may be replaced.
    pub force: bool,
}

impl OutFile<'_> {
    /// Refuses the file before any work: the `input` being read (`input_what` says what it
    /// is, e.g. `the bag being read`), a folder (the error suggests `example`, a file name in
    /// it), or an existing file without [`OutFile::force`].
    ///
    /// # Errors
    /// Bad input (exit 2) naming the option, the path and what to give instead.
    pub fn check(&self, input: &Path, input_what: &str, example: &str) -> Result<(), LabError> {
        let (out, option) = (self.path, self.option);
        let same = match (out.canonicalize(), input.canonicalize()) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        };
        if same {
            return Err(LabError::bad_input(format!(
                "{option} {} is {input_what}: give another file",
                out.display()
            )));
        }
        if out.is_dir() {
            return Err(LabError::bad_input(format!(
                "{option} {} is a folder: give a file name, such as {}",
                out.display(),
                out.join(example).display()
            )));
        }
        if out.exists() && !self.force {
            return Err(LabError::bad_input(format!(
                "{option} {} exists: give another file, or {} to replace it",
                out.display(),
                self.force_option
            )));
        }
        Ok(())
    }

    /// Writes `bytes` to a temporary sibling of the file and renames it into place, so that
    /// the file is never left half written (the sibling is removed on a failure).
    ///
    /// # Errors
    /// [`LabError::Io`] naming the file.
    pub fn write(&self, bytes: &[u8]) -> Result<(), LabError> {
        let path = self.path;
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "log.jsonl".into());
        let temp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
        let context = format!("writing {}", path.display());
        let result = std::fs::File::create(&temp)
            .and_then(|mut file| {
                file.write_all(bytes)?;
                file.sync_all()
            })
            .and_then(|()| std::fs::rename(&temp, path));
        if let Err(e) = result {
            std::fs::remove_file(&temp).ok();
            return Err(LabError::io(context, e));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_file_is_refused_as_the_input_a_folder_or_existing_and_written_whole() {
        let dir = std::env::temp_dir().join(format!("ftwire-app-out-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a temporary folder");
        let input = dir.join("bag.mcap");
        std::fs::write(&input, "bag").expect("written");
        fn out(path: &Path, force: bool) -> OutFile<'_> {
            OutFile {
                path,
                option: "--out",
                force_option: "--force",
                force,
            }
        }
        let error = |file: OutFile| {
            file.check(&input, "the bag being read", "log.jsonl")
                .expect_err("refused")
                .to_string()
        };
        assert!(error(out(&input, true)).contains("is the bag being read: give another file"));
        let folder = error(out(&dir, true));
        assert!(
            folder.contains("is a folder: give a file name, such as"),
            "{folder}"
        );
        assert!(folder.ends_with("log.jsonl"), "{folder}");
        let log = dir.join("log.jsonl");
        let file = out(&log, false);
        assert!(
            file.check(&input, "the bag being read", "log.jsonl")
                .is_ok()
        );
        file.write(b"first\n").expect("written");
        assert!(error(file).ends_with("exists: give another file, or --force to replace it"));
        let forced = out(&log, true);
        assert!(
            forced
                .check(&input, "the bag being read", "log.jsonl")
                .is_ok()
        );
        forced.write(b"second\n").expect("replaced");
        assert_eq!(
            std::fs::read_to_string(&log).ok().as_deref(),
            Some("second\n")
        );
        let names: Vec<_> = std::fs::read_dir(&dir)
            .expect("listed")
            .filter_map(|e| e.ok().map(|e| e.file_name()))
            .collect();
        assert_eq!(names.len(), 2, "no temporary file left: {names:?}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
