//! The Kirchhoff model for one configuration ([`single`]) or a JSON Lines batch ([`Batch`]),
//! as `ftwire solve` answers them.
//!
//! A batch line is one [`Request`], `{"c": [C1, C2, C3], "length": L, "a": [A1, .., A6]}` with
//! optional `"radius"` and `"nodes"`, answered by [`answer`]. A bad line (malformed JSON,
//! bytes that are not UTF-8, a value out of range) gets an error naming the line and the
//! batch goes on; a line obeys the bounds of the single solve (`"nodes"` within the model's
//! `[MIN_NODES, MAX_NODES]`, the radius below half the length), and a byte-order mark before
//! the first line is dropped. [`BatchTally`] sums the batch up: bad input if any line was,
//! else no answer if any line had none (an integration that diverged); [`serve`] answers a
//! batch line by line, as `ftwire solve --batch` does.
//!
//! Guarded by this module's tests and `crates/ftwire/tests/solve_cli.rs`.

use std::fmt;
use std::io::{self, BufRead, BufReader, Write};
use std::path::Path;

use ftwire_app::input::CountRange;
use ftwire_app::output::{ErrorLine, JsonLines};

use ftwire_core::{CoreError, WireParams, text};
use ftwire_rod::rod::{MAX_NODES, MIN_NODES};
use ftwire_rod::{DEFAULT_NODES, Load, Rod, Solution};
use nalgebra::{Vector3, Vector6};
use serde::{Deserialize, Serialize};

use crate::error::{EXIT_BAD_INPUT, LabError, from_rod};

/// `--nodes` (and a batch line's `"nodes"`): the model's own range. The shape (positions and
/// rotations), the costates and the self-contact search grow in proportion to the nodes, a
/// couple of hundred bytes each, so a million stay well under a gigabyte.
pub const NODES: CountRange = CountRange::new(MIN_NODES, MAX_NODES);

/// One configuration to solve, and the wire's load.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveParams {
    /// The wire.
    pub wire: WireParams,
    /// The configuration `a = (τ1, τ2, τ3, f1, f2, f3)`: the wrench on the base gripper,
    /// torque \[N·m\] first, then force \[N\], base clamp frame.
    pub a: [f64; 6],
    /// Shape nodes from `t = 0` to `t = L`, both ends included.
    pub nodes: usize,
    /// Gravity \[m/s²\] in the base clamp frame: the loaded model with the wire's weight;
    /// `None`: no weight.
    pub gravity: Option<Vector3<f64>>,
    /// The wire's density \[kg/m³\], for its weight under [`Self::gravity`].
    pub density: f64,
    /// Natural (rest) strains \[1/m\] in the body frame; `None`: a straight, untwisted wire.
    pub natural_curvature: Option<Vector3<f64>>,
}

impl SolveParams {
    /// The load: the weight `density · π · radius² · gravity` with [`Self::gravity`], the
    /// rest strains with [`Self::natural_curvature`], none without them.
    ///
    /// # Errors
    /// Bad input for a load the model refuses (a density that is not positive, ...).
    pub fn load(&self) -> Result<Load, LabError> {
        let weight = match self.gravity {
            Some(g) => Load::from_gravity(self.density, self.wire.radius(), g),
            None => Ok(Load::none()),
        };
        let load = match self.natural_curvature {
            Some(k) => weight.and_then(|l| l.with_natural_curvature(k)),
            None => weight,
        };
        load.map_err(|e| LabError::bad_input(format!("invalid load: {e}")))
    }

    /// Bad settings refused before solving ([`Self::load`]).
    ///
    /// # Errors
    /// As [`Self::load`].
    pub fn check(&self) -> Result<(), LabError> {
        self.load().map(|_| ())
    }
}

/// Solves one configuration.
///
/// # Errors
/// As [`SolveParams::load`] and [`solve`].
pub fn single(params: &SolveParams) -> Result<SingleSolve, LabError> {
    let load = params.load()?;
    let solution = solve(params.wire, load, &params.a, params.nodes)?;
    Ok(SingleSolve {
        output: SolveOutput::from(&solution),
        wire: params.wire,
        load,
        a: params.a,
        solution,
    })
}

