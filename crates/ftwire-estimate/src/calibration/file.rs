//! The calibration weights file: one JSON document that other commands load.
//!
//! Format version 1 (`FORMAT_VERSION`), written by [`Calibration::to_json`] and
//! [`Calibration::save`]:
//!
//! ```text
//! {
//!   "format": "ftwire-calibration",          // always this string
//!   "version": 1,                            // FORMAT_VERSION
//!   "architecture": {
//!     "inputs": 6, "outputs": 6,             // raw reading (force first) → a (torque first)
//!     "hidden": [64, 64],                    // hidden widths
//!     "activation": "tanh"                   // or "gelu"; the output layer is linear
//!   },
//!   "input_normaliser":  { "mean": [6 numbers], "std": [6 numbers > 0] },   // raw units
//!   "output_normaliser": { "mean": [6 numbers], "std": [6 numbers > 0] },   // a's units
//!   "affine": { "matrix": [6 rows of 6], "offset": [6] } | null,            // normalised units
//!   "polynomial": { "degree": 2 | 3,         // optional: W φ(z), the monomials of degree 2
//!     "weights": [6 rows of 21 | 77] },      // to d of z (`Polynomial`), normalised units
//!   "layers": [                              // first hidden layer to output layer
//!     { "weights": [outputs rows of inputs numbers], "bias": [outputs numbers] }, ...
//!   ],
//!   "training": { ... },                     // TrainingRecord: seed, config, split sizes,
//!                                            // epochs, losses, test RMSE, history
//!   "drift": {                               // optional: the offset's drift (`Drift`)
//!     "reference_time": s, "rate": [6],      // in a's units per second
//!     "span": [first s, last s]              // the session's times: never extrapolated
//!   },                                       // beyond them (absent: the drift left out)
//!   "model": {                               // the wire model of the labels (`LabelModel`;
//!     "kind": "weightless" | "loaded",       // absent: weightless)
//!     "gravity_in_clamp": [x, y, z] | null   // m/s², base clamp frame, with "loaded"
//!   },
//!   "input": "raw" | "tared"                 // the map's input (absent: raw)
//! }
//! ```
//!
//! The map is `a = F(raw) − F(0)` when `training.config.anchored` (absent: `false`), else
//! `a = F(raw)`, with `F(raw) = μ_out + σ_out ⊙ (A z + c + W φ(z) + f(z))`, `z = (raw − μ_in) ⊘ σ_in` (see
//! [`Calibration`]); when `training.config.through_zero` (absent: `false`, so older files keep
//! their meaning) the network's term is `ρ f(z)`, `ρ = q / (1 + q)`, `q = |raw ⊘ σ_in|²`. Numbers are written shortest-round-trip and read back exactly, so a saved
//! calibration loads bit-identical (guarded by `tests/calibration_file.rs`). Loading checks the
//! format and version, every array's length against the architecture, and that every number is
//! finite (and every `std` positive), and names the offending array.

use std::path::Path;

use nalgebra::{Matrix6, Vector6};
use serde::{Deserialize, Serialize};

use super::{
    Activation, Affine, Calibration, CalibrationInput, LabelModel, Mlp, Normaliser, Polynomial,
    TrainingRecord,
};
use crate::EstimateError;

/// The `format` string of a calibration file.
pub const FORMAT_NAME: &str = "ftwire-calibration";

/// The format version this build writes and reads.
pub const FORMAT_VERSION: u32 = 1;

