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
//! A bounding-volume hierarchy over the polyline, in its own order: a balanced binary tree of
//! index ranges of segments, each with the axis-aligned box of its nodes, leaves of at most
//! 8 segments (`LEAF`). Pairs of ranges are searched from the root down and dropped when their
//! boxes are farther apart than the diameter, when every pair in them is adjacent (closer in
//! index than the offset above), or when none can come before the first contact found so far.
//! Along a smooth wire the boxes separate once they are shorter than about `r/2` of arc, so the
//! work grows as `n log n` with the node count `n` (a table of all pairs of chunks would grow
//! as `n²` in memory). The tests against the boxes are conservative, with a margin for
//! rounding, so the result is that of the plain pair walk (tests `skip_agrees_with_brute_force`
//! and `near_touching_agrees_with_brute_force`): the first contact in the order of `i`, then
//! `j`. A pair of segments is measured by [`segment_distance`], the workspace's one
//! segment–segment distance (`ftwire_core::geometry`, re-exported here), after a cheaper test
//! of the balls around their midpoints.

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
    // Smallest index offset j − i with (j − i − 1)·Δ ≥ π r, and at least 2.
    let ratio = std::f64::consts::PI * radius / spacing;
    let min_offset = if ratio.is_finite() && ratio < segments as f64 {
        (1 + ratio.ceil() as usize).max(2)
    } else {
        return None;
    };
    let search = Search::new(positions, radius, min_offset);
    let mut best = None;
    search.visit(0, 0, &mut best);
    best
}

/// Segments per leaf of the hierarchy of [`self_contact`].
const LEAF: usize = 8;

/// An index range of segments and the box of its nodes.
#[derive(Debug, Clone, Copy)]
struct Range {
    /// First segment.
    lo: usize,
    /// One past the last segment.
    hi: usize,
    /// The box's lowest corner \[m\].
    min: Vector3<f64>,
    /// The box's highest corner \[m\].
    max: Vector3<f64>,
    /// Whether every coordinate of its nodes is finite (a box with a NaN or an infinity is
    /// near everything, so that its pairs are measured as the plain walk measures them).
    finite: bool,
    /// The two halves (indices into the tree), or none for a leaf.
    halves: Option<(usize, usize)>,
}

/// The hierarchy of one polyline and what its search needs.
struct Search<'a> {
    positions: &'a [Vector3<f64>],
    /// The tree; the root is the first.
    tree: Vec<Range>,
    /// Midpoint of each segment.
    mid: Vec<Vector3<f64>>,
    /// Half the length of each segment \[m\].
    half: Vec<f64>,
    /// `2·radius` \[m\]: segments closer than this touch.
    diameter: f64,
    /// The diameter plus a margin that covers the rounding of the box and ball tests, so that
    /// they drop only pairs that [`segment_distance`] puts at the diameter or farther.
    limit: f64,
    /// Smallest index offset of two segments that are compared.
    min_offset: usize,
}

impl<'a> Search<'a> {
    fn new(positions: &'a [Vector3<f64>], radius: f64, min_offset: usize) -> Self {
        let segments = positions.len() - 1;
        let diameter = 2.0 * radius;
        let scale = positions
            .iter()
            .flat_map(|p| p.iter())
            .filter(|x| x.is_finite())
            .fold(0.0, |m: f64, x| m.max(x.abs()));
        let mut search = Self {
            positions,
            tree: Vec::with_capacity(2 * segments.div_ceil(LEAF)),
            mid: positions.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect(),
            half: positions
                .windows(2)
                .map(|w| 0.5 * (w[1] - w[0]).norm())
                .collect(),
            diameter,
            limit: diameter + 1e-9 * (diameter.abs() + scale),
            min_offset,
        };
        search.build(0, segments);
        search
    }

    /// Adds the range `lo..hi` and its descendants to the tree; returns its index.
    fn build(&mut self, lo: usize, hi: usize) -> usize {
        let index = self.tree.len();
        let nodes = &self.positions[lo..=hi];
        let first = nodes[0];
        let (min, max) = nodes
            .iter()
            .fold((first, first), |(min, max), p| (min.inf(p), max.sup(p)));
        let finite = nodes.iter().all(|p| p.iter().all(|x| x.is_finite()));
        self.tree.push(Range {
            lo,
            hi,
            min,
            max,
            finite,
            halves: None,
        });
        if hi - lo > LEAF {
            let middle = lo + (hi - lo) / 2;
            let left = self.build(lo, middle);
            let right = self.build(middle, hi);
            self.tree[index].halves = Some((left, right));
        }
        index
    }

