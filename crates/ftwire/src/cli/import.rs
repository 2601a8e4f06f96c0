//! Arguments of `ftwire import <format>`: recordings made elsewhere to ftwire's log.
//!
//! Units in `--help` are written `[m]`, not as escaped Markdown, hence the allowed "links".
#![allow(rustdoc::broken_intra_doc_links)]

use std::path::PathBuf;

use clap::{Args, Subcommand};
use ftwire::args::parse_finite;

/// `ftwire import <format>`.
#[derive(Debug, Clone, Args)]
pub struct ImportArgs {
    /// The format of the recording.
    #[command(subcommand)]
    pub format: ImportFormat,
}

/// The formats.
#[derive(Debug, Clone, Subcommand)]
pub enum ImportFormat {
    /// A ROS 2 bag in MCAP storage: one log line per rest of the second gripper, with the
    /// wrench averaged over the rest (`raw`, force first, sensor frame), the tip pose (`b`)
    /// and the markers, for `ftwire shape --log`, `identify --log` and `calibrate --log`.
    Mcap(McapArgs),
}

/// `ftwire import mcap BAG.mcap --wrench TOPIC --tip-pose TOPIC --out LOG.jsonl`.
///
/// A rest is a run of tip poses that all stay within `--rest-position-mm` and
/// `--rest-angle-rad` of the run's first pose for at least `--min-rest-s`; its wrench is
/// averaged from `--settle-s` after its start to its end; the line's `time` is the rest's end
/// [s] on the messages' header stamps. Messages that cannot be used (non-finite values, a
/// wrong frame, stamps going backwards) are skipped and counted in the summary on stderr.
#[derive(Debug, Clone, Args)]
pub struct McapArgs {
    /// The bag: an MCAP file as `ros2 bag record -s mcap` writes it.
    #[arg(value_name = "BAG.mcap")]
    pub bag: PathBuf,
    /// The wrench topic (geometry_msgs/msg/WrenchStamped, at the sensor's rate): force [N]
    /// and torque [N·m] in the sensor frame, as the sensor gives them.
    #[arg(long, value_name = "TOPIC")]
    pub wrench: String,
    /// The tip pose topic (geometry_msgs/msg/PoseStamped): the second gripper's clamp pose
    /// relative to the base clamp, position [m].
    #[arg(long, value_name = "TOPIC")]
    pub tip_pose: String,
    /// The markers topic (geometry_msgs/msg/PoseArray): marker positions [m] in the base
    /// clamp frame, in order along the wire; a NaN position is a dropout (null in the log).
    #[arg(long, value_name = "TOPIC")]
    pub markers: Option<String>,
    /// The log to write (JSON Lines).
    #[arg(long, value_name = "LOG.jsonl")]
    pub out: PathBuf,
    /// Replace `--out` if it exists.
    #[arg(long)]
    pub force: bool,
    /// How far the tip may move during a rest [mm] [default: 1].
    #[arg(long, value_name = "MM", value_parser = parse_finite, allow_hyphen_values = true)]
    pub rest_position_mm: Option<f64>,
    /// How far the tip may turn during a rest [rad] [default: 0.01].
    #[arg(long, value_name = "RAD", value_parser = parse_finite, allow_hyphen_values = true)]
    pub rest_angle_rad: Option<f64>,
    /// The shortest rest, settle time included [s] [default: 1.5]; above --settle-s.
    #[arg(long, value_name = "S", value_parser = parse_finite, allow_hyphen_values = true)]
    pub min_rest_s: Option<f64>,
    /// Left out at each rest's start while the wire settles [s] [default: 1].
    #[arg(long, value_name = "S", value_parser = parse_finite, allow_hyphen_values = true)]
    pub settle_s: Option<f64>,
    /// The frame_id every wrench must have; others are skipped [default: any].
    #[arg(long, value_name = "FRAME")]
    pub wrench_frame: Option<String>,
    /// The frame_id every tip pose must have; others are skipped [default: any].
    #[arg(long, value_name = "FRAME")]
    pub tip_frame: Option<String>,
    /// The frame_id every markers message must have; others are skipped [default: any].
    #[arg(long, value_name = "FRAME")]
    pub markers_frame: Option<String>,
}
