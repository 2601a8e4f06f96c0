//! The global stage of the shape fit: where the local refinement starts.
//!
//! The paper solves eq. 15 with PSO (§IV-A). The fit asks its global stage only for a few
//! promising starts, given the fit's cost as a function of the normalised configuration, through
//! the [`GlobalSearch`] trait. Two stages implement it: [`MultiStart`], the best of `K` seeded
//! samples of `A_stable` (the default), and [`SwarmSearch`], the paper's PSO (the particle swarm
//! of `identify`) over normalised `A`.

use std::cell::RefCell;

use nalgebra::Vector6;
use rand::{Rng, RngExt};

use crate::EstimateError;
use crate::identify::ParticleSwarm;
use crate::shape::setting;

/// A global search over normalised configurations `z` (torque in `c2/L`, force in `c2/L²`).
pub trait GlobalSearch {
    /// Up to a handful of starts for the local refinement, best first.
    ///
    /// `cost(z)` is the fit's cost at `z`, or `None` where `z` is not admissible (outside
    /// `A_stable`, or the model cannot be solved). All randomness comes from `rng`.
    ///
    /// # Errors
    /// [`EstimateError::NoFitStart`] if no admissible start was found.
    fn starts<R: Rng + ?Sized>(
        &self,
        cost: &mut dyn FnMut(&Vector6<f64>) -> Option<f64>,
        rng: &mut R,
    ) -> Result<Vec<Vector6<f64>>, EstimateError>;
}

/// Seeded multi-start: draws `samples` admissible configurations uniformly from the box
/// `[−half_width, half_width]⁶` (normalised units; rejection sampling, so samples of `A_stable`
/// when the cost rejects unstable ones) and returns the `starts` cheapest.
///
/// # Example
/// ```
/// use ftwire_estimate::shape::{GlobalSearch, MultiStart};
/// use nalgebra::Vector6;
/// use rand::SeedableRng;
/// let search = MultiStart { samples: 200, starts: 2, ..MultiStart::default() };
/// let target = Vector6::repeat(1.0);
/// let mut cost = |z: &Vector6<f64>| Some((z - target).norm_squared());
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
/// let starts = search.starts(&mut cost, &mut rng)?;
/// assert_eq!(starts.len(), 2);
/// assert!((starts[0] - target).norm() <= (starts[1] - target).norm());
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultiStart {
    /// Admissible samples drawn, `K` (default `256`).
    pub samples: usize,
    /// Half-width of the sampling box in normalised units (default `20`).
    pub half_width: f64,
    /// Starts handed to the local refinement (default `8`).
    pub starts: usize,
    /// Draws allowed per admissible sample before giving up (default `20`).
    pub attempts_per_sample: usize,
}

impl Default for MultiStart {
    fn default() -> Self {
        Self {
            samples: 256,
            half_width: 20.0,
            starts: 8,
            attempts_per_sample: 20,
        }
    }
}

impl MultiStart {
    fn validate(&self) -> Result<(), EstimateError> {
        let counts = [
            ("global.samples", self.samples),
            ("global.starts", self.starts),
            ("global.attempts_per_sample", self.attempts_per_sample),
        ];
        for (name, value) in counts {
            setting::count(name, value, 1, usize::MAX, "at least 1")?;
        }
        setting::positive(
            "global.half_width",
            self.half_width,
            "finite and > 0 (normalised units)",
        )
    }
}

impl GlobalSearch for MultiStart {
    fn starts<R: Rng + ?Sized>(
        &self,
        cost: &mut dyn FnMut(&Vector6<f64>) -> Option<f64>,
        rng: &mut R,
    ) -> Result<Vec<Vector6<f64>>, EstimateError> {
        self.validate()?;
        let w = self.half_width;
        let budget = self.samples.saturating_mul(self.attempts_per_sample);
        let mut scored: Vec<(f64, Vector6<f64>)> = Vec::with_capacity(self.samples);
        let mut attempts = 0;
        while scored.len() < self.samples && attempts < budget {
            attempts += 1;
            let z = Vector6::from_fn(|_, _| rng.random_range(-w..=w));
            if let Some(c) = cost(&z).filter(|c| c.is_finite()) {
                scored.push((c, z));
            }
        }
        if scored.is_empty() {
            return Err(EstimateError::NoFitStart { attempts });
        }
        scored.sort_by(|a, b| a.0.total_cmp(&b.0));
        Ok(scored
            .into_iter()
            .take(self.starts)
            .map(|(_, z)| z)
            .collect())
    }
}

