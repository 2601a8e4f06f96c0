//! Shape fitting: the configuration `a` whose centreline passes through the markers (paper
//! §IV-A, eq. 15),
//!
//! ```text
//! a = argmin_a  Σ_k ‖x_k(a) − p_k‖²
//! ```
//!
//! with `x_k(a)` the model's point matched to marker `p_k` ([`Correspondence`]).
//!
//! The fit works in normalised units `z` (torque in `c2/L`, force in `c2/L²`; see
//! [`ftwire_rod::to_normalised`]) and residuals in units of `L`, so that its settings suit any
//! wire. It runs in two stages:
//!
//! 1. **Global** ([`GlobalSearch`]; [`MultiStart`] by default, the paper's PSO
//!    [`crate::shape::SwarmSearch`] on request): first a coarse continuation
//!    from the straight wire (the markers are blended from their straight-wire places to the
//!    measured ones in a few steps, each refined from the last); if that does not give a
//!    trusted fit, the cheapest samples of `A_stable` the global search returns.
//! 2. **Local**: Levenberg–Marquardt ([`LevenbergMarquardt`]) from each start, with the analytic
//!    derivative of every marker position ([`crate::shape::centreline_point`]); the lowest cost
//!    wins.
//!
//! Guarded by `tests/shape_fit.rs`.

use ftwire_rod::{from_normalised, to_normalised};
use nalgebra::{Matrix3, Matrix3x6, Matrix6, Vector3, Vector6};
use rand::Rng;

use crate::shape::centreline_point::centreline_point;
use crate::shape::global::{GlobalSearch, MultiStart};
use crate::shape::levenberg_marquardt::{LeastSquares, LevenbergMarquardt, Normal, Termination};
use crate::shape::markers::Markers;
use crate::shape::polyline::closest_point;
use crate::shape::setting;
use crate::{EstimateError, WireModel};

/// Which point of the model's centreline a marker is compared with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Correspondence {
    /// `x_k = p(s_k; a)`, the point at the marker's known arc length (default).
    ///
    /// Better conditioned than [`Correspondence::ClosestPoint`]: each marker constrains all 3
    /// coordinates instead of the 2 across the wire, so a shape that slides along itself (the
    /// near-straight wire under tension, twist, a uniform arc) still moves the residual; the cost
    /// is smooth in `a` and its Jacobian exact, where the closest point jumps between branches
    /// of the wire and makes the cost only piecewise smooth.
    #[default]
    ArcLength,
    /// `x_k` = the closest point of `Φ(a)` to `p_k`, as the paper writes eq. 15. Use it when the
    /// markers' arc lengths are not known. The residual is the distance to the tangent line at
    /// the closest point (which point-to-curve distance it equals to first order), with the
    /// Jacobian projected across the tangent.
    ClosestPoint,
}

/// Settings of the shape fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitParams {
    /// Marker-to-model matching (default [`Correspondence::ArcLength`]).
    pub correspondence: Correspondence,
    /// The local refinement (default [`LevenbergMarquardt::default`]).
    pub local: LevenbergMarquardt,
    /// Blending steps of the continuation from the straight wire; `0` turns it off (default
    /// `4`).
    pub continuation_steps: usize,
    /// A fit is trusted when it converged and its RMS marker residual is at most this \[m\]
    /// (default `0.0015`, 1.5 mm: three times the 0.52 mm RMS that 0.3 mm noise per axis gives).
    pub trusted_rms: f64,
    /// Stop trying starts at the first trusted fit (default `true`); `false` refines every start.
    pub stop_when_trusted: bool,
    /// Nodes of the polyline on which closest points are searched
    /// ([`Correspondence::ClosestPoint`] only) (default `101`).
    pub closest_point_nodes: usize,
}

impl Default for FitParams {
    fn default() -> Self {
        Self {
            correspondence: Correspondence::ArcLength,
            local: LevenbergMarquardt::default(),
            continuation_steps: 4,
            trusted_rms: 1.5e-3,
            stop_when_trusted: true,
            closest_point_nodes: 101,
        }
    }
}

