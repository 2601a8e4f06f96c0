//! Pure geometry queries shared by the model and the robot, as free functions.
//!
//! [`segment_distance`] is the one segment–segment distance of the workspace: the wire's
//! self-contact test (`ftwire_rod::self_contact`, its hot path) and the robot's capsule checks
//! (`ftwire_robot`) both call it. Its property test against a sampled minimum is
//! `segment_distance_is_the_sampled_minimum` in ftwire-rod's `intersection` module (ftwire-robot's
//! `tests/collision.rs` checks it the same way on its capsules).

use nalgebra::Vector3;

/// The distance \[m\] between segments `[p1, q1]` and `[p2, q2]` (Ericson, *Real-Time Collision
/// Detection*, §5.1.9: the closest points of the two lines, clamped to the segments).
///
/// Degenerate segments (a point, or both) are allowed: a segment counts as a point only when
/// its squared length is below `1e-300` m², so that no length scale is assumed (a 1 µm wire
/// segment is as valid as a 1 m arm link). Parallel segments take `s = 0` on the first one
/// and the clamped closest point on the second, which gives the exact distance.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// let d = ftwire_core::geometry::segment_distance(
///     &Vector3::new(0.0, 0.0, 0.0), &Vector3::new(1.0, 0.0, 0.0),
///     &Vector3::new(0.5, -1.0, 0.3), &Vector3::new(0.5, 1.0, 0.3),
/// );
/// assert!((d - 0.3).abs() < 1e-15);
/// ```
#[inline]
pub fn segment_distance(
    p1: &Vector3<f64>,
    q1: &Vector3<f64>,
    p2: &Vector3<f64>,
    q2: &Vector3<f64>,
) -> f64 {
    const EPS: f64 = 1e-300;
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.dot(&d1);
    let e = d2.dot(&d2);
    let f = d2.dot(&r);
    let (s, t);
    if a <= EPS && e <= EPS {
        return r.norm();
    }
    if a <= EPS {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if e <= EPS {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let s0 = if denom > 0.0 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            } else {
                t = t0;
                s = s0;
            }
        }
    }
    ((p1 + d1 * s) - (p2 + d2 * t)).norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
        Vector3::new(x, y, z)
    }

    #[test]
    fn degenerate_segments_are_points() {
        let o = v(0.0, 0.0, 0.0);
        assert!(
            (segment_distance(&o, &o, &v(3.0, 4.0, 0.0), &v(3.0, 4.0, 0.0)) - 5.0).abs() < 1e-15
        );
        // A point against a segment: the distance to its nearest end or its interior.
        let (p, q) = (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0));
        assert!(
            (segment_distance(&v(2.0, 1.0, 0.0), &v(2.0, 1.0, 0.0), &p, &q) - 2f64.sqrt()).abs()
                < 1e-15
        );
        assert!(
            (segment_distance(&p, &q, &v(0.5, 0.0, 2.0), &v(0.5, 0.0, 2.0)) - 2.0).abs() < 1e-15
        );
    }

    #[test]
    fn parallel_segments_take_the_gap_between_them() {
        // Overlapping in x, 0.5 apart; and end to end along the same line, 1 apart.
        let d = segment_distance(
            &v(0.0, 0.0, 0.0),
            &v(1.0, 0.0, 0.0),
            &v(0.5, 0.5, 0.0),
            &v(2.0, 0.5, 0.0),
        );
        assert!((d - 0.5).abs() < 1e-15);
        let d = segment_distance(
            &v(0.0, 0.0, 0.0),
            &v(1.0, 0.0, 0.0),
            &v(3.0, 0.0, 0.0),
            &v(2.0, 0.0, 0.0),
        );
        assert!((d - 1.0).abs() < 1e-15);
    }

    #[test]
    fn tiny_segments_are_not_treated_as_points() {
        // Two crossing 1 µm segments 1 nm apart: the distance is the gap, not an end distance.
        let h = 5e-7;
        let d = segment_distance(
            &v(-h, 0.0, 0.0),
            &v(h, 0.0, 0.0),
            &v(0.0, -h, 1e-9),
            &v(0.0, h, 1e-9),
        );
        assert!((d - 1e-9).abs() < 1e-20);
    }
}
