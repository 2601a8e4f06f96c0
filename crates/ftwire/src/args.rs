//! Argument groups and value parsers shared by the `ftwire` subcommands.
//!
//! Each group is one `#[derive(Args)]` struct, flattened (`#[command(flatten)]`) into the
//! commands that use it, so that every command spells, parses, checks and documents an option
//! the same way. Defaults come from the library presets (`ftwire_lab::wire::default_radius` and the like,
//! the simulator's default rod), never from numbers copied here.
//!
//! The value parsers and count ranges are [`ftwire_app::input`]'s (re-exported here): vectors
//! are comma separated, `X,Y,Z`; a leading minus sign is allowed in both `--opt -1,2,3` and
//! `--opt=-1,2,3` (the options take hyphen values); a bad value is bad input (exit 2) naming
//! the option.
//!
//! The options' doc comments are clap's `--help` text, which shows them verbatim: their units
//! are written `[m]`, not as escaped Markdown, and placeholders `<run>`, not as code spans, hence
//! the allowed "links" and "HTML tags" below.
#![allow(rustdoc::broken_intra_doc_links, rustdoc::invalid_html_tags)]

use std::path::PathBuf;

use clap::Args;
use ftwire_core::Pose;
use ftwire_robot::pose_from_vectors;
use serde::Serialize;

use ftwire_lab::error::LabError;

pub use ftwire_app::input::{
    CountRange, Numbers, Vec3, Vec6, Vec7, parse_finite, parse_numbers, parse_rotation,
};

/// The value parser of every count option (`value_parser = Count(RANGE)`):
/// [`CountRange::check`] with the option's name.
#[derive(Debug, Clone, Copy)]
pub struct Count(pub CountRange);

impl clap::builder::TypedValueParser for Count {
    type Value = usize;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<usize, clap::Error> {
        let name = arg
            .and_then(clap::Arg::get_long)
            .map_or_else(|| "the value".to_owned(), |long| format!("--{long}"));
        self.0
            .check(&name, &value.to_string_lossy())
            .map_err(|message| {
                clap::Error::raw(clap::error::ErrorKind::ValueValidation, message)
                    .format(&mut cmd.clone())
            })
    }
}

/// The wire: stiffnesses, length and radius.
///
/// Commands read it through [`WireArgs::params`], not field by field, so that how the wire is
/// put together from the options (and checked) is decided in that one method.
#[derive(Debug, Clone, Args, Serialize)]
pub struct WireArgs {
    /// Stiffnesses C1,C2,C3 [N·m²]: torsion, bending about body y, bending about body z.
    #[arg(
        long,
        value_name = "C1,C2,C3",
        allow_hyphen_values = true,
        value_parser = parse_numbers::<3>
    )]
    pub c: Option<Vec3>,
    /// Wire length L between the clamp points [m].
    #[arg(
        long,
        value_name = "L",
        allow_hyphen_values = true,
        value_parser = parse_finite
    )]
    pub length: Option<f64>,
    /// Wire radius [m] (self-intersection, contact and weight).
    #[arg(
        long,
        value_name = "R",
        default_value_t = ftwire_lab::wire::default_radius(),
        allow_hyphen_values = true,
        value_parser = parse_finite
    )]
    pub radius: f64,
}

impl WireArgs {
    /// The validated wire.
    ///
    /// # Errors
    /// Bad input: `--c` or `--length` missing, a value that is not finite and positive, or a
    /// radius of half the length or more ([`ftwire_lab::wire::from_numbers`]).
    pub fn params(&self) -> Result<ftwire_core::WireParams, LabError> {
        let c = self
            .c
            .ok_or_else(|| LabError::bad_input("the wire needs --c C1,C2,C3"))?;
        let length = self
            .length
            .ok_or_else(|| LabError::bad_input("the wire needs --length L"))?;
        ftwire_lab::wire::from_numbers(c.0, length, self.radius, ["--radius", "--length"])
    }
}