    /// Whether the boxes of `a` and `b` may hold segments closer than the diameter.
    fn near(&self, a: &Range, b: &Range) -> bool {
        if !(a.finite && b.finite) {
            return true;
        }
        let gap = (b.min - a.max).sup(&(a.min - b.max)).sup(&Vector3::zeros());
        gap.norm_squared() < self.limit * self.limit
    }

    /// Searches the pairs `(i, j)` with `i` in range `a`, `j` in range `b` and
    /// `j ≥ i + min_offset`, keeping in `best` the first contact in the order of `i`, then `j`.
    fn visit(&self, a: usize, b: usize, best: &mut Option<Contact>) {
        let (ra, rb) = (&self.tree[a], &self.tree[b]);
        // The first pair the two ranges could hold.
        let first_j = rb.lo.max(ra.lo + self.min_offset);
        if first_j >= rb.hi || best.is_some_and(|c| (ra.lo, first_j) >= c.segments) {
            return;
        }
        if !self.near(ra, rb) {
            return;
        }
        match (ra.halves, rb.halves) {
            (None, None) => self.leaves(ra, rb, best),
            (Some((left, right)), None) => {
                self.visit(left, b, best);
                self.visit(right, b, best);
            }
            (Some((left, right)), Some(_)) if ra.hi - ra.lo >= rb.hi - rb.lo => {
                self.visit(left, b, best);
                self.visit(right, b, best);
            }
            (_, Some((left, right))) => {
                self.visit(a, left, best);
                self.visit(a, right, best);
            }
        }
    }

