//! A reproduction's experiment as a child process of the `ftwire` binary: started with its
//! parent's process id in [`PARENT_PID_VAR`] and its output into the job's log, so that a
//! child whose parent is gone ends itself ([`end_with_parent`]) and killing the reproduction
//! leaves none of its experiments running.

use std::fs::File;
use std::path::Path;
use std::process::{Command, Stdio};

use super::Job;

/// The environment variable through which `ftwire reproduce` tells the experiments it starts
/// its process id: each one ends (removing its temporary results folder) once that process is
/// gone, so that killing `reproduce` leaves none of them running.
pub const PARENT_PID_VAR: &str = "FTWIRE_PARENT_PID";

impl Job {
    /// Runs the job as a child process of `exe` (the `ftwire` binary) with its arguments, its
    /// standard output and error into its log, this process's id in [`PARENT_PID_VAR`], and
    /// no standard input ([`crate::results::run_child`]: an interrupt ends it first).
    ///
    /// # Errors
    /// Why it did not succeed: the log cannot be written, the process cannot be started, or
    /// its exit code and its log's last line.
    pub fn run_as_child(&self, exe: &Path) -> Result<(), String> {
        let log = &self.log;
        let file = File::create(log).map_err(|e| format!("cannot write {}: {e}", log.display()))?;
        let err = file
            .try_clone()
            .map_err(|e| format!("cannot write {}: {e}", log.display()))?;
        let exit = crate::results::run_child(
            Command::new(exe)
                .args(&self.args)
                .env(PARENT_PID_VAR, std::process::id().to_string())
                .stdin(Stdio::null())
                .stdout(file)
                .stderr(err),
        )
        .map_err(|e| format!("cannot start: {e}"))?;
        if exit.success() {
            Ok(())
        } else {
            let text = std::fs::read_to_string(log).unwrap_or_default();
            let last = text.lines().last().unwrap_or("").to_owned();
            Err(format!("exit {}: {last}", exit.code().unwrap_or(-1)))
        }
    }
}

/// Under `ftwire reproduce` ([`PARENT_PID_VAR`] set), ends this process cleanly once its
/// parent is gone: the parent was killed (even by SIGKILL, which it cannot catch) and this
/// process was handed to another. Checked every 100 ms on a thread of its own; the temporary
/// results folders are removed ([`crate::results::abandon_all_and_exit`], exit 129).
#[cfg(unix)]
pub fn end_with_parent() {
    let Some(parent) = std::env::var(PARENT_PID_VAR)
        .ok()
        .and_then(|v| v.parse::<u32>().ok())
    else {
        return;
    };
    std::thread::spawn(move || {
        loop {
            if std::os::unix::process::parent_id() != parent {
                eprintln!("error: the ftwire process that started this one has ended");
                crate::results::abandon_all_and_exit(129);
            }
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn a_failed_child_says_its_exit_code_and_its_logs_last_line() {
        let dir = std::env::temp_dir().join(format!("ftwire-lab-child-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a temporary folder");
        let job = |args: &[&str]| Job {
            id: "test",
            args: args.iter().map(Into::into).collect(),
            out: dir.join("out"),
            log: dir.join("test.log"),
            expected_s: (0.0, 0.0),
            calibration: None,
        };
        let sh = Path::new("/bin/sh");
        let failed = job(&["-c", "echo first; echo \"$FTWIRE_PARENT_PID\" >&2; exit 3"]);
        let error = failed.run_as_child(sh).expect_err("exit 3");
        assert_eq!(error, format!("exit 3: {}", std::process::id()));
        let log = std::fs::read_to_string(dir.join("test.log")).expect("the log");
        assert!(log.starts_with("first\n"), "{log}");
        assert_eq!(job(&["-c", "exit 0"]).run_as_child(sh), Ok(()));
        let missing = job(&[]).run_as_child(&dir.join("no-such-program"));
        assert!(missing.is_err_and(|e| e.starts_with("cannot start: ")));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
