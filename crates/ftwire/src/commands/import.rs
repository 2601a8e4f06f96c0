//! `ftwire import <format>`: a recording made elsewhere to ftwire's JSON Lines log. The work
//! is [`ftwire_ros2::import`]'s; this command maps the options, guards `--out` and writes the
//! log ([`ftwire_app::out_file`]), and prints a one-line summary on stderr.

use ftwire_app::out_file::OutFile;
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

/// `ftwire import mcap`.
fn mcap(args: &McapArgs) -> Result<(), LabError> {
    let params = params(args);
    params.rest.check().map_err(|e| {
        LabError::bad_input(format!(
            "{e} (--rest-position-mm, --rest-angle-rad, --min-rest-s, --settle-s)"
        ))
    })?;
    let out = OutFile {
        path: &args.out,
        option: "--out",
        force_option: "--force",
        force: args.force,
    };
    out.check(&args.bag, "the bag being read", "log.jsonl")?;
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
    out.write(text.as_bytes())?;
    errln!(
        "ftwire import mcap: {} -> {}: {summary}",
        args.bag.display(),
        args.out.display()
    );
    Ok(())
}
