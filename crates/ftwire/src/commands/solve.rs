//! `ftwire solve`: the Kirchhoff model for one configuration or a JSON Lines batch.
//!
//! Exit codes: 0 on success (a batch succeeds even when some lines are bad; those lines print
//! `{"error": ...}`), 2 for a bad argument (clap's usage errors and our own validation), 1 for
//! an I/O failure while writing.

use std::fs::File;
use std::io::{self, BufRead, BufReader, BufWriter, Write};
use std::process::ExitCode;

use anyhow::Context;
use ftwire_rod::{DEFAULT_NODES, Rod, Solution, WireParams};
use nalgebra::Vector6;
use serde::{Deserialize, Serialize};

use crate::cli::solve::{DEFAULT_RADIUS, SolveArgs};

/// Runs `ftwire solve`.
pub fn run(args: SolveArgs) -> anyhow::Result<ExitCode> {
    match &args.batch {
        Some(path) => run_batch(path),
        None => run_single(&args),
    }
}

/// A validation error that should exit with code 2.
fn usage_error(message: impl std::fmt::Display) -> anyhow::Result<ExitCode> {
    eprintln!("error: {message}");
    Ok(ExitCode::from(2))
}

fn run_single(args: &SolveArgs) -> anyhow::Result<ExitCode> {
    let request = Request {
        c: args.c.clone().unwrap_or_default(),
        length: args.length.unwrap_or(f64::NAN),
        a: args.a.clone().unwrap_or_default(),
        radius: args.radius,
        nodes: args.nodes,
    };
    let solution = match request.solve() {
        Ok(s) => s,
        Err(message) => return usage_error(message),
    };
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    if args.json {
        serde_json::to_writer(&mut out, &Output::from(&solution))?;
        writeln!(out)?;
    } else {
        write_summary(&mut out, &request, &solution)?;
    }
    out.flush().context("writing the solution to stdout")?;
    Ok(ExitCode::SUCCESS)
}

/// A batch always prints JSON Lines, so `--json` changes nothing there.
fn run_batch(path: &std::path::Path) -> anyhow::Result<ExitCode> {
    let input: Box<dyn BufRead> = if path.as_os_str() == "-" {
        Box::new(BufReader::new(io::stdin().lock()))
    } else {
        match File::open(path) {
            Ok(f) => Box::new(BufReader::with_capacity(1 << 16, f)),
            Err(e) => {
                return usage_error(format!("cannot open batch file {}: {e}", path.display()));
            }
        }
    };
    let stdout = io::stdout();
    let mut out = BufWriter::with_capacity(1 << 16, stdout.lock());
    for (number, line) in input.lines().enumerate() {
        let line = line.with_context(|| format!("reading line {} of the batch", number + 1))?;
        if line.trim().is_empty() {
            continue;
        }
        let result = serde_json::from_str::<Request>(&line)
            .map_err(|e| format!("line {}: invalid request: {e}", number + 1))
            .and_then(|r| r.solve().map_err(|e| format!("line {}: {e}", number + 1)));
        match result {
            Ok(solution) => serde_json::to_writer(&mut out, &Output::from(&solution))?,
            Err(error) => serde_json::to_writer(&mut out, &ErrorLine { error })?,
        }
        out.write_all(b"\n")?;
    }
    out.flush().context("writing the batch results to stdout")?;
    Ok(ExitCode::SUCCESS)
}

/// One solve request (a batch line, or the flags).
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

impl Request {
    fn solve(&self) -> Result<Solution, String> {
        let c: [f64; 3] =
            self.c.as_slice().try_into().map_err(|_| {
                format!("c must have 3 values C1,C2,C3 [N·m²], got {}", self.c.len())
            })?;
        let a: [f64; 6] = self.a.as_slice().try_into().map_err(|_| {
            format!(
                "a must have 6 values τ1,τ2,τ3,f1,f2,f3, got {}",
                self.a.len()
            )
        })?;
        let wire = WireParams::new(c, self.length, self.radius.unwrap_or(DEFAULT_RADIUS))
            .map_err(|e| e.to_string())?;
        Rod::new(wire)
            .solve(&Vector6::from(a), self.nodes.unwrap_or(DEFAULT_NODES))
            .map_err(|e| e.to_string())
    }
}

#[derive(Serialize)]
struct ErrorLine {
    error: String,
}

#[derive(Serialize)]
struct Tip {
    position: [f64; 3],
    rotation: [[f64; 3]; 3],
}

/// The JSON output of one solve (keys as documented in the issue and `--help`).
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

fn write_summary(out: &mut impl Write, request: &Request, s: &Solution) -> io::Result<()> {
    let tip = &s.jacobian.tip;
    let p = tip.translation.vector;
    let axis_angle = tip.rotation.scaled_axis();
    let stability = &s.jacobian.stability;
    writeln!(
        out,
        "wire: c = {:?} N·m², L = {} m, a = {:?}",
        request.c, request.length, request.a
    )?;
    writeln!(
        out,
        "tip position  [m]:   ({:+.6}, {:+.6}, {:+.6})",
        p.x, p.y, p.z
    )?;
    writeln!(
        out,
        "tip rotation  [rad]: {:.6} about ({:+.4}, {:+.4}, {:+.4})",
        axis_angle.norm(),
        axis_angle.x / axis_angle.norm().max(f64::MIN_POSITIVE),
        axis_angle.y / axis_angle.norm().max(f64::MIN_POSITIVE),
        axis_angle.z / axis_angle.norm().max(f64::MIN_POSITIVE),
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
