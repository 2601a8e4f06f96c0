//! The maps of `calibrate --log`, fitted on the labelled records ([`Training`]): the drift
//! term (when offered and chosen), the split by blocks of time, the map fitted on the labels
//! in `a` (the paper's §IV-A), and, with [`MapLoss::Shape`], the maps fitted on the markers'
//! distance to the shape, the one kept chosen on the validation block among them and the map
//! fitted on the labels.

use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::calibration::shape_loss::{
    GravityFit, ShapeSample, fit_on_shape, marker_mean,
};
use ftwire_estimate::calibration::{
    Calibration, CalibrationInput, Dataset, Drift, LabelModel, Split,
};
use nalgebra::Vector6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use ftwire_app::Progress;
use ftwire_app::error::{LabError, from_estimate};

use super::drift::choose_drift;
use super::labelled::Labelled;
use super::params::{LogCalibrateParams, MapLoss};
use super::summary::{CandidateOut, FitOut};

/// The labelled records as the maps are fitted on them: the drift term, the pairs of reading
/// and label less the drift, and their split.
pub(super) struct Training<'a> {
    labelled: &'a [Labelled],
    drift: Option<Drift>,
    data: Dataset,
    /// The split of the labelled records, by blocks of time unless set otherwise.
    pub(super) split: Split,
}

impl<'a> Training<'a> {
    /// Chooses the drift term (with `--drift`), takes it out of the labels, and splits the
    /// records.
    ///
    /// # Errors
    /// Bad input when the labelled records cannot be split (too few).
    pub(super) fn new(
        params: &LogCalibrateParams,
        labelled: &'a [Labelled],
    ) -> Result<Self, LabError> {
        let drift = if params.drift {
            choose_drift(labelled, &params.train)
        } else {
            None
        };
        let data = Dataset::new(
            labelled.iter().map(|l| l.raw).collect(),
            labelled
                .iter()
                .map(|l| l.label - offset_at(drift.as_ref(), l))
                .collect(),
        )
        .map_err(|e| from_estimate(e, "the labelled records"))?;
        let split = data
            .split(
                &params.train.split,
                &mut ChaCha8Rng::seed_from_u64(params.seed),
            )
            .map_err(|e| {
                LabError::bad_input(format!(
                    "training on {} labelled records of {}: {e}",
                    labelled.len(),
                    params.log.display()
                ))
            })?;
        Ok(Self {
            labelled,
            drift,
            data,
            split,
        })
    }

    /// The drift term at a record's time (zero without one).
    fn offset(&self, l: &Labelled) -> Vector6<f64> {
        offset_at(self.drift.as_ref(), l)
    }

    /// A fitted map as it is kept: with the drift term, and the model and input it was
    /// fitted for (the log's readings as they were, never tared).
    fn finish(&self, c: Calibration, model: LabelModel) -> Result<Calibration, LabError> {
        let c = match self.drift {
            Some(d) => c
                .with_drift(d)
                .map_err(|e| from_estimate(e, "the drift term"))?,
            None => c,
        };
        c.with_provenance(model, CalibrationInput::Raw)
            .map_err(|e| from_estimate(e, "the calibration's model"))
    }

    /// The map fitted on the labels in `a` (the affine map and the network, §IV-A), under
    /// the labels' model.
    ///
    /// # Errors
    /// Bad input for a bad `--gravity-in-clamp` or when training fails.
    pub(super) fn label_map(&self, params: &LogCalibrateParams) -> Result<Calibration, LabError> {
        let given_model = params
            .gravity
            .map_or(Ok(LabelModel::WEIGHTLESS), LabelModel::loaded)
            .map_err(|e| LabError::bad_input(format!("--gravity-in-clamp: {e}")))?;
        let label_map =
            Calibration::train(&self.data, &params.train, params.seed).map_err(|e| {
                LabError::bad_input(format!(
                    "training on {} labelled records of {}: {e}",
                    self.labelled.len(),
                    params.log.display()
                ))
            })?;
        self.finish(label_map, given_model)
    }

