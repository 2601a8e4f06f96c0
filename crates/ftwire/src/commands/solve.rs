//! `ftwire solve`: the Kirchhoff model for one configuration or a JSON Lines batch.
//!
//! The batch answers each line as soon as it is read, on one flushed line, so that another
//! process can drive `ftwire solve --batch -` as a service (one line in, one line out). A bad
//! line (malformed JSON, bytes that are not UTF-8, a value out of range) gets an error object
//! `{"error", "kind", "line"}` and the batch goes on; a line obeys the bounds of the flags
//! (`"nodes"` those of `--nodes`, the radius below half the length), and a byte-order mark
//! before the first line is dropped. At the end of the input the exit code sums the batch up:
//! 0 if every line was answered, 2 if any line was bad input, else 1 if any line had no answer
//! (an integration that diverged).

use std::fs::File;
use std::io::{self, BufRead, BufReader, Write};
use std::path::Path;

use ftwire::args::{check_radius, default_radius};
use ftwire::output::{self, ErrorLine, JsonLines, Report};
use ftwire_core::text;
use ftwire_lab::error::{EXIT_BAD_INPUT, LabError, from_rod};
use ftwire_rod::{DEFAULT_NODES, Load, Rod, Solution, WireParams};
use nalgebra::Vector6;
use serde::{Deserialize, Serialize};

use crate::cli::solve::{NODES, SolveArgs};

/// Runs `ftwire solve`.
pub fn run(args: SolveArgs) -> Result<(), LabError> {
    match &args.batch {
        Some(path) => run_batch(path),
        None => run_single(&args),
    }
}

fn run_single(args: &SolveArgs) -> Result<(), LabError> {
    let wire = args.wire.params()?;
    let a = args
        .a
        .ok_or_else(|| LabError::bad_input("solve needs --a A1,..,A6"))?;
    let load = load(args, &wire)?;
    let solution = solve(wire, load, &a.0, args.nodes)?;
    let report = SingleReport {
        output: Output::from(&solution),
        wire,
        load,
        a: a.0,
        solution: &solution,
    };
    output::print(&report, args.output.json)
}

/// The load of `--gravity`, `--density` (with the wire's radius) and `--natural-curvature`;
/// none without them.
fn load(args: &SolveArgs, wire: &WireParams) -> Result<Load, LabError> {
    let weight = match &args.gravity {
        Some(g) => Load::from_gravity(args.density.density, wire.radius(), g.to_vector()),
        None => Ok(Load::none()),
    };
    let load = match &args.natural_curvature {
        Some(k) => weight.and_then(|l| l.with_natural_curvature(k.to_vector())),
        None => weight,
    };
    load.map_err(|e| LabError::bad_input(format!("invalid load: {e}")))
}

/// Solves one configuration; every failure is sorted into bad input or no answer.
fn solve(wire: WireParams, load: Load, a: &[f64; 6], nodes: usize) -> Result<Solution, LabError> {
    Rod::new(wire)
        .with_load(load)
        .solve(&Vector6::from(*a), nodes)
        .map_err(|e| from_rod(e, "solve"))
}

/// A batch always prints JSON Lines, so `--json` changes nothing there.
fn run_batch(path: &Path) -> Result<(), LabError> {
    let mut input: Box<dyn BufRead> = if path.as_os_str() == "-" {
        Box::new(io::stdin().lock())
    } else {
        if path.is_dir() {
            return Err(LabError::bad_input(format!(
                "--batch {}: a folder, not a file; give a JSON Lines file, or - for stdin",
                path.display()
            )));
        }
        let file = File::open(path).map_err(|e| {
            LabError::bad_input(format!("cannot open batch file {}: {e}", path.display()))
        })?;
        Box::new(BufReader::new(file))
    };
    let mut out = JsonLines::new(io::stdout().lock());
    let (mut bad_input, mut no_answer) = (0_usize, 0_usize);
    let mut bytes = Vec::new();
    for number in 1.. {
        bytes.clear();
        let read = input
            .read_until(b'\n', &mut bytes)
            .map_err(|e| LabError::io(format!("reading line {number} of the batch"), e))?;
        if read == 0 {
            break;
        }
        // A byte-order mark that an editor put before the first line is not part of it.
        let line = if number == 1 {
            text::strip_bom(&bytes)
        } else {
            &bytes
        };
        let result = match text::utf8(line) {
            Ok(line) if line.trim().is_empty() => continue,
            Ok(line) => answer(line),
            Err(e) => Err(LabError::bad_input(match e {
                ftwire_core::CoreError::NotUtf8 { column, byte, .. } => format!(
                    "column {column}: byte 0x{byte:02X} is not valid UTF-8; a batch is UTF-8 text"
                ),
                e => e.to_string(),
            })),
        };
        match result {
            Ok(solution) => out.write(&Output::from(&solution))?,
            Err(error) => {
                if error.exit_code() == EXIT_BAD_INPUT {
                    bad_input += 1;
                } else {
                    no_answer += 1;
                }
                let error = error.context(format!("line {number}"));
                out.write(&ErrorLine::new(&error, number))?;
            }
        }
    }
    let summary = format!(
        "{bad_input} line(s) of the batch were bad input and {no_answer} had no answer; \
         see their error objects"
    );
    if bad_input > 0 {
        Err(LabError::bad_input(summary))
    } else if no_answer > 0 {
        Err(LabError::no_answer(summary))
    } else {
        Ok(())
    }
}

