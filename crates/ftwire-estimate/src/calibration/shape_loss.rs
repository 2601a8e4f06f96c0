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

use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Matrix6x2, Point3, Vector2, Vector3, Vector6};
use serde::Serialize;

use super::polynomial::{MAX_FEATURES, feature_count, features};
use super::record::{SplitSizes, StopReason, TrainParams, TrainingRecord};
use super::{Affine, Calibration, Mlp, Normaliser, Polynomial};
use crate::shape::{centreline_point, closest_point};
use crate::{EstimateError, WireModel};

/// Huber's constant: the threshold in robust scales (95 % efficiency for Gaussian residuals).
const HUBER_CONSTANT: f64 = 1.345;

/// The smallest Huber threshold \[m\]: below a motion-capture system's jitter.
const MIN_HUBER: f64 = 2e-4;

/// Forward-difference step of gravity's direction \[rad\].
const GRAVITY_STEP: f64 = 1e-4;

/// The default [`ShapeLossParams::label_weight`].
pub const DEFAULT_LABEL_WEIGHT: f64 = 1.0;

/// One training or validation record: the map's input, a fixed offset, and the markers.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeSample {
    /// The reading, the map's input (force first, sensor frame \[N, N·m\]).
    pub raw: Vector6<f64>,
    /// Added to the map's output (the drift term at the record's time), torque first.
    pub offset: Vector6<f64>,
    /// The markers the loss measures, base clamp frame \[m\] (at least one).
    pub markers: Vec<Point3<f64>>,
    /// Their arc lengths as fractions of the wire's length; `None`: matched at their closest
    /// points.
    pub fractions: Option<Vec<f64>>,
}

/// Gravity's direction fitted with the map: the loaded model's weight `ρA |g| ĝ`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GravityFit {
    /// The wire's mass per length `ρA` \[kg/m\].
    pub mass_per_length: f64,
    /// `|g|` \[m/s²\].
    pub norm: f64,
    /// A first direction to start from (any length); `None`: the best of the six axis
    /// directions after a few iterations each.
    pub start: Option<[f64; 3]>,
}

/// How the map is fitted on the shape.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeLossParams {
    /// Candidate degrees of the polynomial part, each 2 or 3 (the affine map, degree 1, is
    /// always a candidate).
    pub degrees: Vec<usize>,
    /// Candidate ridge weights of the polynomial part, relative to the mean curvature of the
    /// loss in the affine weights; each finite and > 0.
    pub ridges: Vec<f64>,
    /// Most Gauss–Newton iterations of one candidate, ≥ 1.
    pub max_iterations: usize,
    /// Huber's threshold \[m\]; `None`: `1.345 ×` the robust scale (1.4826 × median) of the
    /// affine start's marker distances, at least 0.2 mm.
    pub huber: Option<f64>,
    /// Nodes of the shapes the closest points are found on, ≥ 2.
    pub nodes: usize,
    /// Weight of the labels beside the shape, relative to the shape's curvature in the
    /// affine weights (finite, ≥ 0): `½ β Σ |(a_i − ℓ_i) ⊘ σ_a|²` keeps the wrench directions
    /// the shape barely sees (a taut wire's tension) near the labels, which the shape alone
    /// leaves free to extrapolate.
    pub label_weight: f64,
    /// Fit gravity's direction too.
    pub gravity: Option<GravityFit>,
}

impl Default for ShapeLossParams {
    fn default() -> Self {
        Self {
            degrees: vec![2, 3],
            ridges: vec![1.0, 1e-1, 1e-2],
            max_iterations: 25,
            huber: None,
            nodes: 101,
            label_weight: DEFAULT_LABEL_WEIGHT,
            gravity: None,
        }
    }
}

