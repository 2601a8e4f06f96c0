//! The wire's shape at nodes ([`Shape`], re-exported as `ftwire_rod::rod::Shape`) and how it is
//! made from the integrator's knots ([`from_knots`]): septic Hermite interpolation of
//! the frame state between grid points, then Gram–Schmidt re-orthonormalisation of every frame
//! ([`rotation_from_columns`]).

use ftwire_core::Pose;
use nalgebra::{Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};

use crate::arith::{MulAdd, Separate};
use crate::hermite::septic_hermite;
use crate::kirchhoff::FrameJet;

/// The wire's shape at `N` nodes uniformly spaced in arc length from `t = 0` to `t = L`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Shape {
    /// Arc length `t_i = i L / (N − 1)` of each node \[m\].
    pub arc_length: Vec<f64>,
    /// Node positions `p(t_i)` \[m\] in the base clamp frame.
    pub positions: Vec<Vector3<f64>>,
    /// Material frames `R(t_i)` (columns: tangent, then the bending axes of `c2`, `c3`), base
    /// clamp frame from body frame.
    pub rotations: Vec<Rotation3<f64>>,
}

impl Shape {
    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether there are no nodes.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The frame `q(t_i)` of node `i` as a pose (base clamp from body), if it exists.
    pub fn pose(&self, i: usize) -> Option<Pose> {
        let p = self.positions.get(i)?;
        let r = self.rotations.get(i)?;
        Some(Pose::from_parts(
            Translation3::from(*p),
            UnitQuaternion::from_rotation_matrix(r),
        ))
    }

    /// Arc-length spacing of the nodes \[m\].
    pub fn spacing(&self) -> f64 {
        match (self.arc_length.first(), self.arc_length.last()) {
            (Some(a), Some(b)) if self.len() > 1 => (b - a) / (self.len() - 1) as f64,
            _ => 0.0,
        }
    }
}

/// The shape at `nodes` nodes of a wire of `length` \[m\] from the frame jets at the grid
/// points (septic Hermite dense output). AVX2+FMA when the CPU has it.
pub(crate) fn from_knots(length: f64, knots: &[FrameJet], nodes: usize) -> Shape {
    #[cfg(target_arch = "x86_64")]
    if crate::arith::fast_path() {
        // SAFETY: `fast_path` checked that the CPU has AVX2 and FMA (as in
        // `Rod::integrate_full`).
        #[allow(unsafe_code)]
        return unsafe { from_knots_fma(length, knots, nodes) };
    }
    from_knots_with(length, knots, nodes, interpolate_rows::<Separate>)
}

/// [`from_knots`] compiled for AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn from_knots_fma(length: f64, knots: &[FrameJet], nodes: usize) -> Shape {
    from_knots_with(length, knots, nodes, |k0, k1, h, theta| {
        crate::simd::interpolate_frame(k0, k1, h, theta)
    })
}

/// The shape of a wire of `length` \[m\] from the knots: `between(k0, k1, h, θ)` interpolates
/// the flat frame state (rows `(R_i0, R_i1, R_i2, p_i)`) at `θ ∈ (0, 1)` of the step `h` from
/// knot `k0` to knot `k1`; `p` and the first two columns of `R` are kept.
///
/// Two passes: the interpolation of every node, then the re-orthonormalisation of every
/// rotation. Each pass is a loop of independent short computations that the CPU overlaps
/// (one pass doing both is a long chain of dependent operations per node).
#[inline(always)]
pub(crate) fn from_knots_with(
    length: f64,
    knots: &[FrameJet],
    nodes: usize,
    between: impl Fn(&FrameJet, &FrameJet, f64, f64) -> [[f64; 4]; 3],
) -> Shape {
    let steps = knots.len().saturating_sub(1).max(1);
    let h = length / steps as f64;
    let last = nodes.saturating_sub(1).max(1) as f64;
    let mut positions = vec![Vector3::zeros(); nodes];
    let mut rotations = vec![Rotation3::identity(); nodes];
    // The knot interval of the current node, moved forward as the nodes advance (no
    // float-to-integer conversion per node).
    let mut k = 0;
    for (i, (p, r)) in positions.iter_mut().zip(&mut rotations).enumerate() {
        let x = i as f64 * steps as f64 / last;
        while k + 1 < steps && x >= (k + 1) as f64 {
            k += 1;
        }
        let theta = (x - k as f64).clamp(0.0, 1.0);
        let (Some(k0), Some(k1)) = (knots.get(k), knots.get(k + 1)) else {
            continue;
        };
        let r = r.matrix_mut_unchecked();
        if theta == 0.0 || theta == 1.0 {
            let f = if theta == 0.0 { k0 } else { k1 }.frame();
            (*p, *r) = (f.p, f.r);
        } else {
            let [r0, r1, r2] = between(k0, k1, h, theta);
            *p = Vector3::new(r0[3], r1[3], r2[3]);
            *r = Matrix3::new(r0[0], r0[1], 0.0, r1[0], r1[1], 0.0, r2[0], r2[1], 0.0);
        }
    }
    for r in &mut rotations {
        *r = rotation_from_columns(r.matrix());
    }
    Shape {
        arc_length: (0..nodes).map(|i| length * i as f64 / last).collect(),
        positions,
        rotations,
    }
}

