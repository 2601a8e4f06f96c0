//! Clearance polish: the interior waypoints of a path that pass close to an obstacle are moved,
//! each by a short gradient ascent of the wire's clearance in normalised `a`, while they and
//! the edges to their neighbours stay in `Z_free`.
//!
//! Why: a path tracked under gripper noise lands the wire about its waypoints, scattered by
//! every move; the tightest waypoint is where the scatter's tail touches a box (`ftwire
//! experiment passage`: the touches of a run cluster on the leg to one waypoint, the path's
//! closest). RRT*'s cost only trades length against clearance over the whole path, which
//! changes the path everywhere; the polish leaves the path's route alone and widens only its
//! tight spots.
//!
//! Each ascent step takes the central-difference gradient of the clearance (one shape solve per
//! difference, no stability tests, no IK), steps along it toward
//! [`PolishParams::target`], at most [`PolishParams::max_step`], and halves the step until
//! both edges to the neighbours are valid ([`Checker::edge`]: the moved waypoint's sample is
//! the end of the edge from the previous one, its IK following along it) and the clearance
//! grew. The
//! total move of a waypoint is capped by [`PolishParams::max_shift`], so the polished path
//! follows the planned one.
//!
//! With [`PolishParams::landing`], what is ascended is the waypoint's *landing clearance*
//! ([`landing_clearance`]): the smallest clearance over where a move toward it lands when the
//! gripper lands off by a probe on one axis. Waypoints differ in how far one noisy move
//! scatters the wire beside a box, so the waypoints with the closest planned wire need not be
//! those whose landings come closest (`ftwire experiment passage`, seed 8). Each of its
//! evaluations costs a Jacobian and 13 shape solves instead of one.

use nalgebra::Vector6;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use crate::PlanError;
use crate::validity::{Checker, Sample};

/// Settings of [`polish_clearance`] (public fields + `Default`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolishParams {
    /// Clearance \[m\] above which a waypoint is left alone, and which a step aims at
    /// (default `0.025`).
    pub target: f64,
    /// Largest single step in normalised `a` (default `0.5`).
    pub max_step: f64,
    /// Largest total move of one waypoint from where it was planned, in normalised `a`
    /// (default `1.5`).
    pub max_shift: f64,
    /// Half-width of the central differences in normalised `a` (default `0.02`).
    pub difference: f64,
    /// Most ascent steps per waypoint (default `8`).
    pub iterations: usize,
    /// Halvings of a step that was refused (default `4`).
    pub halvings: usize,
    /// What is ascended (default `None`: the wire's clearance at the waypoint). With a
    /// [`Landing`], the smallest clearance over where a noisy move toward the waypoint lands
    /// ([`landing_clearance`]), and `target` applies to that.
    pub landing: Option<Landing>,
}

impl Default for PolishParams {
    fn default() -> Self {
        Self {
            target: 0.025,
            max_step: 0.5,
            max_shift: 1.5,
            difference: 0.02,
            iterations: 8,
            halvings: 4,
            landing: None,
        }
    }
}

/// A polished path and what the polish did.
#[derive(Debug, Clone, PartialEq)]
pub struct Polished {
    /// The waypoints, the same count as given; the ends are never moved.
    pub waypoints: Vec<Sample>,
    /// How many interior waypoints moved.
    pub moved: usize,
    /// The smallest waypoint clearance \[m\] before and after.
    pub min_clearance: (f64, f64),
    /// The smallest of what was ascended \[m\] over the interior waypoints, before and
    /// after: their clearance, or their landing clearance with [`PolishParams::landing`]
    /// (infinite for a path without interior waypoints).
    pub min_score: (f64, f64),
}

/// Moves the interior waypoints of `waypoints` (consecutive samples of a valid path, e.g.
/// [`crate::Path::resample`]'s) whose clearance is below `params.target` away from the
/// obstacles, as the module docs describe. The waypoints' bases stay; only `a` moves.
///
/// # Errors
/// [`PlanError::InvalidParameter`] for a setting that is not finite and positive
/// (`iterations` and `halvings` may be 0).
pub fn polish_clearance(
    checker: &Checker,
    waypoints: &[Sample],
    params: &PolishParams,
) -> Result<Polished, PlanError> {
    PlanError::check_positive(&[
        ("target", params.target),
        ("max_step", params.max_step),
        ("max_shift", params.max_shift),
        ("difference", params.difference),
    ])?;
    if let Some(landing) = &params.landing {
        landing.check()?;
    }
    let min_of = |w: &[Sample]| w.iter().map(|s| s.clearance).fold(f64::INFINITY, f64::min);
    let min_score = |w: &[Sample]| {
        let interior = w.get(1..w.len().saturating_sub(1)).unwrap_or(&[]);
        interior
            .iter()
            .map(|s| score(checker, &s.config, params).unwrap_or(f64::NEG_INFINITY))
            .fold(f64::INFINITY, f64::min)
    };
    let before = min_of(waypoints);
    let score_before = min_score(waypoints);
    let mut out = waypoints.to_vec();
    let mut moved = 0;
    for i in 1..out.len().saturating_sub(1) {
        if polish_one(checker, &mut out, i, params) {
            moved += 1;
        }
    }
    let after = min_of(&out);
    let score_after = min_score(&out);
    Ok(Polished {
        waypoints: out,
        moved,
        min_clearance: (before, after),
        min_score: (score_before, score_after),
    })
}