impl ShapeLossParams {
    fn validate(&self) -> Result<(), EstimateError> {
        #[allow(clippy::cast_precision_loss)] // small numbers
        if let Some(&d) = self.degrees.iter().find(|d| !(2..=3).contains(*d)) {
            return Err(EstimateError::InvalidSetting {
                field: "degrees",
                value: d as f64,
                allowed: "polynomial degrees 2 or 3",
            });
        }
        if let Some(&r) = self.ridges.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
            return Err(EstimateError::InvalidSetting {
                field: "ridges",
                value: r,
                allowed: "finite ridge weights > 0",
            });
        }
        #[allow(clippy::cast_precision_loss)] // small numbers
        for (field, value, least) in [
            ("max_iterations", self.max_iterations, 1),
            ("nodes", self.nodes, 2),
        ] {
            if value < least {
                return Err(EstimateError::InvalidSetting {
                    field,
                    value: value as f64,
                    allowed: "at least 1 iteration and 2 nodes",
                });
            }
        }
        if !(self.label_weight.is_finite() && self.label_weight >= 0.0) {
            return Err(EstimateError::InvalidSetting {
                field: "label_weight",
                value: self.label_weight,
                allowed: "a finite weight ≥ 0",
            });
        }
        if let Some(h) = self.huber
            && !(h.is_finite() && h > 0.0)
        {
            return Err(EstimateError::InvalidSetting {
                field: "huber",
                value: h,
                allowed: "a finite distance > 0 [m]",
            });
        }
        if let Some(g) = &self.gravity {
            for (field, value) in [
                ("gravity.mass_per_length", g.mass_per_length),
                ("gravity.norm", g.norm),
            ] {
                if !(value.is_finite() && value > 0.0 && value <= 1e3) {
                    return Err(EstimateError::InvalidSetting {
                        field,
                        value,
                        allowed: "a finite number in (0, 1000]",
                    });
                }
            }
            if let Some(s) = g.start {
                let norm = Vector3::from(s).norm();
                if !(norm.is_finite() && norm > 0.0) {
                    return Err(EstimateError::InvalidSetting {
                        field: "gravity.start",
                        value: norm,
                        allowed: "a finite direction of non-zero length",
                    });
                }
            }
        }
        Ok(())
    }
}

/// One candidate map as fitted.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Candidate {
    /// Its degree (1: the affine map).
    pub degree: usize,
    /// Its relative ridge weight (0 for the affine map).
    pub ridge: f64,
    /// Gauss–Newton iterations run.
    pub iterations: usize,
    /// Mean marker distance over the training records \[m\].
    pub train_marker_mean: f64,
    /// Mean marker distance over the validation records \[m\] (what chooses).
    pub validation_marker_mean: f64,
    /// Validation records whose shape could not be solved (counted before the distance).
    pub validation_failures: usize,
    /// Gravity in the clamp frame it ended with \[m/s²\] (with a gravity fit).
    pub gravity_in_clamp: Option<[f64; 3]>,
}

/// A gravity start and where the affine fit took it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GravityStart {
    /// The start direction (unit).
    pub start: [f64; 3],
    /// The direction after a few iterations (unit).
    pub end: [f64; 3],
    /// The training loss there (Huber, summed \[m²\]).
    pub loss: f64,
}

/// The map fitted on the shape.
#[derive(Debug, Clone)]
pub struct ShapeFitted {
    /// The chosen map (affine part, and a polynomial part when chosen).
    pub calibration: Calibration,
    /// The affine map fitted on the shape (the first candidate).
    pub affine: Calibration,
    /// Every candidate, the affine map first.
    pub candidates: Vec<Candidate>,
    /// The index of the chosen one.
    pub chosen: usize,
    /// Huber's threshold used \[m\].
    pub huber: f64,
    /// Gravity in the clamp frame of the chosen map \[m/s²\] (with a gravity fit).
    pub gravity_in_clamp: Option<[f64; 3]>,
    /// The gravity starts tried (with a gravity fit and no start given).
    pub gravity_starts: Vec<GravityStart>,
    /// Training records left out because the start map's shape could not be solved.
    pub train_failures: usize,
}

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

/// The standardisations and the shapes' resolution.
struct Frame {
    input: Normaliser,
    output: Normaliser,
    nodes: usize,
}