impl FitParams {
    fn validate(&self) -> Result<(), EstimateError> {
        self.local.validate()?;
        setting::positive("trusted_rms", self.trusted_rms, "finite and > 0 [m]")?;
        setting::count(
            "closest_point_nodes",
            self.closest_point_nodes,
            3,
            100_000,
            "3 to 100000",
        )
    }
}

/// The result of a shape fit.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeFit {
    /// The fitted configuration `a` \[N·m, N\] (torque first, base clamp frame).
    pub a: Vector6<f64>,
    /// RMS over the observed markers of the residual distance `‖x_k(a) − p_k‖` \[m\].
    pub rms: f64,
    /// Each observed marker's residual distance \[m\], in the order of [`Markers::iter`].
    pub residuals: Vec<f64>,
    /// Whether the fit can be trusted: the local stage converged and `rms ≤ trusted_rms`.
    pub trusted: bool,
    /// Whether `a ∈ A_stable`.
    pub stable: bool,
    /// Why the local refinement of the returned fit stopped.
    pub termination: Termination,
    /// Local iterations (Jacobian evaluations) of the returned fit.
    pub iterations: usize,
    /// Starts refined.
    pub starts: usize,
}

/// Fits `a` to motion-capture markers with a wire model (paper eq. 15).
///
/// # Example
/// ```
/// use ftwire_core::WireParams;
/// use ftwire_estimate::{KirchhoffModel, WireModel};
/// use ftwire_estimate::shape::{Markers, ShapeFitter, evenly_spaced_fractions};
/// use nalgebra::{Point3, Vector6};
/// use rand::SeedableRng;
/// let model = KirchhoffModel::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
/// let truth = Vector6::new(0.01, 0.02, -0.03, -0.05, 0.1, 0.02);
/// // Markers at 0, 0.1 L, …, L on the true shape.
/// let shape = model.shape(&truth, 11)?;
/// let seen: Vec<_> = shape.positions.iter().map(|p| Some(Point3::from(*p))).collect();
/// let markers = Markers::new(&evenly_spaced_fractions(11), &seen)?;
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
/// let fit = ShapeFitter::new(model).fit(&markers, &mut rng)?;
/// assert!(fit.trusted && fit.rms < 1e-6);
/// assert!((fit.a - truth).norm() < 1e-4 * truth.norm());
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeFitter<M, G = MultiStart> {
    model: M,
    global: G,
    config: FitParams,
}

impl<M: WireModel> ShapeFitter<M> {
    /// A fitter with the default settings and global stage.
    #[must_use]
    pub fn new(model: M) -> Self {
        Self {
            model,
            global: MultiStart::default(),
            config: FitParams::default(),
        }
    }
}

impl<M: WireModel, G: GlobalSearch> ShapeFitter<M, G> {
    /// The same fitter with other settings.
    ///
    /// # Errors
    /// [`EstimateError::BadShapeSetting`] naming a setting out of range.
    pub fn with_config(self, config: FitParams) -> Result<Self, EstimateError> {
        config.validate()?;
        Ok(Self { config, ..self })
    }

    /// The same fitter with another global stage (e.g. a particle swarm).
    #[must_use]
    pub fn with_global<H: GlobalSearch>(self, global: H) -> ShapeFitter<M, H> {
        ShapeFitter {
            model: self.model,
            global,
            config: self.config,
        }
    }

    /// The wire model.
    pub fn model(&self) -> &M {
        &self.model
    }

    /// The settings.
    pub fn config(&self) -> &FitParams {
        &self.config
    }