/// The first two fields, read before the rest so that a newer file gets a version error.
#[derive(Deserialize)]
struct Header {
    format: String,
    version: u32,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CalibrationFile {
    format: String,
    version: u32,
    architecture: Architecture,
    input_normaliser: NormaliserFile,
    output_normaliser: NormaliserFile,
    affine: Option<AffineFile>,
    /// The polynomial part (absent: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    polynomial: Option<PolynomialFile>,
    layers: Vec<LayerFile>,
    training: TrainingRecord,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    drift: Option<DriftFile>,
    /// The label model (absent in older files: weight-free).
    #[serde(default)]
    model: LabelModel,
    /// The map's input (absent in older files: raw).
    #[serde(default)]
    input: CalibrationInput,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct DriftFile {
    reference_time: f64,
    rate: [f64; 6],
    /// The session's first and last time (absent in older files: the drift is left out).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    span: Option<[f64; 2]>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Architecture {
    inputs: usize,
    outputs: usize,
    hidden: Vec<usize>,
    activation: Activation,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct NormaliserFile {
    mean: [f64; 6],
    std: [f64; 6],
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct AffineFile {
    matrix: [[f64; 6]; 6],
    offset: [f64; 6],
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct PolynomialFile {
    degree: usize,
    weights: Vec<Vec<f64>>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LayerFile {
    weights: Vec<Vec<f64>>,
    bias: Vec<f64>,
}

impl Calibration {
    /// The calibration as a JSON document in the format of the module docs.
    ///
    /// # Errors
    /// [`EstimateError::CalibrationSyntax`] if serialisation fails (it does not for the types
    /// here).
    pub fn to_json(&self) -> Result<String, EstimateError> {
        serde_json::to_string_pretty(&self.to_file()).map_err(syntax_error)
    }

    /// A calibration from a JSON document in the format of the module docs.
    ///
    /// # Errors
    /// [`EstimateError::CalibrationSyntax`] for malformed JSON, a missing or unknown field or
    /// the wrong `format`; [`EstimateError::CalibrationVersion`] for another format version;
    /// [`EstimateError::CalibrationShape`] for an array of the wrong length;
    /// [`EstimateError::CalibrationValue`] for a non-finite number or a non-positive `std`;
    /// [`EstimateError::InvalidSetting`] for hidden widths out of range.
    pub fn from_json(json: &str) -> Result<Self, EstimateError> {
        let header: Header = serde_json::from_str(json).map_err(syntax_error)?;
        if header.format != FORMAT_NAME {
            return Err(EstimateError::CalibrationSyntax {
                line: 0,
                column: 0,
                message: format!("format is {:?}, expected {FORMAT_NAME:?}", header.format),
            });
        }
        if header.version != FORMAT_VERSION {
            return Err(EstimateError::CalibrationVersion {
                found: header.version,
                supported: FORMAT_VERSION,
            });
        }
        let file: CalibrationFile = serde_json::from_str(json).map_err(syntax_error)?;
        Self::from_file(file)
    }

    /// Writes the calibration to `path` as JSON.
    ///
    /// # Errors
    /// [`EstimateError::CalibrationIo`] when the file cannot be written.
    pub fn save(&self, path: &Path) -> Result<(), EstimateError> {
        std::fs::write(path, self.to_json()?).map_err(|e| io_error(path, &e))
    }

    /// Reads a calibration written by [`Calibration::save`].
    ///
    /// # Errors
    /// [`EstimateError::CalibrationIo`] when the file cannot be read,
    /// [`EstimateError::CalibrationSyntax`] with the line and column when it is not UTF-8 (a
    /// leading byte-order mark is allowed); otherwise as [`Calibration::from_json`].
    pub fn load(path: &Path) -> Result<Self, EstimateError> {
        let mut bytes = Vec::new();
        std::fs::metadata(path).map_err(|e| io_error(path, &e))?;
        let file =
            ftwire_core::text::open_regular(path).map_err(|e| EstimateError::CalibrationIo {
                path: path.to_path_buf(),
                kind: std::io::ErrorKind::InvalidInput,
                message: e.to_string(),
            })?;
        std::io::Read::read_to_end(
            &mut std::io::Read::take(file, ftwire_core::text::MAX_TEXT_BYTES),
            &mut bytes,
        )
        .map_err(|e| io_error(path, &e))?;
        let json = ftwire_core::text::decode(&bytes).map_err(|e| match e {
            ftwire_core::CoreError::NotUtf8 {
                line, column, byte, ..
            } => EstimateError::CalibrationSyntax {
                line,
                column,
                message: format!("byte 0x{byte:02X} is not valid UTF-8; the file must be UTF-8"),
            },
            e => EstimateError::CalibrationSyntax {
                line: 0,
                column: 0,
                message: e.to_string(),
            },
        })?;
        Self::from_json(json)
    }

    fn to_file(&self) -> CalibrationFile {
        let normaliser = |n: &Normaliser| NormaliserFile {
            mean: (*n.mean()).into(),
            std: (*n.std()).into(),
        };
        let layers = self
            .mlp()
            .layers()
            .map(|(inputs, weights, bias)| LayerFile {
                weights: weights.chunks_exact(inputs).map(<[f64]>::to_vec).collect(),
                bias: bias.to_vec(),
            })
            .collect();
        CalibrationFile {
            format: FORMAT_NAME.into(),
            version: FORMAT_VERSION,
            architecture: Architecture {
                inputs: 6,
                outputs: 6,
                hidden: self.mlp().hidden().to_vec(),
                activation: self.mlp().activation(),
            },
            input_normaliser: normaliser(self.input_normaliser()),
            output_normaliser: normaliser(self.output_normaliser()),
            affine: self.affine().map(|a| AffineFile {
                matrix: std::array::from_fn(|i| std::array::from_fn(|j| a.matrix[(i, j)])),
                offset: a.offset.into(),
            }),
            polynomial: self.polynomial().map(|p| PolynomialFile {
                degree: p.degree(),
                weights: p.weights().to_vec(),
            }),
            layers,
            training: self.record().clone(),
            drift: self.drift().map(|d| DriftFile {
                reference_time: d.reference_time,
                rate: d.rate.into(),
                span: d.span,
            }),
            model: *self.model(),
            input: self.input(),
        }
    }

    fn from_file(file: CalibrationFile) -> Result<Self, EstimateError> {
        let architecture = &file.architecture;
        for (what, found) in [
            ("architecture.inputs", architecture.inputs),
            ("architecture.outputs", architecture.outputs),
        ] {
            if found != 6 {
                return Err(EstimateError::CalibrationShape {
                    what: what.into(),
                    expected: 6,
                    found,
                });
            }
        }
        let hidden = &architecture.hidden;
        let widths: Vec<usize> = std::iter::once(6)
            .chain(hidden.iter().copied())
            .chain(std::iter::once(6))
            .collect();
        if file.layers.len() != hidden.len() + 1 {
            return Err(EstimateError::CalibrationShape {
                what: "layers".into(),
                expected: hidden.len() + 1,
                found: file.layers.len(),
            });
        }
        let mut parameters = Vec::new();
        for (l, (layer, shape)) in file.layers.iter().zip(widths.windows(2)).enumerate() {
            let [inputs, outputs] = [shape[0], shape[1]];
            check_len(
                &format!("layers[{l}].weights"),
                outputs,
                layer.weights.len(),
            )?;
            for (j, row) in layer.weights.iter().enumerate() {
                let what = format!("layers[{l}].weights[{j}]");
                check_len(&what, inputs, row.len())?;
                check_finite(&what, row)?;
                parameters.extend_from_slice(row);
            }
            let what = format!("layers[{l}].bias");
            check_len(&what, outputs, layer.bias.len())?;
            check_finite(&what, &layer.bias)?;
            parameters.extend_from_slice(&layer.bias);
        }
        let mlp = Mlp::from_parameters(hidden, architecture.activation, parameters)?;
        let input = normaliser("input_normaliser", &file.input_normaliser)?;
        let output = normaliser("output_normaliser", &file.output_normaliser)?;
        let affine = match &file.affine {
            None => None,
            Some(a) => {
                for (i, row) in a.matrix.iter().enumerate() {
                    check_finite(&format!("affine.matrix[{i}]"), row)?;
                }
                check_finite("affine.offset", &a.offset)?;
                Some(Affine {
                    matrix: Matrix6::from_fn(|i, j| a.matrix[i][j]),
                    offset: Vector6::from(a.offset),
                })
            }
        };
        let polynomial = match file.polynomial {
            None => None,
            Some(p) => {
                for (i, row) in p.weights.iter().enumerate() {
                    check_finite(&format!("polynomial.weights[{i}]"), row)?;
                }
                Some(Polynomial::new(p.degree, p.weights)?)
            }
        };
        if let Some(rmse) = &file.training.test_rmse {
            // The test error becomes every shape's error bar: a reading's size at most.
            let torque_force = "from 0 to 1e3 N·m for a torque, to 1e4 N for a force";
            for (index, (&value, max)) in rmse
                .iter()
                .zip([MAX_RMSE_TORQUE; 3].into_iter().chain([MAX_RMSE_FORCE; 3]))
                .enumerate()
            {
                if !(value.is_finite() && (0.0..=max).contains(&value)) {
                    return Err(EstimateError::CalibrationValue {
                        what: "training.test_rmse".into(),
                        index,
                        value,
                        allowed: torque_force,
                    });
                }
            }
        }
        let calibration = Self::from_parts(input, output, affine, mlp, file.training)
            .with_polynomial(polynomial)
            .with_provenance(file.model, file.input)?;
        match &file.drift {
            None => Ok(calibration),
            Some(d) => {
                check_finite("drift.rate", &d.rate)?;
                let time = "finite times [s], at most 1e10 in size";
                check_within("drift.reference_time", &[d.reference_time], MAX_TIME, time)?;
                if let Some(span) = &d.span {
                    check_within("drift.span", span, MAX_TIME, time)?;
                }
                calibration.with_drift(super::Drift {
                    reference_time: d.reference_time,
                    rate: Vector6::from(d.rate),
                    span: d.span,
                })
            }
        }
    }
}

/// A normaliser from its saved form, naming the offending entry.
fn normaliser(what: &str, file: &NormaliserFile) -> Result<Normaliser, EstimateError> {
    check_finite(&format!("{what}.mean"), &file.mean)?;
    if let Some((index, &value)) = file
        .std
        .iter()
        .enumerate()
        .find(|(_, s)| !(s.is_finite() && **s >= 1e-12 && **s <= MAX_VALUE))
    {
        return Err(EstimateError::CalibrationValue {
            what: format!("{what}.std"),
            index,
            value,
            allowed: "numbers from 1e-12 to 1e6",
        });
    }
    Normaliser::from_parts(Vector6::from(file.mean), Vector6::from(file.std)).ok_or_else(|| {
        EstimateError::CalibrationValue {
            what: what.into(),
            index: 0,
            value: f64::NAN,
            allowed: "finite means and positive finite stds",
        }
    })
}

fn check_len(what: &str, expected: usize, found: usize) -> Result<(), EstimateError> {
    if expected == found {
        Ok(())
    } else {
        Err(EstimateError::CalibrationShape {
            what: what.into(),
            expected,
            found,
        })
    }
}

/// Largest size of a number of a calibration file (weights, biases, normalisers, the affine
/// part, the drift rate): a trained map's are of order 1 (normalised units) or of the
/// readings' (N, N·m); one above this is a damaged file whose every answer would overflow.
pub const MAX_VALUE: f64 = 1e6;

/// Largest test error of a torque channel in a calibration file \[N·m\]
/// (`training.test_rmse`): the largest plausible torque reading ([`crate::log::MAX_TORQUE`]).
pub const MAX_RMSE_TORQUE: f64 = crate::log::MAX_TORQUE;

/// Largest test error of a force channel in a calibration file \[N\]
/// (`training.test_rmse`): the largest plausible force reading ([`crate::log::MAX_FORCE`]).
pub const MAX_RMSE_FORCE: f64 = crate::log::MAX_FORCE;

/// Largest time of a calibration file \[s\] (`drift.reference_time`, `drift.span`).
pub const MAX_TIME: f64 = 1e10;

fn check_finite(what: &str, values: &[f64]) -> Result<(), EstimateError> {
    check_within(
        what,
        values,
        MAX_VALUE,
        "finite numbers, at most 1e6 in size",
    )
}

fn check_within(
    what: &str,
    values: &[f64],
    max: f64,
    allowed: &'static str,
) -> Result<(), EstimateError> {
    match values
        .iter()
        .enumerate()
        .find(|(_, v)| !(v.is_finite() && v.abs() <= max))
    {
        None => Ok(()),
        Some((index, &value)) => Err(EstimateError::CalibrationValue {
            what: what.into(),
            index,
            value,
            allowed,
        }),
    }
}

fn syntax_error(e: serde_json::Error) -> EstimateError {
    EstimateError::CalibrationSyntax {
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    }
}

fn io_error(path: &Path, e: &std::io::Error) -> EstimateError {
    EstimateError::CalibrationIo {
        path: path.to_path_buf(),
        kind: e.kind(),
        message: e.to_string(),
    }
}
