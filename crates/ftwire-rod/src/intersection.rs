//! Self-intersection of the wire (paper §II-A, the definition of `A_free`): two *non-adjacent*
//! segments of the centreline polyline closer than the wire's diameter `2·radius`.
//!
//! # Which segments are adjacent
//!
//! Adjacency is defined in arc length, not in node indices, so that fine node spacing does not
//! turn neighbours into contacts: segments `i < j` of a polyline with uniform node spacing `Δ`
//! are compared only if the arc length strictly between them, `(j − i − 1)·Δ`, is at least
//! `π·radius`. Why `π·radius`: a tube of radius `r` cannot bend tighter than radius `r`, and by
//! Schur's comparison theorem two points of a curve with curvature `≤ 1/r` at arc-length
//! separation `s ≤ π r` are at least `2 r sin(s / 2r)` apart, which reaches `2 r` exactly at
//! `s = π r`. So pairs closer in arc length than `π r` are explained by the bending of the wire
//! itself, and pairs farther apart and closer than `2 r` in space are true self-contact.
//!
//! # Speed
//!
//! A two-level bounding-ball filter instead of a BVH: the segments are grouped in chunks of 8
//! consecutive ones, each inside a ball around the mean of its nodes; only pairs of chunks
//! whose balls are closer than `2r` are searched, and within them a pair of segments is
//! measured only if the balls around their midpoints (radius half the segment) are closer
//! than `2r`. Both tests compare squared distances (no square roots) and are conservative, so
//! the result is that of the plain pair walk (test `skip_agrees_with_brute_force`): the first
//! contact in the order of `i`, then `j`. A pair is measured by [`segment_distance`], the
//! workspace's one segment–segment distance (`ftwire_core::geometry`, re-exported here).

use nalgebra::Vector3;

pub use ftwire_core::geometry::segment_distance;

/// A self-contact found on the centreline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Indices of the two segments (segment `i` joins nodes `i` and `i + 1`).
    pub segments: (usize, usize),
    /// Distance between their centrelines \[m\] (less than the diameter).
    pub distance: f64,
}

/// The first self-contact of a centreline polyline with uniform arc-length node spacing
/// `spacing` \[m\] and wire radius `radius` \[m\], or `None` (see the module docs for which
/// segments count as non-adjacent).
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// // A hairpin: out along x and back 1 mm above itself, with a 2 mm thick wire.
/// let nodes: Vec<Vector3<f64>> = (0..=10).map(|i| Vector3::new(i as f64 * 0.01, 0.0, 0.0))
///     .chain((0..=10).rev().map(|i| Vector3::new(i as f64 * 0.01, 0.0, 0.001)))
///     .collect();
/// let contact = ftwire_rod::self_contact(&nodes, 0.01, 0.001);
/// assert!(contact.is_some());
/// assert!(ftwire_rod::self_contact(&nodes[..11], 0.01, 0.001).is_none());
/// ```
pub fn self_contact(positions: &[Vector3<f64>], spacing: f64, radius: f64) -> Option<Contact> {
    let segments = positions.len().checked_sub(1)?;
    if segments < 2 || spacing.is_nan() || spacing <= 0.0 {
        return None;
    }
    let diameter = 2.0 * radius;
    // Smallest index offset j − i with (j − i − 1)·Δ ≥ π r, and at least 2.
    let ratio = std::f64::consts::PI * radius / spacing;
    let min_offset = if ratio.is_finite() && ratio < segments as f64 {
        (1 + ratio.ceil() as usize).max(2)
    } else {
        return None;
    };
    let mid: Vec<Vector3<f64>> = positions.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
    let half: Vec<f64> = positions
        .windows(2)
        .map(|w| 0.5 * (w[1] - w[0]).norm())
        .collect();
    // Bounding balls of chunks of CHUNK consecutive segments (centre: mean of the chunk's
    // nodes; radius: farthest node, so the chunk's segments lie inside).
    let chunks = segments.div_ceil(CHUNK);
    let balls: Vec<(Vector3<f64>, f64)> = (0..chunks)
        .map(|c| {
            let nodes = &positions[c * CHUNK..=((c + 1) * CHUNK).min(segments)];
            let centre = nodes.iter().sum::<Vector3<f64>>() / nodes.len() as f64;
            let r2 = nodes
                .iter()
                .map(|p| (p - centre).norm_squared())
                .fold(0.0, f64::max);
            (centre, r2.sqrt())
        })
        .collect();
    // near[a * chunks + b]: chunks a and b may hold segments closer than the diameter.
    let mut near = vec![false; chunks * chunks];
    for a in 0..chunks {
        for b in a..chunks {
            let (ca, ra) = &balls[a];
            let (cb, rb) = &balls[b];
            let limit = diameter + ra + rb;
            // Not "far" rather than "near", so that NaN counts as near (and is then measured).
            let far = (ca - cb).norm_squared() >= limit * limit;
            near[a * chunks + b] = !far;
            near[b * chunks + a] = !far;
        }
    }
    for i in 0..segments {
        let first = i + min_offset;
        if first >= segments {
            break;
        }
        let row = &near[(i / CHUNK) * chunks..(i / CHUNK + 1) * chunks];
        for (b, _) in row
            .iter()
            .enumerate()
            .skip(first / CHUNK)
            .filter(|(_, n)| **n)
        {
            for j in first.max(b * CHUNK)..((b + 1) * CHUNK).min(segments) {
                // Segment i lies within half[i] of mid[i]: no contact if the balls are apart.
                let limit = diameter + half[i] + half[j];
                if (mid[i] - mid[j]).norm_squared() >= limit * limit {
                    continue;
                }
                let distance = segment_distance(
                    &positions[i],
                    &positions[i + 1],
                    &positions[j],
                    &positions[j + 1],
                );
                if distance < diameter {
                    return Some(Contact {
                        segments: (i, j),
                        distance,
                    });
                }
            }
        }
    }
    None
}

