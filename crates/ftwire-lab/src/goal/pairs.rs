//! The start–goal pairs of the goal experiment: seeded draws of `A_free`, A-connected, stable
//! under the steering model with a margin; and the obstacle of a pair's contact run.

use ftwire_control::open_loop::{a_connected, line_in_a};
use ftwire_core::Pose;
use ftwire_estimate::WireModel;
use ftwire_rod::sampling::Sampler;
use ftwire_rod::{Rod, from_normalised};
use ftwire_sim::BoxObstacle;
use nalgebra::{Vector3, Vector6};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use super::trial::Context;
use super::trial::Pair;
use crate::error::{LabError, from_rod, from_sim};

/// How the pairs were drawn.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct PairDraws {
    /// Draws in all.
    pub drawn: usize,
    /// Draws whose segment left `A_free`.
    pub not_connected: usize,
    /// Draws whose start or goal is unstable under the steering model.
    pub unstable_for_model: usize,
    /// Segments that come within the stability margin of the boundary.
    pub near_boundary: usize,
}

/// Half-width of the normalised box the pairs are drawn from. In the sampler's default box
/// most draws sit near the stability boundary, where the true wire and the model disagree
/// about stability and closed-loop runs snapped repeatedly in the simulator.
const PAIR_BOX: f64 = 5.0;
/// Distance \[normalised\] every point of a pair's segment keeps from the model's stability
/// boundary along each axis.
const STABILITY_MARGIN: f64 = 2.0;
/// Points of the segment checked for A-connectivity (`checks + 1`).
const CONNECT_CHECKS: usize = 20;
/// Draws per requested pair before giving up.
const MAX_DRAWS_PER_PAIR: usize = 200;
/// Half edge of the obstacle box \[m\].
const BOX_HALF: f64 = 0.01;
/// Least distance \[m\] from the start shape to the box centre.
const BOX_CLEARANCE: f64 = 0.04;

/// Draws `count` pairs (see the module docs), counting the draws in `draws`.
pub(super) fn draw_pairs(
    ctx: &Context<'_>,
    rod: &Rod,
    count: usize,
    rng: &mut ChaCha8Rng,
    draws: &mut PairDraws,
) -> Result<Vec<Pair>, LabError> {
    let sampler = Sampler {
        half_width: PAIR_BOX,
        ..Sampler::default()
    };
    let mut pairs = Vec::with_capacity(count);
    while pairs.len() < count {
        if draws.drawn >= MAX_DRAWS_PER_PAIR * count.max(1) {
            return Err(LabError::no_answer(format!(
                "found only {} A-connected pairs in {} draws",
                pairs.len(),
                draws.drawn
            )));
        }
        draws.drawn += 1;
        let a_s = sampler
            .sample_free(rod, rng)
            .map_err(|e| from_rod(e, "sampling A_free"))?;
        let a_g = sampler
            .sample_free(rod, rng)
            .map_err(|e| from_rod(e, "sampling A_free"))?;
        if !a_connected(rod, &a_s, &a_g, CONNECT_CHECKS)
            .map_err(|e| LabError::no_answer(e.to_string()))?
        {
            draws.not_connected += 1;
            continue;
        }
        if !ctx.model.is_stable(&a_g).unwrap_or(false)
            || !ctx.model.is_stable(&a_s).unwrap_or(false)
        {
            draws.unstable_for_model += 1;
            continue;
        }
        if !stable_with_margin(ctx, &a_s, &a_g, STABILITY_MARGIN) {
            draws.near_boundary += 1;
            continue;
        }
        pairs.push(Pair {
            a_s,
            a_g,
            goal_shape: ctx.shape(&a_g)?,
            start_shape: ctx.shape(&a_s)?,
        });
    }
    Ok(pairs)
}

/// Whether every point of the segment's check grid stays in `A_stable` of the model when moved
/// by `margin` (normalised) along each axis, both ways.
fn stable_with_margin(
    ctx: &Context<'_>,
    a_s: &Vector6<f64>,
    a_g: &Vector6<f64>,
    margin: f64,
) -> bool {
    line_in_a(a_s, a_g, CONNECT_CHECKS).iter().all(|a| {
        (0..12).all(|k| {
            let mut step = Vector6::zeros();
            step[k / 2] = if k % 2 == 0 { margin } else { -margin };
            let moved = a + from_normalised(&ctx.params, &step);
            ctx.model.is_stable(&moved).unwrap_or(false)
        })
    })
}

/// The box of the collision sub-run for `pair`: 20 mm at a node of `Φ(a_g)` (middle first)
/// far enough from the start shape; `None` when no node qualifies.
pub(super) fn obstacle_for(pair: &Pair) -> Result<Option<BoxObstacle>, LabError> {
    let n = pair.goal_shape.len();
    for fraction in [0.5, 0.35, 0.65] {
        let centre = pair.goal_shape[((n - 1) as f64 * fraction).round() as usize];
        let clearance = pair
            .start_shape
            .iter()
            .map(|p| (p - centre).norm())
            .fold(f64::INFINITY, f64::min);
        if clearance >= BOX_CLEARANCE {
            let pose = Pose::translation(centre.x, centre.y, centre.z);
            return BoxObstacle::new(pose, Vector3::repeat(BOX_HALF))
                .map(Some)
                .map_err(|e| from_sim(e, "the obstacle"));
        }
    }
    Ok(None)
}
