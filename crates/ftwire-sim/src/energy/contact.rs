//! Smooth penalty contact between the wire's edges and the obstacles.
//!
//! Each edge is sampled at `S` points `p = (1 − s)·x_a + s·x_b`. A sample whose signed distance
//! `d` to an obstacle is less than the wire radius `r` penetrates by `δ = r − d` and stores the
//! energy `w·k·δ³/3`, with `k` the contact stiffness \[N/m³\] and `w` the sample's share of the
//! edge's rest length (trapezoidal rule). The energy is C² in `δ`, so Newton's method sees a
//! continuous Hessian. The sample spacing is at most `min(r, 2r + t)`, with `t` the thinnest
//! obstacle's thickness, so no part of an edge can straddle a thin obstacle unseen: an edge
//! crossing a plate of thickness `t` always has a sample within `r + t/2` of its mid-plane.

use nalgebra::{Matrix3, Point3, Vector3};

use crate::obstacle::Obstacle;
use crate::state::RodState;
use crate::world::World;

/// The penalty of one sample: energy \[J\], gradient \[N\] and Hessian \[N/m\] with respect to the
/// sample point, or `None` if it does not touch the obstacle.
pub(crate) fn sample_penalty(
    obstacle: &Obstacle,
    p: &Point3<f64>,
    radius: f64,
    stiffness: f64,
    weight: f64,
    with_hessian: bool,
) -> Option<(f64, Vector3<f64>, Matrix3<f64>)> {
    let (d, n, dn) = obstacle.distance_derivatives(p);
    let delta = radius - d;
    if delta <= 0.0 {
        return None;
    }
    let k = stiffness * weight;
    let energy = k * delta.powi(3) / 3.0;
    let grad = n * (-k * delta * delta);
    let hess = if with_hessian {
        n * n.transpose() * (2.0 * k * delta) - dn * (k * delta * delta)
    } else {
        Matrix3::zeros()
    };
    Some((energy, grad, hess))
}

/// Sample positions `s` and weights \[m\] on an edge, over the part `[lo, hi]` of it that is
/// inside the wire.
pub(crate) fn samples(
    lo: f64,
    hi: f64,
    count: usize,
    rest: f64,
) -> impl Iterator<Item = (f64, f64)> {
    let count = count.max(2);
    let step = (hi - lo) / (count - 1) as f64;
    (0..count).map(move |k| {
        let w = if k == 0 || k == count - 1 { 0.5 } else { 1.0 };
        (lo + step * k as f64, w * step * rest)
    })
}

/// The largest node displacement \[m\] that cannot carry a contact sample across the
/// mid-plane of the thin dimension of a box: half the smallest `d + t/2` over the samples near a
/// box (`d` the sample's signed distance, `t` the box's thickness), capped by
/// [`World::contact_step_limit`]. `None` without boxes.
pub(crate) fn step_limit(world: &World, state: &RodState) -> Option<f64> {
    let mut limit = world.contact_step_limit()?;
    let radius = world.rod().params().radius;
    let n = state.edges();
    let count = world.samples_per_edge();
    for obstacle in world.obstacles() {
        let Obstacle::Box(b) = obstacle else {
            continue;
        };
        let half = 0.5 * b.thickness();
        for j in 0..n {
            let (xa, xb) = (state.nodes[j], state.nodes[j + 1]);
            let mid = Point3::from((xa + xb) * 0.5);
            let reach = 0.5 * (xb - xa).norm() + radius + 2.0 * limit;
            if b.signed_distance(&mid) > reach {
                continue;
            }
            for (s, _) in samples(0.0, 1.0, count, 1.0) {
                let d = b.signed_distance(&Point3::from(xa * (1.0 - s) + xb * s));
                let room = d + half;
                if room > 0.0 {
                    limit = limit.min(0.5 * room);
                }
            }
        }
    }
    Some(limit)
}