    /// Fits `a` to `markers`: global stage, then local refinement (see the module docs).
    ///
    /// # Errors
    /// [`EstimateError::NoFitStart`] if no start could be evaluated; model errors if the final
    /// fit cannot be evaluated.
    pub fn fit<R: Rng + ?Sized>(
        &self,
        markers: &Markers,
        rng: &mut R,
    ) -> Result<ShapeFit, EstimateError> {
        let problem = self.problem(markers);
        let mut best: Option<Candidate> = None;
        let mut starts = 0;
        if let Some(z) = self.continuation(markers) {
            starts += 1;
            if self.consider(&problem, &z, &mut best) {
                return self.finish(&problem, best, starts);
            }
        }
        let model = &self.model;
        let mut cost = |z: &Vector6<f64>| -> Option<f64> {
            let a = from_normalised(model.wire(), z);
            if !model.is_stable(&a).ok()? {
                return None;
            }
            problem.cost(z).ok()
        };
        let global_starts = match self.global.starts(&mut cost, rng) {
            Ok(found) => found,
            Err(error) if best.is_none() => return Err(error),
            Err(_) => Vec::new(),
        };
        for z in &global_starts {
            starts += 1;
            if self.consider(&problem, z, &mut best) {
                break;
            }
        }
        self.finish(&problem, best, starts)
    }

    /// Refines a fit from a known start `a0` (e.g. the previous frame's fit), local stage only.
    ///
    /// # Errors
    /// As [`WireModel::jacobian`] at `a0`.
    pub fn refine(&self, markers: &Markers, a0: &Vector6<f64>) -> Result<ShapeFit, EstimateError> {
        let problem = self.problem(markers);
        let z0 = to_normalised(self.model.wire(), a0);
        let refined = self.config.local.minimise(&problem, &z0)?;
        self.finish(&problem, Some(Candidate(refined.z, refined)), 1)
    }

    fn problem<'a>(&'a self, markers: &Markers) -> MarkerProblem<'a, M> {
        MarkerProblem {
            model: &self.model,
            targets: markers
                .iter()
                .map(|m| (m.fraction, m.position.coords))
                .collect(),
            correspondence: self.config.correspondence,
            nodes: self.config.closest_point_nodes,
        }
    }

    /// Refines from `z` and keeps the result if it is the best so far; `true` when it is a
    /// trusted fit and the settings say to stop there.
    fn consider(
        &self,
        problem: &MarkerProblem<'_, M>,
        z: &Vector6<f64>,
        best: &mut Option<Candidate>,
    ) -> bool {
        let Ok(refined) = self.config.local.minimise(problem, z) else {
            return false;
        };
        let trusted = refined.termination.converged()
            && rms_of(refined.cost, problem) * problem.length() <= self.config.trusted_rms;
        if best.as_ref().is_none_or(|b| refined.cost < b.1.cost) {
            *best = Some(Candidate(refined.z, refined));
        }
        trusted && self.config.stop_when_trusted
    }

    /// The continuation from the straight wire: the start it ends on, if every step solved.
    fn continuation(&self, markers: &Markers) -> Option<Vector6<f64>> {
        let steps = self.config.continuation_steps;
        if steps == 0 {
            return None;
        }
        let length = self.model.wire().length();
        let local = LevenbergMarquardt {
            max_iterations: self.config.local.max_iterations.min(8),
            ..self.config.local
        };
        // Nearly straight, and inside A.
        let mut z = Vector6::new(0.0, 1e-3, 1e-3, 0.0, 1e-3, 1e-3);
        for step in 1..steps {
            let lambda = step as f64 / steps as f64;
            let mut problem = self.problem(markers);
            for (target, marker) in problem.targets.iter_mut().zip(markers) {
                let straight = Vector3::new(marker.fraction * length, 0.0, 0.0);
                target.1 = straight + lambda * (marker.position.coords - straight);
            }
            z = local.minimise(&problem, &z).ok()?.z;
        }
        Some(z)
    }

    fn finish(
        &self,
        problem: &MarkerProblem<'_, M>,
        best: Option<Candidate>,
        starts: usize,
    ) -> Result<ShapeFit, EstimateError> {
        let Some(Candidate(z, refined)) = best else {
            return Err(EstimateError::NoFitStart { attempts: starts });
        };
        let a = from_normalised(self.model.wire(), &z);
        let length = problem.length();
        let residuals: Vec<f64> = problem
            .residuals(&z, false)?
            .iter()
            .map(|m| m.residual.norm() * length)
            .collect();
        let rms =
            (residuals.iter().map(|r| r * r).sum::<f64>() / residuals.len().max(1) as f64).sqrt();
        Ok(ShapeFit {
            a,
            rms,
            residuals,
            trusted: refined.termination.converged() && rms <= self.config.trusted_rms,
            stable: self.model.is_stable(&a)?,
            termination: refined.termination,
            iterations: refined.iterations,
            starts,
        })
    }
}