/// What the polish ascends at `config`: its clearance, or its landing clearance with
/// [`PolishParams::landing`]; `None` where the model refuses it.
fn score(checker: &Checker, config: &crate::ZPoint, params: &PolishParams) -> Option<f64> {
    match &params.landing {
        None => checker.clearance(config).ok(),
        Some(landing) => landing_clearance(checker, config, landing).ok(),
    }
}

/// The ascent of waypoint `i` (interior); whether it moved.
fn polish_one(checker: &Checker, path: &mut [Sample], i: usize, params: &PolishParams) -> bool {
    let wire = *checker.rod().wire();
    let origin = ftwire_rod::to_normalised(&wire, &path[i].config.a);
    let mut moved = false;
    let Some(mut current) = score(checker, &path[i].config, params) else {
        return false;
    };
    for _ in 0..params.iterations {
        if current >= params.target {
            break;
        }
        let here = &path[i];
        let x = ftwire_rod::to_normalised(&wire, &here.config.a);
        let score_at = |x: &Vector6<f64>| {
            let config = crate::ZPoint {
                a: ftwire_rod::from_normalised(&wire, x),
                ..here.config
            };
            score(checker, &config, params)
        };
        let mut gradient = Vector6::zeros();
        let h = params.difference;
        let mut ok = true;
        for k in 0..6 {
            let mut up = x;
            let mut down = x;
            up[k] += h;
            down[k] -= h;
            match (score_at(&up), score_at(&down)) {
                (Some(u), Some(d)) => gradient[k] = (u - d) / (2.0 * h),
                _ => ok = false,
            }
        }
        let slope = gradient.norm();
        if !ok || slope.is_nan() || slope <= 1e-9 {
            break;
        }
        let direction = gradient / slope;
        let mut length = ((params.target - current) / slope).min(params.max_step);
        let mut accepted = None;
        for _ in 0..=params.halvings {
            let mut next = x + length * direction;
            let shift = next - origin;
            if shift.norm() > params.max_shift {
                next = origin + shift * (params.max_shift / shift.norm());
            }
            let config = crate::ZPoint {
                a: ftwire_rod::from_normalised(&wire, &next),
                ..here.config
            };
            if let Some(sample) = valid_between(checker, path, i, &config)
                && let Some(value) = score(checker, &sample.config, params)
                && value > current
            {
                accepted = Some((sample, value));
                break;
            }
            length *= 0.5;
        }
        match accepted {
            Some((sample, value)) => {
                path[i] = sample;
                current = value;
                moved = true;
            }
            None => break,
        }
    }
    moved
}

/// `config` as waypoint `i`: its sample when it and the edges from `path[i − 1]` and to
/// `path[i + 1]` are valid.
fn valid_between(
    checker: &Checker,
    path: &[Sample],
    i: usize,
    config: &crate::ZPoint,
) -> Option<Sample> {
    let edge = checker.edge(&path[i - 1], config).ok()?;
    let sample = edge.end;
    checker.edge(&sample, &path[i + 1].config).ok()?;
    Some(sample)
}

/// One gripper move's landing error, as the probes of [`landing_clearance`]: a body twist
/// at the second gripper's clamp of `rotation` about, or `position` along, one of its axes,
/// either way (12 probes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Landing {
    /// Translation of a probe \[m\].
    pub position: f64,
    /// Rotation of a probe \[rad\].
    pub rotation: f64,
}

/// The wire's smallest clearance \[m\] over where a move toward `config` lands when the
/// second gripper lands off by one of `landing`'s probes, and where it lands as sent. Each
/// probe's `a` is `a + J⁻¹ ξ` (`J` the checker's model's at `a`: the body twist `ξ` of the
/// probe to first order), its shape solved by the checker's model. A probe the model refuses,
/// and every probe where `J` is singular (a fold), counts as clearance 0.
///
/// A landing that pierces a box counts as `−radius` (a centreline inside it is at distance
/// 0), whatever its depth: [`polish_clearance`] raises landings beside a box, not out of one.
///
/// Probes on one axis at a time, not a clearance's gradient: in a gap between two boxes a
/// landing either way along an axis comes closer to one of them, and the two central
/// differences cancel.
///
/// # Errors
/// [`PlanError::InvalidParameter`] for a probe size that is not finite and non-negative;
/// [`PlanError::Rod`] when the model refuses `config.a`.
pub fn landing_clearance(
    checker: &Checker,
    config: &crate::ZPoint,
    landing: &Landing,
) -> Result<f64, PlanError> {
    landing.check()?;
    let clearance_at = |a: &Vector6<f64>| clearance_at(checker, config, a);
    let mut least = clearance_at(&config.a)?;
    let lu = checker.rod().jacobian(&config.a)?.jacobian.lu();
    for axis in 0..6 {
        let size = if axis < 3 {
            landing.rotation
        } else {
            landing.position
        };
        for sign in [1.0, -1.0] {
            let mut xi = Vector6::zeros();
            xi[axis] = sign * size;
            let probe = lu
                .solve(&xi)
                .and_then(|da| clearance_at(&(config.a + da)).ok());
            least = least.min(probe.unwrap_or(0.0));
        }
    }
    Ok(least)
}