/// `Θ = (A | c | W)`, six rows of `7 + K` weights in normalised units.
#[derive(Debug, Clone, PartialEq)]
struct Map {
    degree: usize,
    theta: DMatrix<f64>,
}

impl Map {
    fn affine(affine: &Affine) -> Self {
        let mut theta = DMatrix::zeros(6, 7);
        for i in 0..6 {
            for j in 0..6 {
                theta[(i, j)] = affine.matrix[(i, j)];
            }
            theta[(i, 6)] = affine.offset[i];
        }
        Self { degree: 1, theta }
    }

    fn width(degree: usize) -> usize {
        7 + feature_count(degree)
    }

    /// The same map with a zero polynomial part of `degree`.
    fn extended(&self, degree: usize) -> Self {
        let mut theta = DMatrix::zeros(6, Self::width(degree));
        theta.columns_mut(0, 7).copy_from(&self.theta.columns(0, 7));
        Self { degree, theta }
    }

    fn psi(&self, z: &Vector6<f64>) -> DVector<f64> {
        let mut phi = [0.0; MAX_FEATURES];
        let count = features(self.degree, z, &mut phi);
        let mut psi = DVector::zeros(7 + count);
        psi.rows_mut(0, 6).copy_from(z);
        psi[6] = 1.0;
        psi.rows_mut(7, count).copy_from_slice(&phi[..count]);
        psi
    }

    fn calibration(
        &self,
        frame: &Frame,
        record: TrainingRecord,
    ) -> Result<Calibration, EstimateError> {
        let affine = Affine {
            matrix: Matrix6::from_fn(|i, j| self.theta[(i, j)]),
            offset: Vector6::from_fn(|i, _| self.theta[(i, 6)]),
        };
        let polynomial = if self.degree >= 2 {
            let rows = (0..6)
                .map(|i| self.theta.row(i).iter().skip(7).copied().collect())
                .collect();
            Some(Polynomial::new(self.degree, rows)?)
        } else {
            None
        };
        let mlp = Mlp::from_parameters(&[], super::Activation::Tanh, vec![0.0; 42])?;
        Ok(
            Calibration::from_parts(frame.input, frame.output, Some(affine), mlp, record)
                .with_polynomial(polynomial),
        )
    }
}

/// One record's terms of the normal equations in `a` (and gravity's two directions).
struct Terms {
    loss: f64,
    distances: Vec<f64>,
    g: Matrix6<f64>,
    b: Vector6<f64>,
    c: Matrix6x2<f64>,
    gg: nalgebra::Matrix2<f64>,
    bg: Vector2<f64>,
}

/// What a solve ended with.
struct Outcome {
    loss: f64,
    iterations: usize,
}

struct Problem<'a, M> {
    model: &'a M,
    frame: &'a Frame,
    samples: Vec<&'a ShapeSample>,
    z: Vec<Vector6<f64>>,
    gravity: Option<GravityFit>,
    huber: f64,
    /// The normalised labels of the samples (empty: no label term).
    targets: Vec<Vector6<f64>>,
    /// The label term's relative weight.
    label_weight: f64,
}

impl<'a, M: WireModel> Problem<'a, M> {
    fn new(
        model: &'a M,
        frame: &'a Frame,
        samples: &'a [ShapeSample],
        gravity: Option<GravityFit>,
    ) -> Self {
        Self {
            model,
            frame,
            samples: samples.iter().collect(),
            z: samples
                .iter()
                .map(|s| frame.input.normalise(&s.raw))
                .collect(),
            gravity,
            huber: f64::INFINITY,
            targets: Vec::new(),
            label_weight: 0.0,
        }
    }

    /// `½ β Σ |Θ ψ_i − y_i|²`, the label term in normalised units.
    fn label_term(&self, map: &Map, beta: f64) -> f64 {
        if beta == 0.0 {
            return 0.0;
        }
        0.5 * beta
            * self
                .targets
                .iter()
                .zip(&self.z)
                .map(|(y, z)| {
                    (&map.theta * map.psi(z) - DVector::from_column_slice(y.as_slice()))
                        .norm_squared()
                })
                .sum::<f64>()
    }