/// A refined start.
struct Candidate(Vector6<f64>, crate::shape::levenberg_marquardt::Refined);

/// RMS residual (units of `L`) from the cost `½‖r‖²`.
fn rms_of<M: WireModel>(cost: f64, problem: &MarkerProblem<'_, M>) -> f64 {
    (2.0 * cost / problem.targets.len().max(1) as f64).sqrt()
}

/// One marker's residual `(x_k − p_k) / L` and its Jacobian with respect to `z`.
struct MarkerResidual {
    residual: Vector3<f64>,
    jacobian: Matrix3x6<f64>,
}

/// Eq. 15 as a least-squares problem in normalised `z`, residuals in units of `L`.
struct MarkerProblem<'a, M> {
    model: &'a M,
    /// `(s_k / L, p_k)` per observed marker.
    targets: Vec<(f64, Vector3<f64>)>,
    correspondence: Correspondence,
    nodes: usize,
}

impl<M: WireModel> MarkerProblem<'_, M> {
    fn length(&self) -> f64 {
        self.model.wire().length()
    }

    /// `∂a/∂z`: the normalisation's diagonal.
    fn scales(&self) -> Vector6<f64> {
        from_normalised(self.model.wire(), &Vector6::repeat(1.0))
    }

    /// Each marker's residual `(x_k − p_k) / L` and, with `with_jacobian`, its Jacobian with
    /// respect to `z`.
    fn residuals(
        &self,
        z: &Vector6<f64>,
        with_jacobian: bool,
    ) -> Result<Vec<MarkerResidual>, EstimateError> {
        let a = from_normalised(self.model.wire(), z);
        let length = self.length();
        let scales = Matrix6::from_diagonal(&(self.scales() / length));
        let arc_lengths: Vec<f64> = match self.correspondence {
            Correspondence::ArcLength => self.targets.iter().map(|t| t.0 * length).collect(),
            Correspondence::ClosestPoint => {
                let shape = self.model.shape(&a, self.nodes)?;
                let spacing = length / (self.nodes - 1) as f64;
                self.targets
                    .iter()
                    .map(|(_, p)| {
                        closest_point(&shape.positions, p)
                            .map_or(0.0, |c| (c.segment as f64 + c.parameter) * spacing)
                    })
                    .collect()
            }
        };
        let mut out = Vec::with_capacity(self.targets.len());
        for ((_, p), s) in self.targets.iter().zip(arc_lengths) {
            let point = centreline_point(self.model, &a, s, with_jacobian)?;
            let mut residual = (point.position - p) / length;
            let mut jacobian = point.jacobian * scales;
            if self.correspondence == Correspondence::ClosestPoint {
                let across = Matrix3::identity() - point.tangent * point.tangent.transpose();
                residual = across * residual;
                jacobian = across * jacobian;
            }
            out.push(MarkerResidual { residual, jacobian });
        }
        Ok(out)
    }
}

impl<M: WireModel> LeastSquares for MarkerProblem<'_, M> {
    fn cost(&self, z: &Vector6<f64>) -> Result<f64, EstimateError> {
        Ok(0.5
            * self
                .residuals(z, false)?
                .iter()
                .map(|m| m.residual.norm_squared())
                .sum::<f64>())
    }

    fn linearise(&self, z: &Vector6<f64>) -> Result<Normal, EstimateError> {
        let mut normal = Normal {
            cost: 0.0,
            jtj: Matrix6::zeros(),
            jtr: Vector6::zeros(),
        };
        for MarkerResidual {
            residual: r,
            jacobian: j,
        } in self.residuals(z, true)?
        {
            normal.cost += 0.5 * r.norm_squared();
            normal.jtj += j.transpose() * j;
            normal.jtr += j.transpose() * r;
        }
        Ok(normal)
    }
}
