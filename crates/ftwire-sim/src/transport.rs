//! Parallel transport of directors between tangents (Bergou et al. 2010, §4.1).
//!
//! `P(a → b)` is the rotation about `a × b` that takes the unit vector `a` to the unit vector
//! `b`: `P v = (a·b) v + (a×b)×v + ((a×b)·v)/(1 + a·b) · (a×b)`. It is smooth for `a·b > −1`.
//! The rod uses it twice: *space*-parallel transport from one edge to the next defines the
//! reference twist; *time*-parallel transport of each edge's reference director from the
//! tangent it had at the last update to its current tangent defines the reference frame, as a
//! smooth function of the edge vector.

use nalgebra::Vector3;

use crate::dual::{Scalar, V3, cross_c, dot_c};
#[cfg(test)]
use crate::dual::{cross, dot, scale};

/// `P(a → b) v` for a constant `a`, `v` and a variable `b` (all unit, `a·b > −1`).
pub(crate) fn transport_from_const<S: Scalar>(
    a: &Vector3<f64>,
    b: &V3<S>,
    v: &Vector3<f64>,
) -> V3<S> {
    // a × b with a constant on the left is −(b × a).
    let ab = cross_c(b, a);
    let ab = [-ab[0], -ab[1], -ab[2]];
    let c = dot_c(b, a);
    let abv = dot_c(&ab, v);
    let k = abv / (c + 1.0);
    let abxv = cross_c(&ab, v);
    [
        c * v.x + abxv[0] + k * ab[0],
        c * v.y + abxv[1] + k * ab[1],
        c * v.z + abxv[2] + k * ab[2],
    ]
}

/// `P(a → b) v` for variable unit vectors `a`, `b` and a variable `v` (the reference for the
/// dot-product form of the reference twist).
#[cfg(test)]
pub(crate) fn transport<S: Scalar>(a: &V3<S>, b: &V3<S>, v: &V3<S>) -> V3<S> {
    let ab = cross(a, b);
    let c = dot(a, b);
    let k = dot(&ab, v) / (c + 1.0);
    let abxv = cross(&ab, v);
    let cv = scale(v, c);
    [
        cv[0] + abxv[0] + k * ab[0],
        cv[1] + abxv[1] + k * ab[1],
        cv[2] + abxv[2] + k * ab[2],
    ]
}

/// `P(a → b) v` in plain `f64`.
pub(crate) fn transport_f64(a: &Vector3<f64>, b: &Vector3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    let ab = a.cross(b);
    let c = a.dot(b);
    c * v + ab.cross(v) + ab * (ab.dot(v) / (1.0 + c))
}

/// A unit vector perpendicular to `t`, closest to `d` (Gram–Schmidt), or any perpendicular
/// unit vector if `d` is parallel to `t`.
pub(crate) fn perpendicular(t: &Vector3<f64>, d: &Vector3<f64>) -> Vector3<f64> {
    let p = d - t * t.dot(d);
    let n = p.norm();
    if n > 1e-9 {
        p / n
    } else {
        let helper = if t.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        t.cross(&helper).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transport_maps_a_to_b_and_preserves_angles() {
        let a = Vector3::new(1.0, 0.2, -0.3).normalize();
        let b = Vector3::new(-0.1, 1.0, 0.4).normalize();
        assert!((transport_f64(&a, &b, &a) - b).norm() < 1e-14);
        let v = Vector3::new(0.3, -0.5, 0.8);
        let w = Vector3::new(-0.2, 0.1, 0.9);
        let (pv, pw) = (transport_f64(&a, &b, &v), transport_f64(&a, &b, &w));
        assert!((pv.dot(&pw) - v.dot(&w)).abs() < 1e-14);
        // The axis a × b is fixed.
        let axis = a.cross(&b);
        assert!((transport_f64(&a, &b, &axis) - axis).norm() < 1e-14);
        let g: V3<f64> = [b.x, b.y, b.z];
        let pc = transport_from_const(&a, &g, &v);
        assert!((Vector3::from(pc) - pv).norm() < 1e-14);
    }
}