/// The wire's weight: its density (the radius is in [`WireArgs`]).
#[derive(Debug, Clone, Args, Serialize)]
pub struct DensityArgs {
    /// Material density [kg/m³] (the default is nitinol's).
    #[arg(
        long,
        value_name = "RHO",
        default_value_t = ftwire_lab::wire::default_density(),
        allow_hyphen_values = true,
        value_parser = parse_finite
    )]
    pub density: f64,
}

/// A target pose: `--position` and `--rotation` (a rotation vector, axis × angle).
#[derive(Debug, Clone, Args, Serialize)]
pub struct PoseArgs {
    /// Target position [m]: X,Y,Z.
    #[arg(
        long,
        value_name = "X,Y,Z",
        allow_hyphen_values = true,
        value_parser = parse_numbers::<3>
    )]
    pub position: Vec3,
    /// Target rotation as a rotation vector (axis times angle) [rad]: RX,RY,RZ, of norm at most
    /// 1e6.
    #[arg(
        long,
        value_name = "RX,RY,RZ",
        allow_hyphen_values = true,
        value_parser = parse_rotation
    )]
    pub rotation: Vec3,
}

impl PoseArgs {
    /// The pose.
    pub fn pose(&self) -> Pose {
        pose_from_vectors(self.position.to_vector(), self.rotation.to_vector())
    }
}

/// The tip clamp's pose in the base clamp frame: `--tip-position`, `--tip-rotation`.
#[derive(Debug, Clone, Args, Serialize)]
pub struct TipPoseArgs {
    /// Tip clamp position [m] in the base clamp frame: X,Y,Z.
    #[arg(
        long,
        value_name = "X,Y,Z",
        allow_hyphen_values = true,
        value_parser = parse_numbers::<3>
    )]
    pub tip_position: Vec3,
    /// Tip clamp orientation as a rotation vector (axis × angle) [rad] in the base clamp frame:
    /// RX,RY,RZ, of norm at most 1e6.
    #[arg(
        long,
        value_name = "RX,RY,RZ",
        allow_hyphen_values = true,
        value_parser = parse_rotation
    )]
    pub tip_rotation: Vec3,
}

impl TipPoseArgs {
    /// The tip clamp pose.
    pub fn pose(&self) -> Pose {
        pose_from_vectors(self.tip_position.to_vector(), self.tip_rotation.to_vector())
    }
}

/// The seed of every random choice of a command (same seed, same result).
#[derive(Debug, Clone, Copy, Args, Serialize)]
pub struct SeedArgs {
    /// Seed of every random choice; the same seed gives the same result.
    #[arg(
        long,
        value_name = "SEED",
        default_value_t = 0,
        allow_hyphen_values = true
    )]
    pub seed: u64,
}

/// Print JSON instead of the human-readable text.
#[derive(Debug, Clone, Copy, Args, Serialize)]
pub struct JsonArgs {
    /// Print JSON instead of a human-readable summary.
    #[arg(long)]
    pub json: bool,
}

/// Where a run writes its results folder (see [`ftwire_lab::results::ResultsFolder`]): `--out` and
/// `--force`.
#[derive(Debug, Clone, Default, Args, Serialize)]
pub struct ResultsArgs {
    /// Results folder [default: results/<run>, e.g. results/demo]. Written whole into a
    /// temporary sibling and renamed into place at the end. An existing folder is replaced
    /// only when an earlier ftwire run wrote it (it holds `.ftwire-results`) or it is empty;
    /// its parent must exist.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Replace `--out` even when it is a folder ftwire did not write, with everything in it.
    /// A folder that holds one of the run's inputs or the working folder is never replaced.
    #[arg(long)]
    #[serde(skip)]
    pub force: bool,
}