    /// The map kept, its affine part fitted on the shape (with [`MapLoss::Shape`]), and how
    /// it was fitted and chosen. `label_map` is [`Self::label_map`]'s, kept with
    /// [`MapLoss::Labels`] and one more candidate with [`MapLoss::Shape`].
    ///
    /// # Errors
    /// No answer or bad input when the fit on the shape fails.
    pub(super) fn fit(
        &self,
        params: &LogCalibrateParams,
        label_model: &KirchhoffModel,
        label_map: &Calibration,
        progress: Progress<'_>,
    ) -> Result<(Calibration, Option<Calibration>, FitOut), LabError> {
        match params.loss {
            MapLoss::Labels => {
                let fit = FitOut {
                    loss: MapLoss::Labels,
                    map: if params.train.hidden.is_empty() {
                        "affine".to_owned()
                    } else {
                        "affine+network".to_owned()
                    },
                    chosen_by: "validation_loss".to_owned(),
                    gravity_in_clamp: params.gravity,
                    degree: None,
                    ridge: None,
                    validation_marker_mean_mm: None,
                    huber_mm: None,
                    candidates: Vec::new(),
                    label_map_validation_marker_mean_mm: None,
                    gravity_starts: Vec::new(),
                    train_failures: 0,
                };
                Ok((label_map.clone(), None, fit))
            }
            MapLoss::Shape => self.on_shape(params, label_model, label_map, progress),
        }
    }

    /// [`Self::fit`] with [`MapLoss::Shape`].
    fn on_shape(
        &self,
        params: &LogCalibrateParams,
        label_model: &KirchhoffModel,
        label_map: &Calibration,
        progress: Progress<'_>,
    ) -> Result<(Calibration, Option<Calibration>, FitOut), LabError> {
        let split = &self.split;
        progress(&format!(
            "fitting the map on the shape: {} training and {} validation records",
            split.train.len(),
            split.validation.len()
        ));
        let samples = |indices: &[usize]| -> Vec<ShapeSample> {
            indices
                .iter()
                .filter_map(|&i| self.labelled.get(i))
                .map(|l| ShapeSample {
                    raw: l.raw,
                    offset: self.offset(l),
                    markers: l.loss_markers.clone(),
                    fractions: l.loss_fractions.clone(),
                })
                .collect()
        };
        let train_labels: Vec<Vector6<f64>> = split
            .train
            .iter()
            .filter_map(|&i| self.data.labels().get(i).copied())
            .collect();
        let mut shape = params.shape.clone();
        shape.gravity = params.fit_gravity.map(|norm| GravityFit {
            mass_per_length: params.wire.density
                * std::f64::consts::PI
                * params.wire.radius.powi(2),
            norm,
            start: params.gravity,
        });
        let fitted = fit_on_shape(
            label_model,
            &samples(&split.train),
            &train_labels,
            &samples(&split.validation),
            &shape,
        )
        .map_err(|e| from_estimate(e, "fitting the map on the shape"))?;
        let gravity = fitted.gravity_in_clamp.or(params.gravity);
        let model = gravity
            .map_or(Ok(LabelModel::WEIGHTLESS), LabelModel::loaded)
            .map_err(|e| from_estimate(e, "the fitted gravity"))?;
        let chosen = &fitted.candidates[fitted.chosen];
        // The map fitted on the labels is one more candidate, judged the same way.
        let (label_map_validation, label_map_failures) = marker_mean(
            label_model,
            label_map,
            &samples(&split.validation),
            shape.nodes,
        )
        .map_err(|e| from_estimate(e, "judging the map fitted on the labels"))?;
        let shape_wins = (chosen.validation_failures, chosen.validation_marker_mean)
            <= (label_map_failures, label_map_validation);
        let fit = FitOut {
            loss: MapLoss::Shape,
            map: if shape_wins {
                map_name(chosen.degree).to_owned()
            } else {
                "affine+network (fitted on the labels)".to_owned()
            },
            chosen_by: "validation_marker_mean".to_owned(),
            gravity_in_clamp: if shape_wins { gravity } else { params.gravity },
            degree: shape_wins.then_some(chosen.degree),
            ridge: shape_wins.then_some(chosen.ridge),
            validation_marker_mean_mm: Some(
                1e3 * chosen.validation_marker_mean.min(label_map_validation),
            ),
            huber_mm: Some(1e3 * fitted.huber),
            candidates: fitted.candidates.iter().map(CandidateOut::from).collect(),
            label_map_validation_marker_mean_mm: Some(1e3 * label_map_validation),
            gravity_starts: fitted.gravity_starts.clone(),
            train_failures: fitted.train_failures,
        };
        let calibration = if shape_wins {
            self.finish(fitted.calibration, model)?
        } else {
            label_map.clone()
        };
        Ok((calibration, Some(self.finish(fitted.affine, model)?), fit))
    }
}

/// The drift term at a record's time (zero without one).
fn offset_at(drift: Option<&Drift>, l: &Labelled) -> Vector6<f64> {
    drift.map_or(Vector6::zeros(), |d| d.at(l.time))
}

/// A polynomial degree's name in `fit.map`.
fn map_name(degree: usize) -> &'static str {
    match degree {
        1 => "affine",
        2 => "affine+quadratic",
        _ => "affine+cubic",
    }
}
