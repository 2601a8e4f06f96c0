//! `--out` never deletes what ftwire did not write, and an interrupted run leaves nothing
//! behind: a results folder is replaced whole or not at all, and only a folder that an earlier
//! run wrote (it holds `.ftwire-results`) or an empty one is replaced without `--force`; a
//! folder holding the run's own inputs or the working folder never is. SIGINT and SIGTERM
//! remove the run's temporary folder, the next run removes one a SIGKILL left, and the
//! experiments `reproduce` starts end with it.

mod cli_support;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use cli_support::{TempDir, assert_exit, assert_success, ftwire};

/// The mark of a results folder.
const MARK: &str = ".ftwire-results";

/// The cheapest command that writes a results folder (well under a second); a `--wire` in
/// `extra` replaces its preset.
fn identify_into(out: &Path, extra: &[&str]) -> Output {
    let out = out.to_string_lossy();
    let mut args = vec![
        "experiment",
        "identify",
        "--pipeline",
        "mounting",
        "--trials",
        "1",
        "--samples",
        "2",
        "--gravity",
        "off",
        "--out",
        &out,
    ];
    if !extra.contains(&"--wire") {
        args.extend(["--wire", "nitinol-2mm-630"]);
    }
    args.extend_from_slice(extra);
    ftwire(&args)
}

/// The same cheap run with the working folder `cwd` and `out_args` (`--out` given there or
/// not).
fn identify_in(cwd: &Path, out_args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ftwire"))
        .args(["experiment", "identify", "--pipeline", "mounting"])
        .args(["--trials", "1", "--samples", "2", "--gravity", "off"])
        .args(out_args)
        .current_dir(cwd)
        .output()
        .expect("runs")
}

/// A user's project folder: a file and a sub-folder with a file.
fn users_folder(dir: &Path) {
    fs::create_dir_all(dir.join("src")).expect("creates src");
    fs::write(dir.join("thesis.tex"), "thesis").expect("writes the thesis");
    fs::write(dir.join("src").join("main.c"), "int main;").expect("writes a source");
}

fn assert_users_folder_intact(dir: &Path) {
    assert_eq!(
        fs::read_to_string(dir.join("thesis.tex")).expect("the thesis is still there"),
        "thesis"
    );
    assert_eq!(
        fs::read_to_string(dir.join("src").join("main.c")).expect("the source is still there"),
        "int main;"
    );
}

/// The hidden temporary folders (`.NAME.partial-*`, `.NAME.old-*`) in `dir`.
fn temporaries(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .expect("lists")
        .filter_map(|e| {
            let name = e.expect("entry").file_name().to_string_lossy().into_owned();
            (name.contains(".partial-") || name.contains(".old-")).then_some(name)
        })
        .collect()
}

#[test]
fn a_users_folder_is_refused_and_kept_whole() {
    let tmp = TempDir::new("out-user");
    let proj = tmp.0.join("proj");
    users_folder(&proj);
    let output = identify_into(&proj, &[]);
    assert_exit(&output, 2, "--force", "a folder ftwire did not write");
    assert_exit(&output, 2, &proj.to_string_lossy(), "names the folder");
    assert_users_folder_intact(&proj);
    assert!(!proj.join("summary.json").exists());
    assert!(temporaries(&tmp.0).is_empty(), "no temporary folder left");
}

#[test]
fn an_earlier_results_folder_is_replaced_and_an_empty_one_is_used() {
    let tmp = TempDir::new("out-replace");
    let run = tmp.0.join("run");
    fs::create_dir(&run).expect("creates an empty folder");
    assert_success(&identify_into(&run, &[]), "into an empty folder");
    let mark = fs::read_to_string(run.join(MARK)).expect("the results folder is marked");
    let header: serde_json::Value = serde_json::from_str(&mark).expect("the mark is JSON");
    assert_eq!(header["command"], "experiment identify");
    fs::write(run.join("stale.txt"), "from the first run").expect("writes");
    assert_success(&identify_into(&run, &[]), "over an earlier results folder");
    assert!(run.join("summary.json").is_file());
    assert!(!run.join("stale.txt").exists(), "replaced whole");
    assert!(temporaries(&tmp.0).is_empty(), "no temporary folder left");
}

#[test]
fn force_replaces_a_users_folder() {
    let tmp = TempDir::new("out-force");
    let proj = tmp.0.join("proj");
    users_folder(&proj);
    assert_success(&identify_into(&proj, &["--force"]), "--force");
    assert!(proj.join("summary.json").is_file());
    assert!(
        !proj.join("thesis.tex").exists(),
        "--force replaces the folder whole"
    );
}

