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

use nalgebra::Vector6;

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
    let min_of = |w: &[Sample]| w.iter().map(|s| s.clearance).fold(f64::INFINITY, f64::min);
    let before = min_of(waypoints);
    let mut out = waypoints.to_vec();
    let mut moved = 0;
    for i in 1..out.len().saturating_sub(1) {
        if polish_one(checker, &mut out, i, params) {
            moved += 1;
        }
    }
    let after = min_of(&out);
    Ok(Polished {
        waypoints: out,
        moved,
        min_clearance: (before, after),
    })
}

/// The ascent of waypoint `i` (interior); whether it moved.
fn polish_one(checker: &Checker, path: &mut [Sample], i: usize, params: &PolishParams) -> bool {
    let wire = *checker.rod().wire();
    let origin = ftwire_rod::to_normalised(&wire, &path[i].config.a);
    let mut moved = false;
    for _ in 0..params.iterations {
        let here = &path[i];
        if here.clearance >= params.target {
            break;
        }
        let x = ftwire_rod::to_normalised(&wire, &here.config.a);
        let clearance_at = |x: &Vector6<f64>| {
            let config = crate::Config {
                a: ftwire_rod::from_normalised(&wire, x),
                ..here.config
            };
            checker.clearance(&config).ok()
        };
        let mut gradient = Vector6::zeros();
        let h = params.difference;
        let mut ok = true;
        for k in 0..6 {
            let mut up = x;
            let mut down = x;
            up[k] += h;
            down[k] -= h;
            match (clearance_at(&up), clearance_at(&down)) {
                (Some(u), Some(d)) => gradient[k] = (u - d) / (2.0 * h),
                _ => ok = false,
            }
        }
        let slope = gradient.norm();
        if !ok || slope.is_nan() || slope <= 1e-9 {
            break;
        }
        let direction = gradient / slope;
        let mut length = ((params.target - here.clearance) / slope).min(params.max_step);
        let mut accepted = None;
        for _ in 0..=params.halvings {
            let mut next = x + length * direction;
            let shift = next - origin;
            if shift.norm() > params.max_shift {
                next = origin + shift * (params.max_shift / shift.norm());
            }
            let config = crate::Config {
                a: ftwire_rod::from_normalised(&wire, &next),
                ..here.config
            };
            if let Some(sample) = valid_between(checker, path, i, &config)
                && sample.clearance > here.clearance
            {
                accepted = Some(sample);
                break;
            }
            length *= 0.5;
        }
        match accepted {
            Some(sample) => {
                path[i] = sample;
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
    config: &crate::Config,
) -> Option<Sample> {
    let edge = checker.edge(&path[i - 1], config).ok()?;
    let sample = edge.end;
    checker.edge(&sample, &path[i + 1].config).ok()?;
    Some(sample)
}
