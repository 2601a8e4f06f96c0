//! What the map fitted on the shape minimises: each record's markers' distances to
//! `Φ_g(a)` under Huber's loss, with the label term and the ridge ([`Problem`]), and each
//! record's terms of the normal equations through the model's Jacobian ([`Terms`]), computed
//! on every core in record order; the candidates' reports and [`marker_mean`], which judge a
//! map the same way.

use nalgebra::{DVector, Matrix3, Matrix6, Matrix6x2, Vector2, Vector3, Vector6};

use super::fitted::Candidate;
use super::settings::{GravityFit, ShapeSample};
use super::theta::{Frame, Map};
use crate::calibration::Calibration;
use crate::shape::{centreline_point, closest_point};
use crate::{EstimateError, WireModel};

/// Forward-difference step of gravity's direction \[rad\].
const GRAVITY_STEP: f64 = 1e-4;

/// One record's terms of the normal equations in `a` (and gravity's two directions).
pub(super) struct Terms {
    pub(super) loss: f64,
    pub(super) distances: Vec<f64>,
    pub(super) g: Matrix6<f64>,
    pub(super) b: Vector6<f64>,
    pub(super) c: Matrix6x2<f64>,
    pub(super) gg: nalgebra::Matrix2<f64>,
    pub(super) bg: Vector2<f64>,
}

/// The loss over a set of records: the model, the records and their standardised readings,
/// gravity's fit, Huber's threshold and the label term.
pub(super) struct Problem<'a, M> {
    pub(super) model: &'a M,
    pub(super) frame: &'a Frame,
    pub(super) samples: Vec<&'a ShapeSample>,
    pub(super) z: Vec<Vector6<f64>>,
    pub(super) gravity: Option<GravityFit>,
    pub(super) huber: f64,
    /// The normalised labels of the samples (empty: no label term).
    pub(super) targets: Vec<Vector6<f64>>,
    /// The label term's relative weight.
    pub(super) label_weight: f64,
}

impl<'a, M: WireModel> Problem<'a, M> {
    pub(super) fn new(
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
    pub(super) fn label_term(&self, map: &Map, beta: f64) -> f64 {
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
    pub(super) fn keep(&mut self, evaluations: &[Option<Terms>]) {
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
    pub(super) fn start_gravity(&self) -> Option<Vector3<f64>> {
        self.gravity.map(|g| {
            g.start
                .map_or(-Vector3::z(), |s| Vector3::from(s).normalize())
        })
    }

    pub(super) fn gravity_vector(&self, direction: &Vector3<f64>) -> Vector3<f64> {
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
    pub(super) fn evaluate(
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
    pub(super) fn objective(
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

    /// A fitted map's report, with its validation distance.
    pub(super) fn candidate(
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

/// How a calibration's shapes meet `samples`' markers, as the candidates are judged: the mean over
/// records of each one's mean marker distance to `Φ(apply(raw) + offset)` \[m\], and the records
/// whose shape could not be solved. `nodes` as
/// [`ShapeLossParams::nodes`](super::ShapeLossParams::nodes).
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
pub(super) fn ridge_term(map: &Map, lambda: f64) -> f64 {
    if map.theta.ncols() <= 7 {
        return 0.0;
    }
    0.5 * lambda * map.theta.columns(7, map.theta.ncols() - 7).norm_squared()
}

/// Two unit vectors across `g` (unit), right-handed with it.
pub(super) fn tangent_basis(g: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let helper = if g.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = g.cross(&helper).normalize();
    let e2 = g.cross(&e1);
    (e1, e2)
}