/// The wire's clearance \[m\] (`Checker::wire_clearance`) at `a`, with `config`'s base.
fn clearance_at(
    checker: &Checker,
    config: &crate::ZPoint,
    a: &Vector6<f64>,
) -> Result<f64, ftwire_rod::RodError> {
    let shape = checker.rod().shape(a, checker.params().nodes)?;
    let centreline = crate::validity::world_centreline(config, &shape.positions);
    Ok(checker.wire_clearance(&centreline).0)
}

/// The scatter of a noisy move's landing for [`touch_rate`]: the second gripper's body twist at
/// its clamp, with independent normal components of `position_std` per axis \[m\] and
/// `orientation_std` per rotation-vector component \[rad\] (the paper's noise), and
/// `samples` landings drawn from a ChaCha8 stream seeded by `seed`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scatter {
    /// σ of the landing's translation per axis \[m\].
    pub position_std: f64,
    /// σ of the landing's rotation per rotation-vector component \[rad\].
    pub orientation_std: f64,
    /// Landings drawn (at least 1).
    pub samples: usize,
    /// Seed of the landings' random stream: the same seed draws the same landings, so that
    /// the rates of two configurations are compared on the same landings.
    pub seed: u64,
}

/// The fraction of a noisy move's landings toward `config` at which the wire touches an
/// obstacle (its clearance below 0): `scatter.samples` body twists `ξ` drawn from `scatter`,
/// each landing's `a` taken to first order as `a + J⁻¹ ξ` (as [`landing_clearance`]'s probes)
/// and its shape solved by the checker's model. A landing the model refuses counts as a
/// touch, and so does every landing where `J` is singular (a fold).
///
/// Why a rate, not the closest landing: a run of the passage touches where many of its rests
/// land beside a box, and a path with one tight waypoint passed once can touch less than one
/// that keeps the wire a little closer over many. The sum of the rates over a path's waypoints
/// is the expected number of touching landings when each is reached by one move.
///
/// # Errors
/// [`PlanError::InvalidParameter`] for a σ that is not finite and non-negative, or no
/// samples; [`PlanError::Rod`] when the model refuses `config.a`.
pub fn touch_rate(
    checker: &Checker,
    config: &crate::ZPoint,
    scatter: &Scatter,
) -> Result<f64, PlanError> {
    scatter.check()?;
    // `J` refuses a configuration the model cannot solve.
    let Some(inverse) = checker.rod().jacobian(&config.a)?.jacobian.try_inverse() else {
        return Ok(1.0);
    };
    let mut rng = ChaCha8Rng::seed_from_u64(scatter.seed);
    let mut touches = 0usize;
    for _ in 0..scatter.samples {
        let xi = Vector6::from_fn(|i, _| {
            let std = if i < 3 {
                scatter.orientation_std
            } else {
                scatter.position_std
            };
            std * rng.sample::<f64, _>(StandardNormal)
        });
        let touched =
            clearance_at(checker, config, &(config.a + inverse * xi)).map_or(true, |c| c < 0.0);
        touches += usize::from(touched);
    }
    Ok(touches as f64 / scatter.samples as f64)
}

impl Scatter {
    /// Both σ finite and non-negative, and at least one sample.
    ///
    /// # Errors
    /// [`PlanError::InvalidParameter`] naming the first that is not.
    pub fn check(&self) -> Result<(), PlanError> {
        for (name, value) in [
            ("scatter.position_std", self.position_std),
            ("scatter.orientation_std", self.orientation_std),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(PlanError::InvalidParameter {
                    name,
                    value,
                    allowed: "a finite value >= 0",
                });
            }
        }
        if self.samples == 0 {
            return Err(PlanError::InvalidParameter {
                name: "scatter.samples",
                value: 0.0,
                allowed: "at least 1",
            });
        }
        Ok(())
    }
}

impl Landing {
    /// Both probe sizes finite and non-negative.
    ///
    /// # Errors
    /// [`PlanError::InvalidParameter`] naming the first that is not.
    pub fn check(&self) -> Result<(), PlanError> {
        for (name, value) in [
            ("landing.position", self.position),
            ("landing.rotation", self.rotation),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(PlanError::InvalidParameter {
                    name,
                    value,
                    allowed: "a finite value >= 0",
                });
            }
        }
        Ok(())
    }
}
