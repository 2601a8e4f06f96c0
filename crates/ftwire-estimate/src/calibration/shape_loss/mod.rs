//! A calibration map fitted where it is judged: on the shape.
//!
//! Labels fitted to markers (eq. 15) are good in shape but poorly determined in some wrench
//! directions (a wire's shape barely moves along them), and a map fitted to them by least
//! squares in `a` trusts those directions as much as the others. Here the map is fitted on the
//! markers' distance to the model's shape instead:
//!
//! ```text
//! min_Θ,g  Σ_i Σ_j ρ_δ(d_ij) + ½ λ |W|²,    d_ij = dist(m_ij, Φ_g(a_i)),
//! a_i = μ_a + σ_a ⊙ (Θ ψ(z_i)) + o_i,       z_i = (raw_i − μ_raw) ⊘ σ_raw,
//! ψ(z) = (z, 1, φ(z)),                      Θ = (A | c | W)
//! ```
//!
//! over the training records `i` and their markers `j`: `A z + c` is the affine part (lever
//! arm, axes, gain, cross-talk, offsets), `W φ(z)` the polynomial part (monomials of degree 2
//! to `d`, [`super::Polynomial`]), `o_i` a fixed offset (the drift term at the record's time),
//! `ρ_δ` Huber's loss (quadratic up to `δ`, linear beyond: a record whose reading is wrong
//! pulls with a bounded force) and `λ` a ridge on the polynomial weights. `g` is gravity's
//! direction in the clamp frame, fitted with the map when asked ([`GravityFit`]).
//!
//! **Gauss–Newton through the model's Jacobian.** The map is linear in `Θ`, so
//! `∂a_i/∂Θ_kp = σ_a,k ψ_p(z_i)`, and a marker's residual moves with `a` by the analytic
//! `∂p(s)/∂a` (`crate::shape::centreline_point`). At the closest point the residual is
//! projected across the tangent, `r = (I − t tᵀ)(p(s) − m)` (the distance does not change to
//! first order along the wire), or, with the markers' arc lengths known, taken at them. Each
//! iteration solves the damped, iteratively reweighted normal equations (Levenberg–Marquardt,
//! Huber weights `min(1, δ/d)`); gravity's two directions are differentiated by forward
//! differences of the loaded model. Per-record terms are computed on every core and
//! summed in record order, so the fit does not depend on the number of threads.
//!
//! **Capacity chosen on the validation block.** The affine map is fitted first (from the
//! least-squares fit to the labels); then each candidate degree and ridge starts from it, and
//! the one whose validation records' markers lie closest to their shapes is kept. The affine
//! fit is always a candidate, so the chosen map is never worse than it on the validation
//! block.
//!
//! Pieces, one per file: `settings` what a caller gives (the records and the settings),
//! `fitted` what the fit returns, `theta` the map in normalised units and its polynomial
//! features, `loss` the loss and each record's terms through the model's Jacobian, `solve`
//! the Gauss–Newton solver; this file fits the candidates in turn and chooses
//! ([`fit_on_shape`]).

use nalgebra::{Vector3, Vector6};

use super::record::{SplitSizes, StopReason, TrainParams, TrainingRecord};
use super::{Affine, Normaliser};
use crate::{EstimateError, WireModel};

mod fitted;
mod loss;
mod settings;
mod solve;
mod theta;

pub use fitted::{Candidate, GravityStart, ShapeFitted};
use loss::Problem;
pub use loss::marker_mean;
pub use settings::{DEFAULT_LABEL_WEIGHT, GravityFit, ShapeLossParams, ShapeSample};
use theta::{Frame, Map};

/// Huber's constant: the threshold in robust scales (95 % efficiency for Gaussian residuals).
const HUBER_CONSTANT: f64 = 1.345;

/// The smallest Huber threshold \[m\]: below a motion-capture system's jitter.
const MIN_HUBER: f64 = 2e-4;

