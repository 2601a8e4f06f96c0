//! Particle swarm optimisation (Kennedy & Eberhart 1995, the paper's ref. 23) in argmin's
//! shape, with a streaming mode.
//!
//! argmin 0.11's `ParticleSwarm` cannot be fed new data: a population handed back keeps its
//! stored costs and personal bests, which go stale when new samples change the objective.
//! Here the method ([`ParticleSwarm`]: validated settings) and the state ([`Swarm`]: plain
//! data) are apart, as in argmin, and [`ParticleSwarm::refresh`] re-evaluates every particle's
//! position and personal best on the new objective, keeps the swarm, and re-injects a few random
//! particles (so a swarm that collapsed into a local minimum of the old objective can still
//! find the new one).
//!
//! The update is the canonical one, with a uniform draw per dimension:
//! `v ← ω v + φp rp ∘ (p_best − x) + φg rg ∘ (g_best − x)`, `x ← clamp(x + v)` (a clamped
//! component's velocity is zeroed).

use rand::{Rng, RngExt};

use crate::EstimateError;

/// A cost to minimise over a box.
pub trait CostFunction {
    /// The cost at `x` (finite; return a large finite value where the cost is undefined).
    fn cost(&self, x: &[f64]) -> f64;
}

impl<F: Fn(&[f64]) -> f64> CostFunction for F {
    fn cost(&self, x: &[f64]) -> f64 {
        self(x)
    }
}

/// The swarm's settings (the method), validated on construction.
///
/// # Example
/// ```
/// use ftwire_estimate::identify::ParticleSwarm;
/// use rand::SeedableRng;
/// let pso = ParticleSwarm::new(vec![-2.0, -2.0], vec![2.0, 2.0], 20)?.with_inertia_factor(0.6)?;
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
/// let cost = |x: &[f64]| (x[0] - 1.0).powi(2) + (x[1] + 0.5).powi(2);
/// let mut swarm = pso.init(&cost, &mut rng);
/// for _ in 0..60 {
///     pso.iterate(&cost, &mut swarm, &mut rng);
/// }
/// assert!(swarm.best_cost < 1e-6);
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleSwarm {
    lower: Vec<f64>,
    upper: Vec<f64>,
    particles: usize,
    inertia: f64,
    cognitive: f64,
    social: f64,
    reinjected: usize,
    candidates: usize,
}

/// One particle.
#[derive(Debug, Clone, PartialEq)]
pub struct Particle {
    /// Current position.
    pub position: Vec<f64>,
    /// Current velocity.
    pub velocity: Vec<f64>,
    /// Cost at `position`.
    pub cost: f64,
    /// The best position this particle has visited (on the current objective).
    pub best_position: Vec<f64>,
    /// Cost at `best_position`.
    pub best_cost: f64,
}

/// The swarm's state: plain data, handed back to the method at each iteration.
#[derive(Debug, Clone, PartialEq)]
pub struct Swarm {
    /// The particles.
    pub particles: Vec<Particle>,
    /// The best position found (on the current objective).
    pub best_position: Vec<f64>,
    /// Cost at `best_position`.
    pub best_cost: f64,
    /// Iterations run since the last [`ParticleSwarm::init`] or [`ParticleSwarm::refresh`].
    pub iterations: usize,
    /// Cost evaluations since creation.
    pub evaluations: usize,
}

fn setting(
    field: &'static str,
    value: f64,
    ok: bool,
    allowed: &'static str,
) -> Result<(), EstimateError> {
    if ok {
        Ok(())
    } else {
        Err(EstimateError::BadIdentifySetting {
            field,
            value,
            allowed,
        })
    }
}

impl Default for ParticleSwarm {
    /// 20 particles (the authors' count), `ω = φp = φg = 0.5`, 2 re-injected, each new one the
    /// best of 10 stratified candidates, over the box `[0, 1]` (replace it with
    /// [`ParticleSwarm::with_bounds`]).
    fn default() -> Self {
        Self {
            lower: vec![0.0],
            upper: vec![1.0],
            particles: 20,
            inertia: 0.5,
            cognitive: 0.5,
            social: 0.5,
            reinjected: 2,
            candidates: 10,
        }
    }
}