/// Septic Hermite interpolation of the flat frame state (rows `(R_i0, R_i1, R_i2, p_i)`)
/// between two knots: one pass over its 12 numbers per term (the portable interpolation of
/// [`from_knots_with`]).
#[inline(always)]
pub(crate) fn interpolate_rows<A: MulAdd>(
    k0: &FrameJet,
    k1: &FrameJet,
    h: f64,
    theta: f64,
) -> [[f64; 4]; 3] {
    let w = septic_hermite(theta);
    let scale = [1.0, h, h * h, h * h * h];
    let mut acc = [0.0; 12];
    for (side, knot) in [k0, k1].into_iter().enumerate() {
        for (order, d) in knot.d.iter().enumerate() {
            let wi = w[4 * side + order] * scale[order];
            for (a, v) in acc.iter_mut().zip(d) {
                *a = A::mul_add(wi, *v, *a);
            }
        }
    }
    std::array::from_fn(|i| std::array::from_fn(|j| acc[4 * i + j]))
}

/// Gram–Schmidt on the first two columns, keeping the tangent's direction; the third column
/// is their cross product.
#[inline(always)]
pub(crate) fn rotation_from_columns(r: &Matrix3<f64>) -> Rotation3<f64> {
    Rotation3::from_matrix_unchecked(orthonormalise(r))
}

/// [`rotation_from_columns`]'s matrix: with `c0`, `c1` the first two columns, `x = c0 / |c0|`
/// and `y = (s00 c1 − s01 c0) / sqrt(s00 D)`, where `s_ij = c_i · c_j` and
/// `D = s00 s11 − s01²` (so that `|s00 c1 − s01 c0|² = s00 D`): two square roots and two
/// divisions per node, independent of each other (the usual form needs a third division,
/// `s01 / s00`, and its second square root waits on it), which the compiler runs for
/// several nodes at once. The divider bounds this pass, so fewer divisions make it faster.
#[inline(always)]
pub(crate) fn orthonormalise(r: &Matrix3<f64>) -> Matrix3<f64> {
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let c0 = [r[(0, 0)], r[(1, 0)], r[(2, 0)]];
    let c1 = [r[(0, 1)], r[(1, 1)], r[(2, 1)]];
    let (s00, s01, s11) = (dot(&c0, &c0), dot(&c0, &c1), dot(&c1, &c1));
    let gram = s00 * s11 - s01 * s01;
    let [n0, n1] = [s00, s00 * gram].map(|v| 1.0 / v.sqrt());
    let x = c0.map(|v| v * n0);
    let y: [f64; 3] = std::array::from_fn(|i| (s00 * c1[i] - s01 * c0[i]) * n1);
    let z = [
        x[1] * y[2] - x[2] * y[1],
        x[2] * y[0] - x[0] * y[2],
        x[0] * y[1] - x[1] * y[0],
    ];
    Matrix3::new(
        x[0], y[0], z[0], //
        x[1], y[1], z[1], //
        x[2], y[2], z[2],
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Gram–Schmidt on two skewed columns: an orthonormal, right-handed result whose first
    /// column is along `c0` and whose second lies in the plane of `c0`, `c1` on `c1`'s side.
    #[test]
    fn orthonormalise_keeps_the_tangent_and_the_plane() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for _ in 0..200 {
            let r = Rotation3::from_scaled_axis(Vector3::new(
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
            ));
            let skew = Matrix3::from_fn(|_, _| rng.random_range(-0.05..0.05));
            let m = r.matrix() * (Matrix3::identity() * rng.random_range(0.5..2.0) + skew);
            let q = orthonormalise(&m);
            let defect = q.transpose() * q - Matrix3::identity();
            assert!(defect.amax() <= 1e-15, "QᵀQ − I = {defect}");
            assert!((q.determinant() - 1.0).abs() <= 1e-15);
            let (c0, c1) = (m.column(0), m.column(1));
            assert!((q.column(0) - c0.normalize()).amax() <= 1e-15);
            let normal = c0.cross(&c1).normalize();
            assert!(q.column(1).dot(&normal).abs() <= 1e-15);
            assert!(q.column(1).dot(&c1) > 0.0);
        }
    }
}