/// Solves one configuration with `nodes` shape nodes.
///
/// # Errors
/// Every failure sorted by [`from_rod`]: an integration that diverged is no answer, anything
/// else (a configuration outside `A`, node counts) bad input.
pub fn solve(
    wire: WireParams,
    load: Load,
    a: &[f64; 6],
    nodes: usize,
) -> Result<Solution, LabError> {
    Rod::new(wire)
        .with_load(load)
        .solve(&Vector6::from(*a), nodes)
        .map_err(|e| from_rod(e, "solve"))
}

/// One batch request.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Request {
    /// Stiffnesses `(c1, c2, c3)` \[N·m²\]: three values.
    pub c: Vec<f64>,
    /// Length \[m\].
    pub length: f64,
    /// The configuration, torque first \[N·m, N\]: six values.
    pub a: Vec<f64>,
    /// Radius \[m\] (default: the simulator's wire's).
    #[serde(default)]
    pub radius: Option<f64>,
    /// Shape nodes (default [`DEFAULT_NODES`]).
    #[serde(default)]
    pub nodes: Option<usize>,
}

/// The answer to one batch line (a [`Request`] in JSON).
///
/// # Errors
/// Bad input for a line that is not a request or has values out of range (three `c`, six
/// `a`, a valid wire with its radius below half its length, `nodes` within the model's
/// range); as [`solve`] otherwise.
///
/// # Example
/// ```
/// use ftwire_lab::solve::answer;
/// let solution = answer(r#"{"c": [0.042, 0.055, 0.055], "length": 0.63, "a": [0, 0, 0.01, 0, 0, 0]}"#)?;
/// assert!(solution.jacobian.stability.stable);
/// let error = answer(r#"{"c": [0.1, 0.1], "length": 0.63, "a": [0, 0, 0, 0, 0, 0]}"#).err();
/// assert_eq!(error.map(|e| e.kind()), Some("bad_input"));
/// # Ok::<(), ftwire_lab::LabError>(())
/// ```
pub fn answer(line: &str) -> Result<Solution, LabError> {
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
    let radius = request.radius.unwrap_or_else(crate::wire::default_radius);
    let wire = crate::wire::from_numbers(c, request.length, radius, ["radius", "length"])?;
    let nodes = request.nodes.unwrap_or(DEFAULT_NODES);
    NODES
        .check_value("nodes", nodes)
        .map_err(LabError::bad_input)?;
    solve(wire, Load::none(), &a, nodes)
}

/// One answered line of a batch.
#[derive(Debug)]
pub struct BatchLine {
    /// The line's number in the input, from 1.
    pub line: usize,
    /// Its answer, or what was wrong (the message starts with `line N: `).
    pub answer: Result<SolveOutput, LabError>,
}

/// The answers of a JSON Lines batch read from `input`, one per line that is not blank, each
/// as soon as its line is read (so that a process can drive the batch as a service: one line
/// in, one answer out).
#[derive(Debug)]
pub struct Batch<R> {
    input: R,
    number: usize,
    bytes: Vec<u8>,
}

impl<R: BufRead> Batch<R> {
    /// The batch of `input` (a file, or stdin).
    pub fn new(input: R) -> Self {
        Self {
            input,
            number: 0,
            bytes: Vec::new(),
        }
    }

    /// The next line's answer; `None` at the end of the input, `Some(Ok(None))` for a blank
    /// line.
    fn read_line(&mut self) -> Option<Result<Option<BatchLine>, LabError>> {
        self.number += 1;
        let number = self.number;
        self.bytes.clear();
        match self.input.read_until(b'\n', &mut self.bytes) {
            Ok(0) => return None,
            Ok(_) => {}
            Err(e) => {
                return Some(Err(LabError::io(
                    format!("reading line {number} of the batch"),
                    e,
                )));
            }
        }
        // A byte-order mark that an editor put before the first line is not part of it.
        let line = if number == 1 {
            text::strip_bom(&self.bytes)
        } else {
            &self.bytes
        };
        let answer = match text::utf8(line) {
            Ok(line) if line.trim().is_empty() => return Some(Ok(None)),
            Ok(line) => answer(line).map(|solution| SolveOutput::from(&solution)),
            Err(e) => Err(LabError::bad_input(match e {
                CoreError::NotUtf8 { column, byte, .. } => format!(
                    "column {column}: byte 0x{byte:02X} is not valid UTF-8; a batch is UTF-8 text"
                ),
                e => e.to_string(),
            })),
        };
        Some(Ok(Some(BatchLine {
            line: number,
            answer: answer.map_err(|e| e.context(format!("line {number}"))),
        })))
    }
}

