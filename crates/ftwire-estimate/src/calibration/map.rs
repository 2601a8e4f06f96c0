//! The learnt calibration map from a raw F/T reading to the configuration `a`.

use nalgebra::Vector6;
use serde::{Deserialize, Serialize};

use super::record::TrainingRecord;
use super::{Affine, Mlp, Normaliser, Polynomial};

/// A trained F/T calibration (paper §IV-A): raw reading (force first, sensor frame, tared) in,
/// configuration `a` (torque first, base clamp frame) out.
///
/// The map is `a = F(raw) − F(0)` (anchored, [`TrainParams::anchored`](super::TrainParams::anchored),
/// for tared readings) or `a = F(raw)`, with `F(raw) = μ_a + σ_a ⊙ (A z + c + f(z))` and
/// `z = (raw − μ_raw) ⊘ σ_raw`: per-channel standardisation fitted on the training split, an
/// optional least-squares affine part `A z + c` ([`Affine`]) and the network `f` ([`Mlp`]) that
/// learns what the affine part leaves. Trained
/// [`through_zero`](super::TrainParams::through_zero), the affine part is zero at a zero
/// reading and the network's term is `ρ(raw) f(z)`, `ρ = q / (1 + q)`, `q = |raw ⊘ σ_raw|²`, so
/// that `F(0) = 0` exactly.
///
/// Build one with [`Calibration::train`]; save and load it with [`Calibration::save`] and
/// [`Calibration::load`] (format in [`super::file`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Calibration {
    input: Normaliser,
    output: Normaliser,
    affine: Option<Affine>,
    /// The polynomial part `W φ(z)` (`None`: none).
    polynomial: Option<Polynomial>,
    mlp: Mlp,
    /// `F(0)` when anchored (zero otherwise): subtracted from every output.
    anchor: Vector6<f64>,
    /// The sensor's offset drift, learnt from a recording (`None`: no drift term).
    drift: Option<Drift>,
    /// The wire model the labels were made with.
    model: LabelModel,
    /// Whether the map's input is the raw reading or the tared one.
    input_kind: CalibrationInput,
    pub(crate) record: TrainingRecord,
}

/// The wire model a calibration's labels were made with (`calibration.json`'s `model`):
/// weight-free, or loaded under gravity in the base clamp frame. A shape solved from the map's
/// `a` should use the same model.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LabelModel {
    /// `weightless` or `loaded`.
    pub kind: LabelModelKind,
    /// Gravity in the base clamp frame \[m/s²\] of the loaded model; `None` for the
    /// weight-free one.
    pub gravity_in_clamp: Option<[f64; 3]>,
}

/// The kind of a [`LabelModel`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LabelModelKind {
    /// The paper's model: no weight.
    #[default]
    Weightless,
    /// The loaded rod: the wire's weight under gravity.
    Loaded,
}

impl LabelModel {
    /// Largest gravity a loaded label model may name \[m/s²\].
    pub const MAX_GRAVITY: f64 = 100.0;

    /// The weight-free model.
    pub const WEIGHTLESS: Self = Self {
        kind: LabelModelKind::Weightless,
        gravity_in_clamp: None,
    };

    /// The loaded model under `gravity_in_clamp` \[m/s²\], base clamp frame.
    ///
    /// # Errors
    /// [`crate::EstimateError::CalibrationValue`] for a gravity not finite, zero, or above
    /// [`Self::MAX_GRAVITY`].
    pub fn loaded(gravity_in_clamp: [f64; 3]) -> Result<Self, crate::EstimateError> {
        let model = Self {
            kind: LabelModelKind::Loaded,
            gravity_in_clamp: Some(gravity_in_clamp),
        };
        model.check()?;
        Ok(model)
    }

    /// Checks the model: a loaded one names a finite gravity of norm in `(0, MAX_GRAVITY]`,
    /// a weight-free one none.
    ///
    /// # Errors
    /// [`crate::EstimateError::CalibrationValue`] naming `model.gravity_in_clamp`.
    pub fn check(&self) -> Result<(), crate::EstimateError> {
        let bad = |value: f64, allowed: &'static str| crate::EstimateError::CalibrationValue {
            what: "model.gravity_in_clamp".into(),
            index: 0,
            value,
            allowed,
        };
        match (self.kind, self.gravity_in_clamp) {
            (LabelModelKind::Weightless, None) => Ok(()),
            (LabelModelKind::Weightless, Some(g)) => Err(bad(
                g[0],
                "null for a weightless model (kind \"loaded\" names a gravity)",
            )),
            (LabelModelKind::Loaded, None) => {
                Err(bad(f64::NAN, "three numbers [m/s²] for a loaded model"))
            }
            (LabelModelKind::Loaded, Some(g)) => {
                let norm = g.iter().map(|v| v * v).sum::<f64>().sqrt();
                if norm.is_finite() && norm > 0.0 && norm <= Self::MAX_GRAVITY {
                    Ok(())
                } else {
                    Err(bad(
                        norm,
                        "a finite gravity of norm above 0 and at most 100 m/s²",
                    ))
                }
            }
        }
    }
}

