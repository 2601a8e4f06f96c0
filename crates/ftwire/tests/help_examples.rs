//! Every example of every `--help` runs as printed: each command's examples, in order, in a
//! fresh folder (with the repository's `scenes/` beside it, as from a clone's root), through
//! `sh` with the built binary first on `PATH`, each exits 0. A help whose example needs what
//! no earlier line of it makes fails here.

mod cli_support;

use std::path::Path;
use std::process::Command;

use cli_support::{TempDir, assert_success, ftwire};

/// The subcommands listed in `help`'s "Commands:" section (but `help`).
fn subcommands(help: &str) -> Vec<String> {
    help.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_owned)
        .collect()
}

/// The example command lines of `help`: lines that start with `ftwire ` or pipe into it,
/// joined over a trailing `\`.
fn examples(help: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut lines = help.lines().map(str::trim);
    while let Some(line) = lines.next() {
        if !(line.starts_with("ftwire ") || line.contains("| ftwire ")) {
            continue;
        }
        let mut command = line.to_owned();
        while command.ends_with('\\') {
            command.pop();
            command.push_str(lines.next().unwrap_or(""));
        }
        found.push(command);
    }
    found
}

/// Every command path (`["experiment", "calibrate"]`) with its help text.
fn helps() -> Vec<(Vec<String>, String)> {
    let mut pending = vec![Vec::<String>::new()];
    let mut all = Vec::new();
    while let Some(path) = pending.pop() {
        let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
        args.push("--help");
        let output = ftwire(&args);
        assert_success(&output, &args.join(" "));
        let help = String::from_utf8(output.stdout).expect("UTF-8 help");
        for sub in subcommands(&help) {
            let mut child = path.clone();
            child.push(sub);
            pending.push(child);
        }
        all.push((path, help));
    }
    all
}

#[test]
fn every_help_example_runs_as_printed() {
    let binary = Path::new(env!("CARGO_BIN_EXE_ftwire"));
    let bin_dir = binary.parent().expect("the binary's folder");
    let path = format!(
        "{}:{}",
        bin_dir.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    // Each command's examples in order, the commands at once (CI has two cores).
    let helps = helps();
    let ran: usize = std::thread::scope(|s| {
        let runs: Vec<_> = helps
            .iter()
            .map(|(command, help)| {
                let (path, scenes) = (&path, &scenes);
                s.spawn(move || {
                    let lines = examples(help);
                    if lines.is_empty() {
                        return 0;
                    }
                    let tmp = TempDir::new(&format!("help-example-{}", command.join("-")));
                    std::os::unix::fs::symlink(scenes, tmp.0.join("scenes"))
                        .expect("links scenes/");
                    for line in &lines {
                        let output = Command::new("sh")
                            .arg("-c")
                            .arg(line)
                            .env("PATH", path)
                            .current_dir(&tmp.0)
                            .output()
                            .expect("sh runs");
                        assert_success(&output, &format!("{}: {line}", command.join(" ")));
                    }
                    lines.len()
                })
            })
            .collect();
        runs.into_iter()
            .map(|run| run.join().expect("a command's examples pass"))
            .sum()
    });
    // calibrate 2, identify 2, plan 2, shape 3, solve 3 at least.
    assert!(ran >= 12, "only {ran} examples found");
}

#[test]
fn examples_are_found_and_joined() {
    let help =
        "Examples:\n  ftwire a --x 1 \\\n    --y 2\n  echo '{}' | ftwire b -\n\nftwire-like text";
    assert_eq!(
        examples(help),
        ["ftwire a --x 1 --y 2", "echo '{}' | ftwire b -"]
    );
    let listing = "Usage: x\n\nCommands:\n  solve  Solve\n  help   Print\n\nOptions:\n";
    assert_eq!(subcommands(listing), ["solve"]);
}