/// The paper's global stage (§IV-A solves eq. 15 with PSO): the particle swarm of
/// [`crate::identify::ParticleSwarm`] over the box `[−half_width, half_width]⁶` of normalised
/// configurations, run for a fixed number of iterations; inadmissible points (outside
/// `A_stable`, or not solvable) cost [`SwarmSearch::PENALTY`]. It returns the swarm's distinct
/// personal bests, best first.
///
/// # Example
/// ```
/// use ftwire_estimate::shape::{GlobalSearch, SwarmSearch};
/// use nalgebra::Vector6;
/// use rand::SeedableRng;
/// let target = Vector6::new(1.0, -2.0, 0.5, 3.0, -1.0, 2.0);
/// let mut cost = |z: &Vector6<f64>| Some((z - target).norm_squared());
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
/// let starts = SwarmSearch::default().starts(&mut cost, &mut rng)?;
/// // A coarse start: the local refinement finishes the job.
/// assert!((starts[0] - target).norm() < 5.0, "{}", (starts[0] - target).norm());
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwarmSearch {
    /// Particles (default `20`, the authors' count).
    pub particles: usize,
    /// Iterations (default `40`).
    pub iterations: usize,
    /// Half-width of the box in normalised units (default `20`).
    pub half_width: f64,
    /// Starts handed to the local refinement (default `4`).
    pub starts: usize,
}

impl Default for SwarmSearch {
    fn default() -> Self {
        Self {
            particles: 20,
            iterations: 40,
            half_width: 20.0,
            starts: 4,
        }
    }
}

impl SwarmSearch {
    /// The cost of an inadmissible point: larger than any fit's cost in normalised units.
    pub const PENALTY: f64 = 1e12;
}

impl GlobalSearch for SwarmSearch {
    fn starts<R: Rng + ?Sized>(
        &self,
        cost: &mut dyn FnMut(&Vector6<f64>) -> Option<f64>,
        rng: &mut R,
    ) -> Result<Vec<Vector6<f64>>, EstimateError> {
        setting::count(
            "global.iterations",
            self.iterations,
            1,
            usize::MAX,
            "at least 1",
        )?;
        setting::count("global.starts", self.starts, 1, usize::MAX, "at least 1")?;
        setting::positive(
            "global.half_width",
            self.half_width,
            "finite and > 0 (normalised units)",
        )?;
        let w = self.half_width;
        let pso = ParticleSwarm::new(vec![-w; 6], vec![w; 6], self.particles)?;
        // The swarm takes a cost by shared reference; the fit's cost is a mutable closure.
        let cost = RefCell::new(cost);
        let objective = |x: &[f64]| {
            let z = Vector6::from_iterator(x.iter().copied());
            (cost.borrow_mut())(&z)
                .filter(|c| c.is_finite())
                .map_or(Self::PENALTY, |c| c.min(Self::PENALTY))
        };
        let mut swarm = pso.init(&objective, rng);
        for _ in 0..self.iterations {
            pso.iterate(&objective, &mut swarm, rng);
        }
        let starts: Vec<Vector6<f64>> = swarm
            .distinct_bests(self.starts, 0.1)
            .into_iter()
            .filter(|best| objective(best) < Self::PENALTY)
            .map(Vector6::from_iterator)
            .collect();
        if starts.is_empty() {
            return Err(EstimateError::NoFitStart {
                attempts: swarm.evaluations,
            });
        }
        Ok(starts)
    }
}