    /// The pair walk over two leaves.
    fn leaves(&self, ra: &Range, rb: &Range, best: &mut Option<Contact>) {
        for i in ra.lo..ra.hi {
            for j in rb.lo.max(i + self.min_offset)..rb.hi {
                if best.is_some_and(|c| (i, j) >= c.segments) {
                    return;
                }
                // Segment i lies within half[i] of mid[i]: no contact if the balls are apart.
                let limit = self.limit + self.half[i] + self.half[j];
                if (self.mid[i] - self.mid[j]).norm_squared() >= limit * limit {
                    continue;
                }
                let p = self.positions;
                let distance = segment_distance(&p[i], &p[i + 1], &p[j], &p[j + 1]);
                if distance < self.diameter {
                    *best = Some(Contact {
                        segments: (i, j),
                        distance,
                    });
                    break;
                }
            }
        }
    }
}

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

        /// The hierarchy never hides a contact: agree with the brute-force pair walk on
        /// random wiggly polylines.
        #[test]
        fn skip_agrees_with_brute_force(
            seed in prop::collection::vec(-1.0..1.0f64, 60..300),
            radius in 0.001..0.05f64,
            bend in 0.05..1.5f64,
        ) {
            // From gently curved (parts far apart) to tightly wound.
            let nodes = wiggly(&seed, bend);
            // The same first contact, not only the same answer.
            prop_assert_eq!(
                self_contact(&nodes, SPACING, radius),
                brute_force(&nodes, SPACING, radius)
            );
        }

        /// Near-touching curves: the radius is set so that the closest compared pair is at
        /// the diameter to within a few units in the last place (or exactly at it), where a
        /// test of boxes or balls without a margin for rounding would drop a contact.
        #[test]
        fn near_touching_agrees_with_brute_force(
            seed in prop::collection::vec(-1.0..1.0f64, 60..600),
            radius in 0.002..0.03f64,
            bend in 0.05..1.0f64,
            ulps in -4_i64..=4,
            offset in prop::array::uniform3(-10.0..10.0f64),
        ) {
            // Far from the origin too, where the coordinates' rounding is coarser.
            let shift = Vector3::from(offset);
            let nodes: Vec<Vector3<f64>> =
                wiggly(&seed, bend).into_iter().map(|p| p + shift).collect();
            let min_offset = min_offset(radius, SPACING);
            let closest = (0..nodes.len() - 1)
                .flat_map(|i| (i + min_offset..nodes.len() - 1).map(move |j| (i, j)))
                .map(|(i, j)| segment_distance(&nodes[i], &nodes[i + 1], &nodes[j], &nodes[j + 1]))
                .fold(f64::INFINITY, f64::min);
            prop_assume!(closest.is_finite() && closest > 0.0);
            let touching = f64::from_bits((0.5 * closest).to_bits().wrapping_add_signed(ulps));
            // The spacing given scaled with the radius, so that the same pairs are compared.
            let spacing = SPACING * touching / radius;
            prop_assume!(min_offset == self::min_offset(touching, spacing));
            prop_assert_eq!(
                self_contact(&nodes, spacing, touching),
                brute_force(&nodes, spacing, touching)
            );
        }

        /// Axis-aligned hairpins, whose boxes are as close as their segments: the gap between
        /// the strands within a few units in the last place of the diameter, far from the
        /// origin too.
        #[test]
        fn hairpins_at_the_diameter_agree_with_brute_force(
            radius in 0.0005..0.01f64,
            ulps in -3_i64..=3,
            offset in prop::array::uniform3(-100.0..100.0f64),
            axis in 0_usize..3,
        ) {
            let shift = Vector3::from(offset);
            let gap = f64::from_bits((2.0 * radius).to_bits().wrapping_add_signed(ulps));
            let along = Vector3::ith(axis, SPACING);
            let across = Vector3::ith((axis + 1) % 3, gap);
            let nodes: Vec<Vector3<f64>> = (0..=40)
                .map(|k| shift + along * f64::from(k))
                .chain((0..=40).rev().map(|k| shift + along * f64::from(k) + across))
                .collect();
            prop_assert_eq!(
                self_contact(&nodes, SPACING, radius),
                brute_force(&nodes, SPACING, radius)
            );
        }
    }

    /// Node spacing of the random polylines \[m\].
    const SPACING: f64 = 0.02;

    /// A polyline of uniform spacing whose direction turns by `bend` times the seed's triples.
    fn wiggly(seed: &[f64], bend: f64) -> Vec<Vector3<f64>> {
        let mut p = Vector3::zeros();
        let mut dir = Vector3::new(1.0, 0.0, 0.0);
        let mut nodes = vec![p];
        for w in seed.chunks(3) {
            let at = |k: usize| w.get(k).copied().unwrap_or(0.0);
            let turn = Vector3::new(at(0), at(1), at(2)) * bend;
            dir = (dir + turn).normalize();
            p += dir * SPACING;
            nodes.push(p);
        }
        nodes
    }

    /// The smallest index offset of compared segments, as [`self_contact`] computes it.
    fn min_offset(radius: f64, spacing: f64) -> usize {
        (1 + (std::f64::consts::PI * radius / spacing).ceil() as usize).max(2)
    }

    /// The definition: every compared pair in the order of `i`, then `j`.
    fn brute_force(nodes: &[Vector3<f64>], spacing: f64, radius: f64) -> Option<Contact> {
        let segments = nodes.len() - 1;
        let min_offset = min_offset(radius, spacing);
        (0..segments)
            .flat_map(|i| (i + min_offset..segments).map(move |j| (i, j)))
            .map(|(i, j)| Contact {
                segments: (i, j),
                distance: segment_distance(&nodes[i], &nodes[i + 1], &nodes[j], &nodes[j + 1]),
            })
            .find(|c| c.distance < 2.0 * radius)
    }

    /// A closed loop of a million nodes touches itself where its ends overlap, and nowhere
    /// else: found without a table of all pairs of its parts.
    #[test]
    fn a_fine_loop_touches_where_its_ends_overlap() {
        let (nodes, loop_radius, radius) = (1_000_000, 0.1, 0.001);
        // One turn and a little more, rising by less than the diameter.
        let turn = 1.02 * std::f64::consts::TAU / f64::from(nodes - 1);
        let positions: Vec<Vector3<f64>> = (0..nodes)
            .map(|k| {
                let t = turn * f64::from(k);
                Vector3::new(loop_radius * t.cos(), loop_radius * t.sin(), 1e-4 * t)
            })
            .collect();
        let spacing = (positions[1] - positions[0]).norm();
        let contact = self_contact(&positions, spacing, radius).expect("the ends overlap");
        // The first segment touches the first segment of the second turn that is closer
        // than the diameter.
        let (i, j) = contact.segments;
        assert_eq!(i, 0);
        assert!(contact.distance < 2.0 * radius);
        let first_close = (i + min_offset(radius, spacing)..nodes as usize - 1)
            .find(|&j| {
                segment_distance(
                    &positions[0],
                    &positions[1],
                    &positions[j],
                    &positions[j + 1],
                ) < 2.0 * radius
            })
            .expect("a segment of the second turn is close");
        assert_eq!(j, first_close);
        // Without the overlap, no contact.
        let one_turn = (0.98 / 1.02 * f64::from(nodes)) as usize;
        assert!(self_contact(&positions[..one_turn], spacing, radius).is_none());
    }

    #[test]
    fn fine_nodes_on_a_straight_wire_are_not_contacts() {
        let nodes: Vec<Vector3<f64>> = (0..=10_000)
            .map(|i| Vector3::new(f64::from(i) * 1e-4, 0.0, 0.0))
            .collect();
        assert!(self_contact(&nodes, 1e-4, 0.001).is_none());
    }
}