impl std::fmt::Display for LabelModel {
    fn fmt(&self, out: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.gravity_in_clamp {
            None => write!(out, "weightless"),
            Some([x, y, z]) => write!(out, "loaded, gravity in the clamp frame {x},{y},{z} m/s²"),
        }
    }
}

/// What a calibration's input is (`calibration.json`'s `input`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CalibrationInput {
    /// The sensor's reading as it comes, offset and all (trained on readings never tared).
    #[default]
    Raw,
    /// The reading less a tare taken with nothing in the gripper.
    Tared,
}

impl std::fmt::Display for CalibrationInput {
    fn fmt(&self, out: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        out.write_str(match self {
            Self::Raw => "raw",
            Self::Tared => "tared",
        })
    }
}

/// A drift of the map's offset over time, learnt from a recording: a real sensor's offsets
/// creep (warm-up, temperature), so that a map learnt early is off later by
/// `rate · (t − reference_time)`, in `a`'s units. For a linear map this is exact for an
/// offset drifting linearly in the sensor frame: `A (raw − o − ȯ t) = A raw − A o − (A ȯ) t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drift {
    /// The time the map is exact at \[s\] (on the recording's clock): [`Calibration::apply`]
    /// gives `a` as of this time.
    pub reference_time: f64,
    /// The drift of `a` per second, torque first \[N·m/s, N/s\].
    pub rate: Vector6<f64>,
    /// The first and last time of the session the drift was learnt on \[s\]: the drift
    /// describes that session only, and is never extrapolated beyond it (it is held at the
    /// span's ends). `None` (a file written without it): the drift is held at
    /// `reference_time`, that is, left out.
    pub span: Option<[f64; 2]>,
}

impl Drift {
    /// The drift term at `time` \[s\]: `rate · (t − reference_time)` with `t` the time held
    /// inside the session's span.
    pub fn at(&self, time: f64) -> Vector6<f64> {
        let t = match self.span {
            Some([first, last]) => time.clamp(first.min(last), last.max(first)),
            None => self.reference_time,
        };
        self.rate * (t - self.reference_time)
    }
}

impl Calibration {
    /// Assembles a calibration from its checked parts.
    pub(crate) fn from_parts(
        input: Normaliser,
        output: Normaliser,
        affine: Option<Affine>,
        mlp: Mlp,
        record: TrainingRecord,
    ) -> Self {
        let mut calibration = Self {
            input,
            output,
            affine,
            polynomial: None,
            mlp,
            anchor: Vector6::zeros(),
            drift: None,
            model: LabelModel::WEIGHTLESS,
            input_kind: CalibrationInput::Raw,
            record,
        };
        if calibration.record.config.anchored {
            calibration.anchor = calibration.unanchored(&Vector6::zeros());
        }
        calibration
    }

    /// `F(raw)`, the trained map before anchoring.
    fn unanchored(&self, raw: &Vector6<f64>) -> Vector6<f64> {
        let z = self.input.normalise(raw);
        let mut y = self.mlp.forward(&z);
        if self.record.config.through_zero {
            y *= remainder_gate(&self.input, raw);
        }
        if let Some(affine) = &self.affine {
            y += affine.apply(&z);
        }
        if let Some(polynomial) = &self.polynomial {
            y += polynomial.apply(&z);
        }
        self.output.denormalise(&y)
    }

    /// What anchoring subtracts from every output, `F(0)` (zero when not anchored), torque first
    /// \[N·m, N\].
    pub fn anchor(&self) -> &Vector6<f64> {
        &self.anchor
    }

    /// The configuration `a` (torque first, base clamp frame \[N·m, N\]) for a raw reading
    /// (force first, sensor frame \[N, N·m\]). Allocation-free.
    ///
    /// A non-finite reading gives a non-finite `a`; readings far outside the training data
    /// (for example saturated ones) are extrapolated and not to be trusted.
    pub fn apply(&self, raw: &Vector6<f64>) -> Vector6<f64> {
        self.unanchored(raw) - self.anchor
    }

    /// [`Calibration::apply`] for a reading taken at `time` \[s\] on the recording's clock:
    /// plus the drift term `rate · (time − reference_time)` when the map has one
    /// ([`Calibration::drift`]), the same as `apply` otherwise.
    pub fn apply_at(&self, raw: &Vector6<f64>, time: f64) -> Vector6<f64> {
        let a = self.apply(raw);
        match &self.drift {
            Some(d) => a + d.at(time),
            None => a,
        }
    }