    /// Keeps the records whose evaluation succeeded.
    fn keep(&mut self, evaluations: &[Option<Terms>]) {
        let keep: Vec<bool> = evaluations.iter().map(Option::is_some).collect();
        let mut k = keep.iter();
        self.samples.retain(|_| *k.next().unwrap_or(&false));
        let mut k = keep.iter();
        self.z.retain(|_| *k.next().unwrap_or(&false));
        if !self.targets.is_empty() {
            let mut k = keep.iter();
            self.targets.retain(|_| *k.next().unwrap_or(&false));
        }
    }

    /// The unit direction gravity starts at (`None` without a gravity fit).
    fn start_gravity(&self) -> Option<Vector3<f64>> {
        self.gravity.map(|g| {
            g.start
                .map_or(-Vector3::z(), |s| Vector3::from(s).normalize())
        })
    }

    fn gravity_vector(&self, direction: &Vector3<f64>) -> Vector3<f64> {
        self.gravity
            .map_or(Vector3::zeros(), |g| g.norm * direction)
    }

    /// The model under gravity's direction (the given model without a gravity fit).
    fn model_under(&self, direction: Option<&Vector3<f64>>) -> Result<M, EstimateError> {
        match (self.gravity, direction) {
            (Some(fit), Some(d)) => self
                .model
                .with_weight_per_length(fit.mass_per_length * fit.norm * d),
            _ => Ok(self.model.clone()),
        }
    }

    fn a_of(&self, map: &Map, k: usize, psi: &DVector<f64>) -> Vector6<f64> {
        let y = Vector6::from_iterator((&map.theta * psi).iter().copied());
        self.frame.output.denormalise(&y) + self.samples[k].offset
    }

    /// Every record's terms (`None` where its shape cannot be solved), computed on every
    /// core, in record order.
    fn evaluate(
        &self,
        map: &Map,
        gravity: Option<Vector3<f64>>,
        linearise: bool,
    ) -> Result<Vec<Option<Terms>>, EstimateError> {
        let model = self.model_under(gravity.as_ref())?;
        let perturbed = match (gravity, linearise) {
            (Some(g), true) => {
                let (e1, e2) = tangent_basis(&g);
                Some([
                    self.model_under(Some(&(g + GRAVITY_STEP * e1).normalize()))?,
                    self.model_under(Some(&(g + GRAVITY_STEP * e2).normalize()))?,
                ])
            }
            _ => None,
        };
        let threads = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
        let chunk = self.samples.len().div_ceil(threads).max(1);
        let indices: Vec<usize> = (0..self.samples.len()).collect();
        let parts: Vec<Vec<Option<Terms>>> = std::thread::scope(|scope| {
            let handles: Vec<_> = indices
                .chunks(chunk)
                .map(|part| {
                    let (model, perturbed) = (&model, perturbed.as_ref());
                    scope.spawn(move || {
                        part.iter()
                            .map(|&k| {
                                let psi = map.psi(&self.z[k]);
                                let a = self.a_of(map, k, &psi);
                                self.terms(model, perturbed, &a, self.samples[k], linearise)
                            })
                            .collect()
                    })
                })
                .collect();
            // A panic is a bug: carried on to the caller's thread as it was.
            handles
                .into_iter()
                .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                .collect()
        });
        Ok(parts.into_iter().flatten().collect())
    }