#[test]
fn a_folder_holding_the_runs_input_is_never_replaced() {
    let tmp = TempDir::new("out-input");
    let proj = tmp.0.join("proj2");
    // `ftwire init` writes a wire file; the folder is then an earlier results folder too, so
    // only the input rule can refuse it.
    assert_success(
        &ftwire(&["init", &proj.to_string_lossy()]),
        "init writes examples",
    );
    fs::write(proj.join(MARK), "{}").expect("marks the folder");
    let wire = proj.join("wire.toml");
    assert!(wire.is_file(), "init wrote wire.toml");
    for extra in [&[][..], &["--force"][..]] {
        let wire_arg = wire.to_string_lossy();
        let mut args = vec!["--wire", &wire_arg];
        args.extend_from_slice(extra);
        let output = identify_into(&proj, &args);
        assert_exit(&output, 2, "holds the run's input --wire", "its own input");
        assert!(wire.is_file(), "the input survives ({extra:?})");
    }
    // A calibration inside the folder it would replace: the same.
    let cal = tmp.0.join("cal");
    fs::create_dir(&cal).expect("creates");
    fs::write(cal.join(MARK), "{}").expect("marks");
    fs::write(cal.join("calibration.json"), "{}").expect("writes");
    let output = ftwire(&[
        "experiment",
        "shape",
        "--calibration",
        &cal.join("calibration.json").to_string_lossy(),
        "--out",
        &cal.to_string_lossy(),
        "--force",
    ]);
    assert_exit(
        &output,
        2,
        "holds the run's input --calibration",
        "--calibration",
    );
    assert!(cal.join("calibration.json").is_file());
}

#[test]
fn the_working_folder_and_links_are_never_replaced() {
    let tmp = TempDir::new("out-cwd");
    let proj = tmp.0.join("proj");
    users_folder(&proj);
    let output = identify_in(&proj.join("src"), &["--out", "../../proj", "--force"]);
    assert_exit(&output, 2, "holds the working folder", "the working folder");
    assert_users_folder_intact(&proj);
    #[cfg(unix)]
    {
        let link = tmp.0.join("link");
        std::os::unix::fs::symlink(&proj, &link).expect("links");
        let output = identify_into(&link, &["--force"]);
        assert_exit(&output, 2, "symbolic link", "a link");
        assert_users_folder_intact(&proj);
    }
}

#[test]
fn a_file_in_the_way_is_named_as_a_file() {
    let tmp = TempDir::new("out-file");
    let afile = tmp.0.join("afile");
    fs::write(&afile, "x").expect("writes");
    let output = identify_into(&afile.join("res"), &[]);
    assert_exit(&output, 2, "is a file, not a folder", "--out afile/res");
    // The default `results/` is a file.
    fs::write(tmp.0.join("results"), "x").expect("writes");
    let output = identify_in(&tmp.0, &[]);
    assert_exit(&output, 2, "results is a file", "a file named results");
    assert_eq!(
        fs::read_to_string(tmp.0.join("results")).expect("kept"),
        "x"
    );
}

#[test]
fn a_temporary_folder_a_killed_run_left_is_removed_by_the_next_run() {
    let tmp = TempDir::new("out-stale");
    let run = tmp.0.join("run");
    // No process has id 999999999 (Linux allows at most 2^22).
    let stale = tmp.0.join(".run.partial-999999999-1");
    fs::create_dir(&stale).expect("creates");
    fs::write(stale.join(MARK), "a results folder being written").expect("marks");
    fs::write(stale.join("half.csv"), "1,2").expect("writes");
    let stale_old = tmp.0.join(".run.old-999999999-2");
    fs::create_dir(&stale_old).expect("creates");
    // Not ftwire's (no mark, not empty): left alone.
    let foreign = tmp.0.join(".run.partial-999999999-3");
    fs::create_dir(&foreign).expect("creates");
    fs::write(foreign.join("mine.txt"), "mine").expect("writes");
    assert_success(&identify_into(&run, &[]), "a run beside stale folders");
    if Path::new("/proc/self").exists() {
        assert!(!stale.exists(), "the stale partial folder is removed");
        assert!(!stale_old.exists(), "the empty stale old folder is removed");
    }
    assert!(
        foreign.join("mine.txt").is_file(),
        "an unmarked one is kept"
    );
}