impl ResultsArgs {
    /// Opens the results folder: `--out`, or `results/<id>`, guarded by `--force` and the
    /// run's `inputs` (see [`ftwire_lab::results::OutGuard`]).
    ///
    /// # Errors
    /// As [`ftwire_lab::results::ResultsFolder::create_or_default`].
    pub fn open(
        &self,
        id: &str,
        inputs: ftwire_lab::results::OutGuard,
    ) -> Result<ftwire_lab::results::ResultsFolder, LabError> {
        // Every path on the command line is an input too (one place for every option).
        let guard = inputs
            .with_force(self.force)
            .command_line(std::env::args_os().skip(1));
        ftwire_lab::results::ResultsFolder::create_or_default(self.out.as_deref(), id, &guard)
    }
}

/// The simulated rig: `--sensor PRESET|FILE.toml` and `--rig FILE.toml` (see
/// [`ftwire_lab::setup`]; every key in `docs/config.md`). Left out of a run header when not given, so
/// that a run with the default sensor and rig writes a header without `sensor` or `rig` keys.
#[derive(Debug, Clone, Default, Args, Serialize)]
pub struct SimSetupArgs {
    /// The simulated F/T sensor: `distorted` (the default sensor: gain, cross-talk and
    /// nonlinearity of about 1 %, noise, bias, drift and dropouts), `undistorted` (the same
    /// without gain, cross-talk and nonlinearity: what a perfect calibration gives),
    /// `real-like` (as a real recording shows a sensor: the clamp 0.11 m out, offsets of
    /// 1–2 N and 0.1–0.4 N·m no tare removes, a weak torsion channel, one reading's scatter,
    /// a hysteresis of 0.12–0.15 N and 0.012 N·m, no drift), or a sensor file (TOML;
    /// `ftwire init` writes an example) [default: distorted].
    #[arg(long, value_name = "PRESET|FILE.toml")]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensor: Option<String>,
    /// The simulated rig (TOML: motion capture, execution error, move timing; `ftwire init`
    /// writes an example) [default: the library's rig].
    #[arg(long, value_name = "FILE.toml")]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rig: Option<PathBuf>,
    /// How a calibration session is recorded (the calibration an experiment collects, and
    /// `--save-log`'s recording): `rests`, each configuration placed anew, tared, and its
    /// reading averaged at rest (the paper's), or `single-readings`, as a real rig logs one:
    /// the gripper stepping about 17 mm from rest to rest through one region it sweeps again
    /// and again, one reading per record at 4 Hz, 2–3 records at some rests, the sensor tared
    /// once and its hysteresis carried along, the markers glued off the centreline, the wire
    /// softening in bending as nitinol does (no model knows it) [default: rests].
    #[arg(long, value_name = "PROTOCOL",
          value_parser = clap::builder::PossibleValuesParser::new(ftwire_lab::setup::Protocol::NAMES))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub protocol: Option<String>,
}

impl SimSetupArgs {
    /// `--protocol` (the parser admits only its names).
    pub fn protocol(&self) -> ftwire_lab::setup::Protocol {
        self.protocol
            .as_deref()
            .and_then(ftwire_lab::setup::Protocol::from_name)
            .unwrap_or_default()
    }

    /// The sensor and the rig.
    ///
    /// # Errors
    /// Bad input naming the file, the line and the key.
    pub fn load(&self) -> Result<ftwire_lab::setup::SimSetup, LabError> {
        ftwire_lab::setup::SimSetup::load(self.sensor.as_deref(), self.rig.as_deref())
            .map(|s| s.with_protocol(self.protocol()))
            .map_err(|e| LabError::bad_input(e.to_string()))
    }
}

/// The value parser of a library enum named by words (`--gravity on|off`, `--model
/// kirchhoff|loaded`): `--help` lists the names, and a wrong one is refused by clap with the
/// allowed ones (exit 2).
pub fn named<T>(names: &'static [&'static str]) -> impl clap::builder::TypedValueParser<Value = T>
where
    T: std::str::FromStr<Err = String> + Clone + Send + Sync + 'static,
{
    use clap::builder::TypedValueParser as _;
    clap::builder::PossibleValuesParser::new(names).try_map(|name| name.parse::<T>())
}