/// Fits the map on the shape (see the module docs). `labels[i]` is a first `a` of
/// `train[i]` (its eq. 15 fit less the sample's offset): the least-squares affine map to them
/// starts the fit, and they fix the output standardisation.
///
/// # Errors
/// [`EstimateError::InvalidSetting`] for bad settings or lists of different lengths;
/// [`EstimateError::TooFewCalibrationSamples`] for no training or validation records, or
/// none whose start shape solves.
pub fn fit_on_shape<M: WireModel>(
    model: &M,
    train: &[ShapeSample],
    labels: &[Vector6<f64>],
    validation: &[ShapeSample],
    params: &ShapeLossParams,
) -> Result<ShapeFitted, EstimateError> {
    params.validate()?;
    if labels.len() != train.len() {
        #[allow(clippy::cast_precision_loss)] // counts
        return Err(EstimateError::InvalidSetting {
            field: "labels",
            value: labels.len() as f64,
            allowed: "one label per training record",
        });
    }
    for (split, got) in [("training", train.len()), ("validation", validation.len())] {
        if got == 0 {
            return Err(EstimateError::TooFewCalibrationSamples {
                samples: train.len() + validation.len(),
                split,
                got,
                needed: 1,
            });
        }
    }
    let input = Normaliser::fit(train.iter().map(|s| &s.raw));
    let output = Normaliser::fit(labels.iter());
    let z: Vec<Vector6<f64>> = train.iter().map(|s| input.normalise(&s.raw)).collect();
    let y: Vec<Vector6<f64>> = labels.iter().map(|a| output.normalise(a)).collect();
    let start = Affine::fit(z.iter().zip(&y));
    let frame = Frame {
        input,
        output,
        nodes: params.nodes,
    };
    let mut problem = Problem::new(model, &frame, train, params.gravity);
    problem.targets = y.clone();
    problem.label_weight = params.label_weight;
    let affine_start = Map::affine(&start);

    // Records whose start shape cannot be solved are left out of the fit.
    let first = problem.evaluate(&affine_start, problem.start_gravity(), false)?;
    let train_failures = first.iter().filter(|e| e.is_none()).count();
    problem.keep(&first);
    if problem.samples.is_empty() {
        return Err(EstimateError::TooFewCalibrationSamples {
            samples: train.len() + validation.len(),
            split: "training (records whose start shape solves)",
            got: 0,
            needed: 1,
        });
    }
    let huber = match params.huber {
        Some(h) => h,
        None => {
            let mut d: Vec<f64> = first
                .iter()
                .flatten()
                .flat_map(|e| e.distances.clone())
                .collect();
            HUBER_CONSTANT * 1.4826 * median(&mut d)
        }
    }
    .max(MIN_HUBER);
    problem.huber = huber;

    let mut gravity_starts = Vec::new();
    let mut gravity = problem.start_gravity();
    if let Some(fit) = params.gravity
        && fit.start.is_none()
    {
        let mut best: Option<(f64, Vector3<f64>)> = None;
        for axis in 0..6 {
            let mut dir = Vector3::zeros();
            dir[axis / 2] = if axis % 2 == 0 { 1.0 } else { -1.0 };
            let mut map = affine_start.clone();
            let mut g = Some(dir);
            let loss = problem.solve(&mut map, &mut g, 0.0, 6)?.loss;
            let end = g.unwrap_or(dir);
            gravity_starts.push(GravityStart {
                start: dir.into(),
                end: end.into(),
                loss,
            });
            if best.is_none_or(|(l, _)| loss < l) {
                best = Some((loss, end));
            }
        }
        gravity = best.map(|(_, g)| g);
    }

    let mut affine_map = affine_start;
    let mut affine_gravity = gravity;
    let outcome = problem.solve(
        &mut affine_map,
        &mut affine_gravity,
        0.0,
        params.max_iterations,
    )?;
    let mut fitted = vec![(affine_map.clone(), affine_gravity)];
    let mut candidates = vec![problem.candidate(
        &affine_map,
        affine_gravity,
        0.0,
        outcome.iterations,
        validation,
    )?];
    for &degree in &params.degrees {
        for &ridge in &params.ridges {
            let mut map = affine_map.extended(degree);
            let mut g = affine_gravity;
            let outcome = problem.solve(&mut map, &mut g, ridge, params.max_iterations)?;
            candidates.push(problem.candidate(&map, g, ridge, outcome.iterations, validation)?);
            fitted.push((map, g));
        }
    }
    let chosen = (0..candidates.len())
        .min_by(|&i, &j| {
            let (a, b) = (&candidates[i], &candidates[j]);
            (a.validation_failures, a.validation_marker_mean)
                .partial_cmp(&(b.validation_failures, b.validation_marker_mean))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
        .unwrap_or(0);
    let sizes = SplitSizes {
        train: problem.samples.len(),
        validation: validation.len(),
        test: 0,
    };
    let build = |k: usize| {
        let (map, _) = &fitted[k];
        map.calibration(&frame, record(&candidates[k], &candidates[0], sizes))
    };
    Ok(ShapeFitted {
        calibration: build(chosen)?,
        affine: build(0)?,
        gravity_in_clamp: fitted[chosen].1.map(|g| problem.gravity_vector(&g).into()),
        candidates,
        chosen,
        huber,
        gravity_starts,
        train_failures,
    })
}

/// The training record of a map fitted on the shape: "epochs" are Gauss–Newton iterations
/// and the losses mean marker distances \[m\] (validation; the initial one the affine map's).
fn record(candidate: &Candidate, affine: &Candidate, samples: SplitSizes) -> TrainingRecord {
    TrainingRecord {
        seed: 0,
        config: TrainParams {
            hidden: Vec::new(),
            residual: true,
            ..TrainParams::default()
        },
        samples,
        epochs: candidate.iterations,
        best_epoch: candidate.iterations,
        stop: StopReason::MaxEpochs,
        initial_validation_loss: affine.validation_marker_mean,
        validation_loss: candidate.validation_marker_mean,
        test_loss: None,
        test_rmse: None,
        history: Vec::new(),
    }
}

fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_unstable_by(f64::total_cmp);
    values[values.len() / 2]
}