impl ParticleSwarm {
    /// A swarm of `particles` particles over the box `[lower, upper]`, with the authors'
    /// factors `ω = φp = φg = 0.5` and 2 re-injected particles per refresh.
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] if the bounds differ in length, are empty,
    /// non-finite or not `lower < upper`, or `particles < 2`.
    pub fn new(lower: Vec<f64>, upper: Vec<f64>, particles: usize) -> Result<Self, EstimateError> {
        setting(
            "pso.particles",
            particles as f64,
            particles >= 2,
            "at least 2",
        )?;
        setting(
            "pso.bounds dimension",
            lower.len() as f64,
            !lower.is_empty() && lower.len() == upper.len(),
            "lower and upper bounds of the same non-zero length",
        )?;
        for (l, u) in lower.iter().zip(&upper) {
            setting(
                "pso.lower bound",
                *l,
                l.is_finite() && u.is_finite() && l < u,
                "finite, below the upper bound",
            )?;
        }
        Ok(Self {
            lower,
            upper,
            particles,
            inertia: 0.5,
            cognitive: 0.5,
            social: 0.5,
            reinjected: 2,
            candidates: 10,
        })
    }

    /// The inertia factor `ω` (default `0.5`).
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] unless `0 ≤ ω < 1`.
    #[must_use = "returns the changed swarm settings"]
    pub fn with_inertia_factor(mut self, inertia: f64) -> Result<Self, EstimateError> {
        setting(
            "pso.inertia",
            inertia,
            (0.0..1.0).contains(&inertia),
            "0 <= inertia < 1",
        )?;
        self.inertia = inertia;
        Ok(self)
    }

    /// The cognitive (personal-best) factor `φp` (default `0.5`).
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] unless finite and `≥ 0`.
    #[must_use = "returns the changed swarm settings"]
    pub fn with_cognitive_factor(mut self, cognitive: f64) -> Result<Self, EstimateError> {
        setting(
            "pso.cognitive",
            cognitive,
            cognitive.is_finite() && cognitive >= 0.0,
            "finite and >= 0",
        )?;
        self.cognitive = cognitive;
        Ok(self)
    }

    /// The social (global-best) factor `φg` (default `0.5`).
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] unless finite and `≥ 0`.
    #[must_use = "returns the changed swarm settings"]
    pub fn with_social_factor(mut self, social: f64) -> Result<Self, EstimateError> {
        setting(
            "pso.social",
            social,
            social.is_finite() && social >= 0.0,
            "finite and >= 0",
        )?;
        self.social = social;
        Ok(self)
    }

    /// How many particles [`ParticleSwarm::refresh`] replaces by random ones, the worst by
    /// personal best first (default `2`).
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] unless fewer than the particles.
    #[must_use = "returns the changed swarm settings"]
    pub fn with_reinjected(mut self, reinjected: usize) -> Result<Self, EstimateError> {
        setting(
            "pso.reinjected",
            reinjected as f64,
            reinjected < self.particles,
            "fewer than the particles",
        )?;
        self.reinjected = reinjected;
        Ok(self)
    }

    /// How many stratified candidates each new particle is chosen from (default `10`): a new
    /// swarm of `n` particles (and `k` re-injected ones) are the lowest-cost `n` (`k`) of `10 n`
    /// (`10 k`) Latin-hypercube candidates. One costs one evaluation, the same as a particle's
    /// move. A cost whose basin is a small fraction of the box in some coordinate (the
    /// stiffness of a strongly bent wire; see [`super::ParameterConstraints`]) is then found
    /// from the start instead of by chance; `1` is the plain stratified swarm.
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] for `0`.
    #[must_use = "returns the changed swarm settings"]
    pub fn with_candidates(mut self, candidates: usize) -> Result<Self, EstimateError> {
        setting(
            "pso.candidates",
            candidates as f64,
            candidates >= 1,
            "at least 1",
        )?;
        self.candidates = candidates;
        Ok(self)
    }

    /// The same settings over another box (e.g. when new samples raise the lower bound on `L`).
    ///
    /// # Errors
    /// As [`ParticleSwarm::new`].
    #[must_use = "returns the changed swarm settings"]
    pub fn with_bounds(self, lower: Vec<f64>, upper: Vec<f64>) -> Result<Self, EstimateError> {
        let fresh = Self::new(lower, upper, self.particles)?;
        Ok(Self {
            lower: fresh.lower,
            upper: fresh.upper,
            ..self
        })
    }

    /// The number of particles.
    pub fn particles(&self) -> usize {
        self.particles
    }

    /// The box `(lower, upper)`.
    pub fn bounds(&self) -> (&[f64], &[f64]) {
        (&self.lower, &self.upper)
    }

    /// `count` particles placed by Latin hypercube sampling of the box: each dimension cut into
    /// `count` equal strata, one particle in each, the strata paired across dimensions by
    /// random permutations. A narrow basin in one coordinate (the stiffness of a strongly
    /// bent wire: its basin in `ln c2` can be a thirtieth of the box) is then never left
    /// between particles by chance, as uniform draws can; velocities are uniform in
    /// `±(upper − lower)`.
    fn stratified_particles<F: CostFunction, R: Rng + ?Sized>(
        &self,
        cost: &F,
        rng: &mut R,
        count: usize,
    ) -> Vec<Particle> {
        let mut candidates = self.stratified(cost, rng, count * self.candidates);
        // Lowest cost first; a stable sort keeps equal costs in draw order (deterministic).
        candidates.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        candidates.truncate(count);
        candidates
    }

    /// `count` Latin-hypercube particles (see [`Self::stratified_particles`]).
    fn stratified<F: CostFunction, R: Rng + ?Sized>(
        &self,
        cost: &F,
        rng: &mut R,
        count: usize,
    ) -> Vec<Particle> {
        let dims = self.lower.len();
        let strata: Vec<Vec<usize>> = (0..dims)
            .map(|_| {
                let mut order: Vec<usize> = (0..count).collect();
                // Fisher–Yates.
                for i in (1..order.len()).rev() {
                    order.swap(i, rng.random_range(0..=i));
                }
                order
            })
            .collect();
        (0..count)
            .map(|k| {
                let mut position = Vec::with_capacity(dims);
                let mut velocity = Vec::with_capacity(dims);
                for (d, (l, u)) in self.lower.iter().zip(&self.upper).enumerate() {
                    let w = u - l;
                    let stratum = strata[d][k] as f64 + rng.random::<f64>();
                    position.push((l + w * stratum / count as f64).clamp(*l, *u));
                    velocity.push(rng.random_range(-w..w));
                }
                let c = cost.cost(&position);
                Particle {
                    best_position: position.clone(),
                    position,
                    velocity,
                    cost: c,
                    best_cost: c,
                }
            })
            .collect()
    }

    /// A new swarm, Latin-hypercube stratified in the box (see `stratified_particles`),
    /// velocities uniform in `±(upper − lower)`.
    pub fn init<F: CostFunction, R: Rng + ?Sized>(&self, cost: &F, rng: &mut R) -> Swarm {
        let particles = self.stratified_particles(cost, rng, self.particles);
        let mut swarm = Swarm {
            best_position: Vec::new(),
            best_cost: f64::INFINITY,
            iterations: 0,
            evaluations: particles.len() * self.candidates,
            particles,
        };
        swarm.update_best();
        swarm
    }

    /// One iteration: every particle moves once and is evaluated.
    pub fn iterate<F: CostFunction, R: Rng + ?Sized>(
        &self,
        cost: &F,
        swarm: &mut Swarm,
        rng: &mut R,
    ) {
        let global = swarm.best_position.clone();
        for p in &mut swarm.particles {
            // Zipped, not indexed: a swarm of another dimension is truncated, never a panic.
            let dims = p
                .position
                .iter_mut()
                .zip(&mut p.velocity)
                .zip(&p.best_position)
                .zip(&global)
                .zip(self.lower.iter().zip(&self.upper));
            for ((((x, v), pb), gb), (l, u)) in dims {
                let (rp, rg): (f64, f64) = (rng.random(), rng.random());
                let step = self.inertia * *v
                    + self.cognitive * rp * (pb - *x)
                    + self.social * rg * (gb - *x);
                let next = (*x + step).clamp(*l, *u);
                *v = if next == *x + step { step } else { 0.0 };
                *x = next;
            }
            p.cost = cost.cost(&p.position);
            if p.cost < p.best_cost {
                p.best_cost = p.cost;
                p.best_position.clone_from(&p.position);
            }
        }
        swarm.evaluations += swarm.particles.len();
        swarm.iterations += 1;
        swarm.update_best();
    }

    /// Makes `swarm` current for a changed objective (new samples) and a possibly changed box:
    /// clamps every position and personal best into the box, re-evaluates both, replaces the
    /// [`ParticleSwarm::with_reinjected`] worst particles by random ones, recomputes the global
    /// best and resets the iteration count.
    pub fn refresh<F: CostFunction, R: Rng + ?Sized>(
        &self,
        cost: &F,
        swarm: &mut Swarm,
        rng: &mut R,
    ) {
        for p in &mut swarm.particles {
            for (d, (l, u)) in self.lower.iter().zip(&self.upper).enumerate() {
                if let Some(x) = p.position.get_mut(d) {
                    *x = x.clamp(*l, *u);
                }
                if let Some(x) = p.best_position.get_mut(d) {
                    *x = x.clamp(*l, *u);
                }
            }
            p.cost = cost.cost(&p.position);
            p.best_cost = cost.cost(&p.best_position);
            if p.cost < p.best_cost {
                p.best_cost = p.cost;
                p.best_position.clone_from(&p.position);
            }
        }
        swarm.evaluations += 2 * swarm.particles.len();
        swarm.iterations = 0;
        swarm.best_cost = f64::INFINITY;
        swarm.best_position.clear();
        self.reinject(cost, swarm, rng, self.reinjected);
    }

    /// Replaces the `count` particles with the worst personal bests by new ones (stratified in
    /// the box) and recomputes the global best: diversity against a swarm that has collapsed
    /// into a local minimum. The iteration count is kept.
    pub fn reinject<F: CostFunction, R: Rng + ?Sized>(
        &self,
        cost: &F,
        swarm: &mut Swarm,
        rng: &mut R,
        count: usize,
    ) {
        swarm
            .particles
            .sort_by(|a, b| a.best_cost.total_cmp(&b.best_cost));
        let keep = swarm.particles.len().saturating_sub(count);
        let fresh = self.stratified_particles(cost, rng, swarm.particles.len() - keep);
        for (p, new) in swarm.particles.iter_mut().skip(keep).zip(fresh) {
            *p = new;
        }
        swarm.evaluations += (swarm.particles.len() - keep) * self.candidates;
        swarm.update_best();
    }
}