    /// The drift term, if the map has one.
    pub fn drift(&self) -> Option<&Drift> {
        self.drift.as_ref()
    }

    /// The map with a drift term (trained on labels brought back to `drift.reference_time`).
    ///
    /// # Errors
    /// [`crate::EstimateError::CalibrationValue`] for a non-finite time or rate.
    pub fn with_drift(mut self, drift: Drift) -> Result<Self, crate::EstimateError> {
        let values = std::iter::once(("drift.reference_time", 0, drift.reference_time)).chain(
            drift
                .rate
                .iter()
                .enumerate()
                .map(|(i, &v)| ("drift.rate", i, v)),
        );
        for (what, index, value) in values {
            if !value.is_finite() {
                return Err(crate::EstimateError::CalibrationValue {
                    what: what.into(),
                    index,
                    value,
                    allowed: "a finite number",
                });
            }
        }
        if let Some([first, last]) = drift.span
            && !(first.is_finite() && last.is_finite() && first <= last)
        {
            return Err(crate::EstimateError::CalibrationValue {
                what: "drift.span".into(),
                index: 0,
                value: first,
                allowed: "two finite times [s], the first not after the last",
            });
        }
        self.drift = Some(drift);
        Ok(self)
    }

    /// The wire model the labels were made with.
    pub fn model(&self) -> &LabelModel {
        &self.model
    }

    /// What the map's input is: the raw reading or the tared one.
    pub fn input(&self) -> CalibrationInput {
        self.input_kind
    }

    /// The calibration with the label model and the input it was trained with.
    ///
    /// # Errors
    /// As [`LabelModel::check`].
    pub fn with_provenance(
        mut self,
        model: LabelModel,
        input: CalibrationInput,
    ) -> Result<Self, crate::EstimateError> {
        model.check()?;
        self.model = model;
        self.input_kind = input;
        Ok(self)
    }

    /// Per-component RMS error `√(mean (apply(raw) − a)²)` over `(raw, a)` pairs, torque first
    /// \[N·m, N·m, N·m, N, N, N\]; zero for no pairs.
    pub fn rmse<'a>(
        &self,
        pairs: impl Iterator<Item = (&'a Vector6<f64>, &'a Vector6<f64>)>,
    ) -> Vector6<f64> {
        let mut count = 0_usize;
        let sum = pairs.fold(Vector6::zeros(), |acc, (raw, a)| {
            count += 1;
            let e = self.apply(raw) - a;
            acc + e.component_mul(&e)
        });
        #[allow(clippy::cast_precision_loss)] // sample counts are far below 2⁵²
        let n = count.max(1) as f64;
        (sum / n).map(f64::sqrt)
    }

    /// The standardisation of raw readings.
    pub fn input_normaliser(&self) -> &Normaliser {
        &self.input
    }

    /// The standardisation of configurations.
    pub fn output_normaliser(&self) -> &Normaliser {
        &self.output
    }

    /// The affine part in normalised units (`None` when the network maps alone).
    pub fn affine(&self) -> Option<&Affine> {
        self.affine.as_ref()
    }

    /// The polynomial part in normalised units (`None` without one).
    pub fn polynomial(&self) -> Option<&Polynomial> {
        self.polynomial.as_ref()
    }

    /// The calibration with a polynomial part `W φ(z)` added to its map (the anchor is
    /// recomputed when the map is anchored).
    pub fn with_polynomial(mut self, polynomial: Option<Polynomial>) -> Self {
        self.polynomial = polynomial;
        if self.record.config.anchored {
            self.anchor = Vector6::zeros();
            self.anchor = self.unanchored(&Vector6::zeros());
        }
        self
    }

    /// The network (normalised units; with an affine part, it gives the residual).
    pub fn mlp(&self) -> &Mlp {
        &self.mlp
    }

    /// How this calibration was trained.
    pub fn record(&self) -> &TrainingRecord {
        &self.record
    }
}

/// The learnt calibration as the last stage of the F/T pipeline
/// ([`crate::ft::FtPipeline`]): a tared raw reading in, `ã` out.
impl crate::ft::FtCalibration for Calibration {
    fn configuration(&self, tared: &Vector6<f64>) -> Vector6<f64> {
        self.apply(tared)
    }
}

/// The gate `ρ = q / (1 + q)`, `q = |raw ⊘ σ_raw|²`, on the network's remainder of a map
/// trained [`through_zero`](super::TrainParams::through_zero): zero at a zero reading,
/// quadratic below the training spread `σ_raw`, near one at the training readings.
pub(crate) fn remainder_gate(input: &Normaliser, raw: &Vector6<f64>) -> f64 {
    let q = raw.component_div(input.std()).norm_squared();
    q / (1.0 + q)
}