/// Segments per chunk of the bounding-ball filter of [`self_contact`].
const CHUNK: usize = 8;

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn vec3() -> impl Strategy<Value = Vector3<f64>> {
        prop::array::uniform3(-1.0..1.0f64).prop_map(Vector3::from)
    }

    proptest! {
        /// The property test of `ftwire_core::geometry::segment_distance` (core has no
        /// proptest): never above the sampled minimum, and within the sampling error of it.
        #[test]
        fn segment_distance_is_the_sampled_minimum(p1 in vec3(), q1 in vec3(), p2 in vec3(), q2 in vec3()) {
            let d = segment_distance(&p1, &q1, &p2, &q2);
            let mut best = f64::INFINITY;
            let n = 200;
            for a in 0..=n {
                let x = p1 + (q1 - p1) * (a as f64 / n as f64);
                for b in 0..=n {
                    let y = p2 + (q2 - p2) * (b as f64 / n as f64);
                    best = best.min((x - y).norm());
                }
            }
            prop_assert!(d <= best + 1e-12);
            prop_assert!(d >= best - 0.02);
        }

        /// The skip never hides a contact: agree with the brute-force pair walk on random
        /// wiggly polylines.
        #[test]
        fn skip_agrees_with_brute_force(
            seed in prop::collection::vec(-1.0..1.0f64, 60..300),
            radius in 0.001..0.05f64,
            bend in 0.05..1.5f64,
        ) {
            // From gently curved (parts far apart) to tightly wound.
            let spacing = 0.02;
            let mut p = Vector3::zeros();
            let mut dir = Vector3::new(1.0, 0.0, 0.0);
            let mut nodes = vec![p];
            for w in seed.chunks(3) {
                let at = |k: usize| w.get(k).copied().unwrap_or(0.0);
                let turn = Vector3::new(at(0), at(1), at(2)) * bend;
                dir = (dir + turn).normalize();
                p += dir * spacing;
                nodes.push(p);
            }
            let fast = self_contact(&nodes, spacing, radius).map(|c| c.segments);
            let min_offset = (1 + (std::f64::consts::PI * radius / spacing).ceil() as usize).max(2);
            let mut brute = None;
            'walk: for i in 0..nodes.len() - 1 {
                for j in i + min_offset..nodes.len() - 1 {
                    if segment_distance(&nodes[i], &nodes[i + 1], &nodes[j], &nodes[j + 1]) < 2.0 * radius {
                        brute = Some((i, j));
                        break 'walk;
                    }
                }
            }
            // The same first contact, not only the same answer.
            prop_assert_eq!(fast, brute);
        }
    }

    #[test]
    fn fine_nodes_on_a_straight_wire_are_not_contacts() {
        let nodes: Vec<Vector3<f64>> = (0..=10_000)
            .map(|i| Vector3::new(f64::from(i) * 1e-4, 0.0, 0.0))
            .collect();
        assert!(self_contact(&nodes, 1e-4, 0.001).is_none());
    }
}