/// Each answered line in order; an error that ends the batch (the input cannot be read) is
/// the last item.
impl<R: BufRead> Iterator for Batch<R> {
    type Item = Result<BatchLine, LabError>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            match self.read_line()? {
                Ok(None) => continue,
                Ok(Some(line)) => return Some(Ok(line)),
                Err(e) => return Some(Err(e)),
            }
        }
    }
}

/// The lines of a batch without an answer, by kind.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BatchTally {
    /// Lines that were bad input.
    pub bad_input: usize,
    /// Lines without an answer.
    pub no_answer: usize,
}

impl BatchTally {
    /// Counts one line's error.
    pub fn count(&mut self, error: &LabError) {
        if error.exit_code() == EXIT_BAD_INPUT {
            self.bad_input += 1;
        } else {
            self.no_answer += 1;
        }
    }

    /// The batch's verdict: `Ok` if every line was answered.
    ///
    /// # Errors
    /// Bad input if any line was, else no answer if any line had none.
    pub fn verdict(&self) -> Result<(), LabError> {
        let summary = format!(
            "{} line(s) of the batch were bad input and {} had no answer; see their error \
             objects",
            self.bad_input, self.no_answer
        );
        if self.bad_input > 0 {
            Err(LabError::bad_input(summary))
        } else if self.no_answer > 0 {
            Err(LabError::no_answer(summary))
        } else {
            Ok(())
        }
    }
}

/// The input of a batch: stdin for `-`, else the file at `path` (a regular file; `option`
/// names the input as the caller's front end spells it, `--batch` on the command line).
///
/// # Errors
/// Bad input for a folder or a file that cannot be opened.
pub fn batch_input(path: &Path, option: &str) -> Result<Box<dyn BufRead>, LabError> {
    if path.as_os_str() == "-" {
        return Ok(Box::new(io::stdin().lock()));
    }
    if path.is_dir() {
        return Err(LabError::bad_input(format!(
            "{option} {}: a folder, not a file; give a JSON Lines file, or - for stdin",
            path.display()
        )));
    }
    let file = text::open_regular(path).map_err(|e| {
        LabError::bad_input(format!("cannot open batch file {}: {e}", path.display()))
    })?;
    Ok(Box::new(BufReader::new(file)))
}

/// Answers every line of `input` on `out` as soon as it is read, so that another process can
/// drive the batch as a service (one line in, one flushed line out): the line's answer, or
/// its error object ([`ErrorLine`]), and the batch goes on.
///
/// # Errors
/// [`LabError::Io`] when the input cannot be read or `out` written; at the end of the input,
/// the batch's verdict ([`BatchTally::verdict`]).
pub fn serve<W: Write>(input: impl BufRead, out: &mut JsonLines<W>) -> Result<(), LabError> {
    let mut tally = BatchTally::default();
    for line in Batch::new(input) {
        let line = line?;
        match &line.answer {
            Ok(answer) => out.write(answer)?,
            Err(error) => {
                tally.count(error);
                out.write(&ErrorLine::new(error, line.line))?;
            }
        }
    }
    tally.verdict()
}

/// The tip's pose.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Tip {
    /// Position \[m\], base clamp frame.
    pub position: [f64; 3],
    /// Rotation matrix, row-major, base clamp frame from tip clamp frame.
    pub rotation: [[f64; 3]; 3],
}

/// The JSON answer of one solve (a batch line's, or a single solve's with `--json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolveOutput {
    /// The tip's pose, base clamp frame.
    pub tip: Tip,
    /// `J(L)`, rows `(δω, δv)`.
    pub jacobian: [[f64; 6]; 6],
    /// Whether the configuration is stable.
    pub stable: bool,
    /// Whether the wire touches itself.
    pub self_intersecting: bool,
    /// The stability record's smallest `|det J(t)|`.
    pub det_j_min: f64,
    /// Node positions \[m\], base clamp frame.
    pub shape: Vec<[f64; 3]>,
}