    /// One record's loss and, with `linearise`, its normal-equation terms.
    fn terms(
        &self,
        model: &M,
        perturbed: Option<&[M; 2]>,
        a: &Vector6<f64>,
        sample: &ShapeSample,
        linearise: bool,
    ) -> Option<Terms> {
        if !a.iter().all(|v| v.is_finite()) {
            return None;
        }
        let length = model.wire().length();
        let shape = model.shape(a, self.frame.nodes).ok()?;
        let mut t = Terms {
            loss: 0.0,
            distances: Vec::with_capacity(sample.markers.len()),
            g: Matrix6::zeros(),
            b: Vector6::zeros(),
            c: Matrix6x2::zeros(),
            gg: nalgebra::Matrix2::zeros(),
            bg: Vector2::zeros(),
        };
        for (j, marker) in sample.markers.iter().enumerate() {
            let fraction = sample.fractions.as_ref().and_then(|f| f.get(j).copied());
            // At a known arc length the point is solved once, with its Jacobian when asked;
            // at the closest point the distance comes from the shape's polyline.
            let (s, distance, known) = match fraction {
                Some(f) => {
                    let s = f * length;
                    let p = centreline_point(model, a, s, linearise).ok()?;
                    (s, (p.position - marker.coords).norm(), Some(p))
                }
                None => {
                    let c = closest_point(&shape.positions, &marker.coords)?;
                    (c.arc_length, c.distance, None)
                }
            };
            t.loss += huber_loss(distance, self.huber);
            t.distances.push(distance);
            if !linearise {
                continue;
            }
            let point = match known {
                Some(p) => p,
                None => centreline_point(model, a, s, true).ok()?,
            };
            let across = if fraction.is_some() {
                Matrix3::identity()
            } else {
                Matrix3::identity() - point.tangent * point.tangent.transpose()
            };
            let r = across * (point.position - marker.coords);
            let j_a = across * point.jacobian;
            let w = if r.norm() <= self.huber {
                1.0
            } else {
                self.huber / r.norm()
            };
            t.g += w * j_a.transpose() * j_a;
            t.b += w * j_a.transpose() * r;
            if let Some(models) = perturbed {
                let mut k = nalgebra::Matrix3x2::zeros();
                for (col, m) in models.iter().enumerate() {
                    let p = centreline_point(m, a, s, false).ok()?.position;
                    k.set_column(col, &(across * (p - point.position) / GRAVITY_STEP));
                }
                t.c += w * j_a.transpose() * k;
                t.gg += w * k.transpose() * k;
                t.bg += w * k.transpose() * r;
            }
        }
        Some(t)
    }

    /// The training objective: the Huber loss plus the ridge; infinite when a record fails.
    fn objective(
        &self,
        map: &Map,
        gravity: Option<Vector3<f64>>,
        (lambda, beta): (f64, f64),
    ) -> Result<f64, EstimateError> {
        let terms = self.evaluate(map, gravity, false)?;
        if terms.iter().any(Option::is_none) {
            return Ok(f64::INFINITY);
        }
        Ok(terms.iter().flatten().map(|t| t.loss).sum::<f64>()
            + ridge_term(map, lambda)
            + self.label_term(map, beta))
    }