/// Waits up to `limit` for `ready`.
fn wait_for(limit: Duration, mut ready: impl FnMut() -> bool) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        if ready() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    ready()
}

/// The ids of the processes whose command line mentions `needle`.
#[cfg(target_os = "linux")]
fn processes_mentioning(needle: &str) -> Vec<u32> {
    let own = std::process::id();
    fs::read_dir("/proc")
        .map(|entries| {
            entries
                .filter_map(|e| {
                    let entry = e.ok()?;
                    let pid: u32 = entry.file_name().to_str()?.parse().ok()?;
                    let cmdline = fs::read(entry.path().join("cmdline")).ok()?;
                    let text = String::from_utf8_lossy(&cmdline).replace('\0', " ");
                    (pid != own && text.contains(needle)).then_some(pid)
                })
                .collect()
        })
        .unwrap_or_default()
}

/// Sends `signal` (a name for `kill -s`) to the process `pid`.
#[cfg(unix)]
fn signal(pid: u32, name: &str) {
    let status = Command::new("kill")
        .args(["-s", name, &pid.to_string()])
        .status()
        .expect("kill runs");
    assert!(status.success(), "kill -s {name} {pid}");
}

/// Starts `ftwire reproduce --quick --jobs 1 --out OUT` in the background.
fn start_reproduce(out: &Path) -> Child {
    Command::new(env!("CARGO_BIN_EXE_ftwire"))
        .args(["reproduce", "--quick", "--jobs", "1", "--out"])
        .arg(out)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts reproduce")
}

/// Waits until an experiment that `reproduce` started writes into `out`'s temporary folder.
#[cfg(target_os = "linux")]
fn wait_for_experiment(out: &Path) -> bool {
    let name = out
        .file_name()
        .expect("a name")
        .to_string_lossy()
        .into_owned();
    // The full path: another test may run reproduce into a folder of the same name.
    let parent = out
        .parent()
        .expect("a parent")
        .to_string_lossy()
        .into_owned();
    let needle = format!("{parent}/.{name}.partial-");
    wait_for(Duration::from_secs(60), || {
        processes_mentioning(&needle)
            .iter()
            .any(|pid| processes_mentioning("experiment").contains(pid))
    })
}

#[cfg(target_os = "linux")]
#[test]
fn sigterm_and_sigint_remove_the_temporary_folder_and_end_the_experiments() {
    for name in ["TERM", "INT"] {
        let tmp = TempDir::new(&format!("out-sig{name}"));
        let out: PathBuf = tmp.0.join("rep");
        let mut child = start_reproduce(&out);
        assert!(wait_for_experiment(&out), "an experiment started");
        signal(child.id(), name);
        let status = child.wait().expect("reproduce ends");
        let number = if name == "TERM" { 15 } else { 2 };
        assert_eq!(
            status.code(),
            Some(128 + number),
            "SIG{name}: exit 128 + signal"
        );
        let needle = tmp.0.to_string_lossy().into_owned();
        assert!(
            wait_for(Duration::from_secs(10), || processes_mentioning(&needle)
                .is_empty()),
            "SIG{name}: the experiments end with reproduce"
        );
        assert!(
            temporaries(&tmp.0).is_empty(),
            "SIG{name}: no temporary folder is left: {:?}",
            temporaries(&tmp.0)
        );
        assert!(!out.exists(), "SIG{name}: nothing half-written at --out");
    }
}

#[cfg(target_os = "linux")]
#[test]
fn sigkill_of_reproduce_ends_its_experiments_and_the_next_run_tidies_up() {
    let tmp = TempDir::new("out-sigkill");
    let out = tmp.0.join("rep");
    let mut child = start_reproduce(&out);
    assert!(wait_for_experiment(&out), "an experiment started");
    child.kill().expect("SIGKILL");
    child.wait().expect("reaped");
    let needle = tmp.0.to_string_lossy().into_owned();
    assert!(
        wait_for(Duration::from_secs(10), || processes_mentioning(&needle)
            .is_empty()),
        "the experiments end once reproduce is killed"
    );
    assert_eq!(
        temporaries(&tmp.0).len(),
        1,
        "SIGKILL leaves the partial folder"
    );
    // The next run into the same folder removes it (here the cheapest run there is).
    assert_success(&identify_into(&out, &[]), "the next run");
    assert!(temporaries(&tmp.0).is_empty(), "the stale folder is gone");
}
