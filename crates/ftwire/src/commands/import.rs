//! `ftwire import <format>`: a recording made elsewhere to ftwire's JSON Lines log. The work
//! is [`ftwire_ros2::import`]'s; this command maps the options, guards `--out`, writes the log
//! and prints a one-line summary on stderr.

use std::io::Write;
use std::path::Path;

use ftwire_estimate::log::to_line;
use ftwire_lab::error::LabError;
use ftwire_ros2::bag::BagReader;
use ftwire_ros2::import::{self, ImportParams, RestParams};

use crate::cli::import::{ImportArgs, ImportFormat, McapArgs};

/// Converts the recording to ftwire's JSON Lines log.
pub fn run(args: ImportArgs) -> Result<(), LabError> {
    match args.format {
        ImportFormat::Mcap(args) => mcap(&args),
    }
}

/// The library's settings of `args`: the rest settings in SI units, the defaults where not
/// given.
fn params(args: &McapArgs) -> ImportParams {
    let defaults = RestParams::default();
    ImportParams {
        wrench_topic: args.wrench.clone(),
        tip_pose_topic: args.tip_pose.clone(),
        markers_topic: args.markers.clone(),
        rest: RestParams {
            position_tolerance: args
                .rest_position_mm
                .map_or(defaults.position_tolerance, |mm| mm * 1e-3),
            angle_tolerance: args.rest_angle_rad.unwrap_or(defaults.angle_tolerance),
            min_duration: args.min_rest_s.unwrap_or(defaults.min_duration),
            settle: args.settle_s.unwrap_or(defaults.settle),
        },
        wrench_frame: args.wrench_frame.clone(),
        tip_frame: args.tip_frame.clone(),
        markers_frame: args.markers_frame.clone(),
    }
}

/// Refuses an `--out` that exists (without `--force`) or that is the bag itself.
fn guard_out(args: &McapArgs) -> Result<(), LabError> {
    let out = &args.out;
    let same = match (out.canonicalize(), args.bag.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if same {
        return Err(LabError::bad_input(format!(
            "--out {} is the bag being read: give another file",
            out.display()
        )));
    }
    if out.is_dir() {
        return Err(LabError::bad_input(format!(
            "--out {} is a folder: give a file name, such as {}",
            out.display(),
            out.join("log.jsonl").display()
        )));
    }
    if out.exists() && !args.force {
        return Err(LabError::bad_input(format!(
            "--out {} exists: give another file, or --force to replace it",
            out.display()
        )));
    }
    Ok(())
}

/// `ftwire import mcap`.
fn mcap(args: &McapArgs) -> Result<(), LabError> {
    let params = params(args);
    params.rest.check().map_err(|e| {
        LabError::bad_input(format!(
            "{e} (--rest-position-mm, --rest-angle-rad, --min-rest-s, --settle-s)"
        ))
    })?;
    guard_out(args)?;
    let bag = BagReader::open(&args.bag).map_err(|e| LabError::bad_input(e.to_string()))?;
    let import = import::import(&bag, &params).map_err(|e| LabError::bad_input(e.to_string()))?;
    let summary = &import.summary;
    if import.records.is_empty() {
        return Err(LabError::no_answer(format!(
            "{}: no rest found, so no log is written ({summary}); a rest needs the tip pose \
             within --rest-position-mm and --rest-angle-rad for --min-rest-s, with wrench \
             samples after --settle-s",
            args.bag.display()
        )));
    }
    let mut text = String::new();
    for record in &import.records {
        let line = to_line(record).map_err(|e| LabError::bad_input(e.to_string()))?;
        text.push_str(&line);
        text.push('\n');
    }
    write_replacing(&args.out, text.as_bytes())?;
    eprintln!(
        "ftwire import mcap: {} -> {}: {summary}",
        args.bag.display(),
        args.out.display()
    );
    Ok(())
}

/// Writes `bytes` to a temporary sibling of `path` and renames it into place, so that `path`
/// is never left half written.
fn write_replacing(path: &Path, bytes: &[u8]) -> Result<(), LabError> {
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