/// The answer to one batch line.
fn answer(line: &str) -> Result<Solution, LabError> {
    let request: Request = serde_json::from_str(line)
        .map_err(|e| LabError::bad_input(format!("invalid request: {e}")))?;
    let c: [f64; 3] = request.c.as_slice().try_into().map_err(|_| {
        LabError::bad_input(format!(
            "c must have 3 values C1,C2,C3 [N·m²], got {}",
            request.c.len()
        ))
    })?;
    let a: [f64; 6] = request.a.as_slice().try_into().map_err(|_| {
        LabError::bad_input(format!(
            "a must have 6 values τ1,τ2,τ3,f1,f2,f3, got {}",
            request.a.len()
        ))
    })?;
    let radius = request.radius.unwrap_or_else(default_radius);
    let wire = WireParams::new(c, request.length, radius)
        .map_err(|e| LabError::bad_input(format!("invalid wire: {e}")))?;
    check_radius(&wire, "radius", "length").map_err(LabError::bad_input)?;
    let nodes = match request.nodes {
        Some(nodes) => NODES
            .check_value("nodes", nodes)
            .map_err(LabError::bad_input)?,
        None => DEFAULT_NODES,
    };
    solve(wire, Load::none(), &a, nodes)
}

/// One batch request.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Request {
    c: Vec<f64>,
    length: f64,
    a: Vec<f64>,
    #[serde(default)]
    radius: Option<f64>,
    #[serde(default)]
    nodes: Option<usize>,
}

#[derive(Serialize)]
struct Tip {
    position: [f64; 3],
    rotation: [[f64; 3]; 3],
}

/// The JSON output of one solve: `tip` (`position` \[m\], row-major `rotation`, base clamp
/// frame), `jacobian` `J(L)` (rows `(δω, δv)`), `stable`, `self_intersecting`, `det_j_min` (the
/// stability record's smallest `|det J(t)|`) and `shape` (node positions \[m\], base clamp
/// frame).
#[derive(Serialize)]
struct Output {
    tip: Tip,
    jacobian: [[f64; 6]; 6],
    stable: bool,
    self_intersecting: bool,
    det_j_min: f64,
    shape: Vec<[f64; 3]>,
}

impl From<&Solution> for Output {
    fn from(s: &Solution) -> Self {
        let tip = &s.jacobian.tip;
        let r = tip.rotation.to_rotation_matrix();
        let j = &s.jacobian.jacobian;
        Output {
            tip: Tip {
                position: tip.translation.vector.into(),
                rotation: std::array::from_fn(|i| std::array::from_fn(|k| r[(i, k)])),
            },
            jacobian: std::array::from_fn(|i| std::array::from_fn(|k| j[(i, k)])),
            stable: s.jacobian.stability.stable,
            self_intersecting: s.self_intersecting,
            det_j_min: s.jacobian.stability.det_j_min,
            shape: s.shape.positions.iter().map(|p| [p.x, p.y, p.z]).collect(),
        }
    }
}

/// A single solve: the JSON [`Output`], or the human summary.
#[derive(Serialize)]
struct SingleReport<'a> {
    #[serde(flatten)]
    output: Output,
    #[serde(skip)]
    wire: WireParams,
    #[serde(skip)]
    load: Load,
    #[serde(skip)]
    a: [f64; 6],
    #[serde(skip)]
    solution: &'a Solution,
}

impl Report for SingleReport<'_> {
    fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        let s = self.solution;
        let tip = &s.jacobian.tip;
        let p = tip.translation.vector;
        let axis_angle = tip.rotation.scaled_axis();
        let angle = axis_angle.norm();
        let axis = axis_angle / angle.max(f64::MIN_POSITIVE);
        let stability = &s.jacobian.stability;
        writeln!(
            out,
            "wire: c = {:?} N·m², L = {} m, a = {:?}",
            self.wire.c(),
            self.wire.length(),
            self.a
        )?;
        if !self.load.is_none() {
            let (w, k) = (self.load.weight_per_length, self.load.natural_curvature);
            writeln!(
                out,
                "load: w = ({:+.4e}, {:+.4e}, {:+.4e}) N/m, u₀ = ({:+.4}, {:+.4}, {:+.4}) 1/m",
                w.x, w.y, w.z, k.x, k.y, k.z
            )?;
        }
        writeln!(
            out,
            "tip position  [m]:   ({:+.6}, {:+.6}, {:+.6})",
            p.x, p.y, p.z
        )?;
        writeln!(
            out,
            "tip rotation  [rad]: {angle:.6} about ({:+.4}, {:+.4}, {:+.4})",
            axis.x, axis.y, axis.z,
        )?;
        writeln!(
            out,
            "det J(L):           {:.6e}",
            s.jacobian.jacobian.determinant()
        )?;
        match stability.first_sign_change {
            None => writeln!(
                out,
                "stable:             yes (min |det J| = {:.3e})",
                stability.det_j_min
            )?,
            Some([t0, t1]) => writeln!(
                out,
                "stable:             no (det J changes sign in t ∈ [{t0:.4}, {t1:.4}] m)"
            )?,
        }
        writeln!(
            out,
            "self-intersecting:  {}",
            if s.self_intersecting { "yes" } else { "no" }
        )?;
        writeln!(
            out,
            "shape:              {} nodes (use --json for them)",
            s.shape.len()
        )
    }
}