impl Swarm {
    fn update_best(&mut self) {
        for p in &self.particles {
            if p.best_cost < self.best_cost || self.best_position.is_empty() {
                self.best_cost = p.best_cost;
                self.best_position.clone_from(&p.best_position);
            }
        }
    }

    /// The personal bests, best first, skipping any closer than `min_distance` (max-norm) to
    /// one already taken: distinct starts for local refinement.
    pub fn distinct_bests(&self, count: usize, min_distance: f64) -> Vec<Vec<f64>> {
        let mut order: Vec<&Particle> = self.particles.iter().collect();
        order.sort_by(|a, b| a.best_cost.total_cmp(&b.best_cost));
        let mut taken: Vec<Vec<f64>> = Vec::with_capacity(count);
        for p in order {
            if taken.len() >= count {
                break;
            }
            let far = taken.iter().all(|t| {
                t.iter()
                    .zip(&p.best_position)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max)
                    >= min_distance
            });
            if far {
                taken.push(p.best_position.clone());
            }
        }
        taken
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn rosenbrock(x: &[f64]) -> f64 {
        (1.0 - x[0]).powi(2) + 100.0 * (x[1] - x[0] * x[0]).powi(2)
    }

    #[test]
    fn finds_a_minimum_and_is_deterministic() -> Result<(), EstimateError> {
        let pso = ParticleSwarm::new(vec![-2.0, -1.0], vec![2.0, 3.0], 20)?;
        let run = |seed| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut swarm = pso.init(&rosenbrock, &mut rng);
            for _ in 0..200 {
                pso.iterate(&rosenbrock, &mut swarm, &mut rng);
            }
            swarm
        };
        let (a, b) = (run(3), run(3));
        assert_eq!(a, b);
        assert!(a.best_cost < 1e-3, "best cost {}", a.best_cost);
        Ok(())
    }

    #[test]
    fn refresh_leaves_nothing_stale() -> Result<(), EstimateError> {
        let pso = ParticleSwarm::new(vec![-2.0], vec![2.0], 10)?.with_reinjected(3)?;
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let old = |x: &[f64]| (x[0] - 1.0).powi(2);
        let new = |x: &[f64]| (x[0] + 1.0).powi(2) + 0.5;
        let mut swarm = pso.init(&old, &mut rng);
        for _ in 0..30 {
            pso.iterate(&old, &mut swarm, &mut rng);
        }
        let narrowed = pso.with_bounds(vec![-1.5], vec![0.5])?;
        narrowed.refresh(&new, &mut swarm, &mut rng);
        for p in &swarm.particles {
            assert!((p.cost - new(&p.position)).abs() < 1e-15);
            assert!((p.best_cost - new(&p.best_position)).abs() < 1e-15);
            assert!((-1.5..=0.5).contains(&p.position[0]));
        }
        assert!(swarm.best_cost >= 0.5);
        for _ in 0..40 {
            narrowed.iterate(&new, &mut swarm, &mut rng);
        }
        assert!((swarm.best_position[0] + 1.0).abs() < 1e-3);
        Ok(())
    }

    #[test]
    fn settings_are_validated() {
        assert!(ParticleSwarm::new(vec![0.0], vec![0.0], 20).is_err());
        assert!(ParticleSwarm::new(vec![0.0], vec![1.0, 2.0], 20).is_err());
        assert!(ParticleSwarm::new(vec![0.0], vec![1.0], 1).is_err());
        let ok = ParticleSwarm::new(vec![0.0], vec![1.0], 4);
        assert!(ok.clone().and_then(|p| p.with_inertia_factor(1.0)).is_err());
        assert!(
            ok.clone()
                .and_then(|p| p.with_social_factor(f64::NAN))
                .is_err()
        );
        assert!(ok.and_then(|p| p.with_reinjected(4)).is_err());
    }
}