    /// Levenberg–Marquardt on the map (and gravity) from where they are; `ridge` relative to
    /// the mean curvature in the affine weights. Returns the final objective.
    fn solve(
        &self,
        map: &mut Map,
        gravity: &mut Option<Vector3<f64>>,
        ridge: f64,
        max_iterations: usize,
    ) -> Result<Outcome, EstimateError> {
        let width = map.theta.ncols();
        let fit_gravity = gravity.is_some() && self.gravity.is_some();
        let n = 6 * width + if fit_gravity { 2 } else { 0 };
        let sigma = *self.frame.output.std();
        let mut mu = 1e-3;
        let mut lambda = None;
        let mut beta = None;
        let mut loss = f64::INFINITY;
        let mut iterations = 0;
        while iterations < max_iterations {
            iterations += 1;
            let terms = self.evaluate(map, *gravity, true)?;
            if terms.iter().any(Option::is_none) {
                break;
            }
            let mut h = DMatrix::<f64>::zeros(n, n);
            let mut b = DVector::<f64>::zeros(n);
            let mut current = 0.0;
            for (k, t) in terms.iter().flatten().enumerate() {
                current += t.loss;
                let psi = map.psi(&self.z[k]);
                let dg = Matrix6::from_diagonal(&sigma) * t.g * Matrix6::from_diagonal(&sigma);
                let db = sigma.component_mul(&t.b);
                for kk in 0..6 {
                    for ll in kk..6 {
                        let v = dg[(kk, ll)];
                        if v == 0.0 {
                            continue;
                        }
                        for q in 0..width {
                            let vq = v * psi[q];
                            for p in 0..width {
                                h[(kk * width + p, ll * width + q)] += vq * psi[p];
                            }
                        }
                    }
                    for p in 0..width {
                        b[kk * width + p] += db[kk] * psi[p];
                    }
                }
                if fit_gravity {
                    let dc = Matrix6::from_diagonal(&sigma) * t.c;
                    for kk in 0..6 {
                        for col in 0..2 {
                            for p in 0..width {
                                h[(kk * width + p, 6 * width + col)] += dc[(kk, col)] * psi[p];
                            }
                        }
                    }
                    for r in 0..2 {
                        for c in 0..2 {
                            h[(6 * width + r, 6 * width + c)] += t.gg[(r, c)];
                        }
                        b[6 * width + r] += t.bg[r];
                    }
                }
            }
            // Only the blocks on and above the diagonal were summed: mirror them.
            for c in 0..n {
                for r in (c + 1)..n {
                    h[(r, c)] = h[(c, r)];
                }
            }
            let lambda = *lambda.get_or_insert_with(|| {
                #[allow(clippy::cast_precision_loss)] // small sizes
                let mean = (0..6)
                    .flat_map(|kk| (0..7).map(move |p| kk * width + p))
                    .map(|i| h[(i, i)])
                    .sum::<f64>()
                    / 42.0;
                ridge * mean
            });
            let beta = *beta.get_or_insert_with(|| {
                if self.targets.is_empty() {
                    return 0.0;
                }
                // The label term's curvature in an affine weight is β Σ ψ_p², ψ_p of z or 1.
                #[allow(clippy::cast_precision_loss)] // small sizes
                let mean_psi = self.z.iter().map(|z| z.norm_squared() + 1.0).sum::<f64>() / 7.0;
                #[allow(clippy::cast_precision_loss)] // small sizes
                let mean_shape = (0..6)
                    .flat_map(|kk| (0..7).map(move |p| kk * width + p))
                    .map(|i| h[(i, i)])
                    .sum::<f64>()
                    / 42.0;
                self.label_weight * mean_shape / mean_psi.max(f64::MIN_POSITIVE)
            });
            if beta > 0.0 {
                for (k, y) in self.targets.iter().enumerate() {
                    let psi = map.psi(&self.z[k]);
                    let e = &map.theta * &psi;
                    for kk in 0..6 {
                        let ek = e[kk] - y[kk];
                        for q in 0..width {
                            let vq = beta * psi[q];
                            for p in 0..width {
                                h[(kk * width + p, kk * width + q)] += vq * psi[p];
                            }
                            b[kk * width + q] += beta * ek * psi[q];
                        }
                    }
                }
            }
            loss = current + ridge_term(map, lambda) + self.label_term(map, beta);
            for kk in 0..6 {
                for p in 7..width {
                    let i = kk * width + p;
                    h[(i, i)] += lambda;
                    b[i] += lambda * map.theta[(kk, p)];
                }
            }
            let mut accepted = false;
            while mu < 1e10 {
                let mut damped = h.clone();
                for i in 0..n {
                    damped[(i, i)] += mu * h[(i, i)].max(1e-12);
                }
                let Some(chol) = damped.cholesky() else {
                    mu *= 10.0;
                    continue;
                };
                let step = chol.solve(&(-&b));
                let mut next = map.clone();
                for kk in 0..6 {
                    for p in 0..width {
                        next.theta[(kk, p)] += step[kk * width + p];
                    }
                }
                let next_gravity = match (*gravity, fit_gravity) {
                    (Some(g), true) => {
                        let (e1, e2) = tangent_basis(&g);
                        Some((g + step[6 * width] * e1 + step[6 * width + 1] * e2).normalize())
                    }
                    (g, _) => g,
                };
                let next_loss = self.objective(&next, next_gravity, (lambda, beta))?;
                if next_loss < loss {
                    let decrease = (loss - next_loss) / loss.max(f64::MIN_POSITIVE);
                    *map = next;
                    *gravity = next_gravity;
                    loss = next_loss;
                    mu = (mu / 3.0).max(1e-9);
                    accepted = decrease > 1e-7;
                    break;
                }
                mu *= 4.0;
            }
            if !accepted {
                break;
            }
        }
        Ok(Outcome { loss, iterations })
    }