impl From<&Solution> for SolveOutput {
    fn from(s: &Solution) -> Self {
        let tip = &s.jacobian.tip;
        let r = tip.rotation.to_rotation_matrix();
        let j = &s.jacobian.jacobian;
        Self {
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

/// A single solve: serialised as its [`SolveOutput`]; its text (its [`fmt::Display`]) a
/// human summary of the wire, the load, the tip and the stability.
#[derive(Debug, Serialize)]
pub struct SingleSolve {
    /// The JSON answer.
    #[serde(flatten)]
    pub output: SolveOutput,
    /// The wire solved.
    #[serde(skip)]
    pub wire: WireParams,
    /// Its load.
    #[serde(skip)]
    pub load: Load,
    /// The configuration.
    #[serde(skip)]
    pub a: [f64; 6],
    /// The model's solution.
    #[serde(skip)]
    pub solution: Solution,
}

impl fmt::Display for SingleSolve {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.solution;
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

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str =
        r#"{"c": [0.042, 0.055, 0.055], "length": 0.63, "a": [0, 0, 0.01, 0, 0, 0], "nodes": 11}"#;

    #[test]
    fn a_served_batch_answers_each_line_at_once_and_sums_up() {
        let input = format!("{GOOD}\n{{not json\n{GOOD}\n");
        let mut out = JsonLines::new(Vec::new());
        let verdict = serve(input.as_bytes(), &mut out).expect_err("a bad line");
        assert_eq!(verdict.exit_code(), EXIT_BAD_INPUT);
        assert!(
            verdict
                .to_string()
                .starts_with("1 line(s) of the batch were bad input and 0")
        );
        let text = String::from_utf8(out.into_inner()).expect("UTF-8");
        let lines: Vec<serde_json::Value> = text
            .lines()
            .map(|l| serde_json::from_str(l).expect("a JSON line"))
            .collect();
        assert_eq!(lines.len(), 3, "{text}");
        assert!(
            lines[0].get("tip").is_some() && lines[2].get("tip").is_some(),
            "{text}"
        );
        assert_eq!(lines[1]["kind"], "bad_input");
        assert_eq!(lines[1]["line"], 2);
        let mut out = JsonLines::new(Vec::new());
        assert!(serve(GOOD.as_bytes(), &mut out).is_ok());
        let folder = batch_input(&std::env::temp_dir(), "--batch").err();
        let message = folder.map(|e| e.to_string()).unwrap_or_default();
        assert!(message.starts_with("--batch ") && message.contains("a folder, not a file"));
    }

    #[test]
    fn a_batch_answers_each_line_and_names_the_bad_ones() {
        let input = format!(
            "\u{feff}{GOOD}\n\n{{not json\n{}\n{}\n",
            GOOD.replace("0.63", "0.001"),
            GOOD.replace("11", "1")
        );
        let lines: Vec<BatchLine> = Batch::new(input.as_bytes())
            .collect::<Result<_, _>>()
            .expect("the input reads");
        assert_eq!(
            lines.iter().map(|l| l.line).collect::<Vec<_>>(),
            [1, 3, 4, 5],
            "the blank line 2 has no answer"
        );
        let first = lines[0].answer.as_ref().expect("the BOM is dropped");
        assert_eq!(first.shape.len(), 11);
        let mut tally = BatchTally::default();
        for (line, needle) in lines[1..]
            .iter()
            .zip(["invalid request", "radius", "nodes 1:"])
        {
            let error = line.answer.as_ref().expect_err("a bad line");
            let message = error.to_string();
            assert!(
                message.starts_with(&format!("line {}: ", line.line)),
                "{message}"
            );
            assert!(message.contains(needle), "{message}");
            tally.count(error);
        }
        assert_eq!(
            tally,
            BatchTally {
                bad_input: 3,
                no_answer: 0
            }
        );
        assert_eq!(tally.verdict().expect_err("bad lines").kind(), "bad_input");
        assert!(BatchTally::default().verdict().is_ok());
    }

    #[test]
    fn a_single_solve_refuses_a_bad_load_and_reports_its_tip() {
        let mut params = SolveParams {
            wire: WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("a wire"),
            a: [0.0, 0.0, 0.01, 0.0, 0.0, 0.0],
            nodes: DEFAULT_NODES,
            gravity: Some(Vector3::new(0.0, 0.0, -9.81)),
            density: -1.0,
            natural_curvature: None,
        };
        let error = params.check().expect_err("a negative density");
        assert!(error.to_string().starts_with("invalid load: "), "{error}");
        params.gravity = None;
        let single = single(&params).expect("solves");
        // A pure moment τ3 bends the weightless wire into an arc in the x-y plane.
        assert!(single.output.tip.position[2].abs() < 1e-9);
        let text = single.to_string();
        assert!(
            text.starts_with("wire: c = [0.042, 0.055, 0.055] N·m²"),
            "{text}"
        );
        assert!(!text.contains("load:"), "no load line without a load");
    }
}