    /// A fitted map's report, with its validation distance.
    fn candidate(
        &self,
        map: &Map,
        gravity: Option<Vector3<f64>>,
        ridge: f64,
        iterations: usize,
        validation: &[ShapeSample],
    ) -> Result<Candidate, EstimateError> {
        let train = self.evaluate(map, gravity, false)?;
        let check = Problem {
            huber: self.huber,
            ..Problem::new(self.model, self.frame, validation, self.gravity)
        };
        let held = check.evaluate(map, gravity, false)?;
        Ok(Candidate {
            degree: map.degree,
            ridge,
            iterations,
            train_marker_mean: mean_distance(&train),
            validation_marker_mean: mean_distance(&held),
            validation_failures: held.iter().filter(|t| t.is_none()).count(),
            gravity_in_clamp: gravity.map(|g| self.gravity_vector(&g).into()),
        })
    }
}

/// How a calibration's shapes meet `samples`' markers, as the candidates are judged: the mean
/// over records of each one's mean marker distance to `Φ(apply(raw) + offset)` \[m\], and the
/// records whose shape could not be solved. `nodes` as [`ShapeLossParams::nodes`].
///
/// # Errors
/// [`EstimateError::InvalidSetting`] for fewer than 2 nodes.
pub fn marker_mean<M: WireModel>(
    model: &M,
    calibration: &Calibration,
    samples: &[ShapeSample],
    nodes: usize,
) -> Result<(f64, usize), EstimateError> {
    if nodes < 2 {
        #[allow(clippy::cast_precision_loss)] // a small number
        return Err(EstimateError::InvalidSetting {
            field: "nodes",
            value: nodes as f64,
            allowed: "at least 2 nodes",
        });
    }
    let frame = Frame {
        input: *calibration.input_normaliser(),
        output: *calibration.output_normaliser(),
        nodes,
    };
    let problem = Problem::new(model, &frame, samples, None);
    let terms: Vec<Option<Terms>> = samples
        .iter()
        .map(|s| {
            problem.terms(
                model,
                None,
                &(calibration.apply(&s.raw) + s.offset),
                s,
                false,
            )
        })
        .collect();
    Ok((
        mean_distance(&terms),
        terms.iter().filter(|t| t.is_none()).count(),
    ))
}

/// The mean over records of each record's mean marker distance \[m\].
fn mean_distance(terms: &[Option<Terms>]) -> f64 {
    let means: Vec<f64> = terms
        .iter()
        .flatten()
        .filter(|t| !t.distances.is_empty())
        .map(|t| {
            #[allow(clippy::cast_precision_loss)] // a handful of markers
            let n = t.distances.len() as f64;
            t.distances.iter().sum::<f64>() / n
        })
        .collect();
    #[allow(clippy::cast_precision_loss)] // counts
    let n = means.len().max(1) as f64;
    means.iter().sum::<f64>() / n
}

/// `ρ_δ(d)`: `d²/2` up to `δ`, `δ (d − δ/2)` beyond.
fn huber_loss(d: f64, delta: f64) -> f64 {
    if d <= delta {
        0.5 * d * d
    } else {
        delta * (d - 0.5 * delta)
    }
}

/// `½ λ |W|²` over the polynomial weights.
fn ridge_term(map: &Map, lambda: f64) -> f64 {
    if map.theta.ncols() <= 7 {
        return 0.0;
    }
    0.5 * lambda * map.theta.columns(7, map.theta.ncols() - 7).norm_squared()
}

/// Two unit vectors across `g` (unit), right-handed with it.
fn tangent_basis(g: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let helper = if g.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = g.cross(&helper).normalize();
    let e2 = g.cross(&e1);
    (e1, e2)
}
