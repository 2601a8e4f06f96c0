//! The discrete rod's configuration: nodes, material angles and reference frames.

use ftwire_core::{Pose, ensure_finite};
use nalgebra::{Matrix3, Point3, Rotation3, UnitQuaternion, Vector3};

use crate::discrete_rod::DiscreteRod;
use crate::error::SimError;
use crate::transport::{perpendicular, transport_f64};

/// A configuration of the discrete elastic rod (Bergou et al. 2010, §4): `N + 1` nodes in the
/// world frame, and for each edge a material angle `θ_j` measured from a reference director.
///
/// The reference director of edge `j` is stored with the tangent it belongs to; when the edge
/// moves, its reference director is the time-parallel transport of the stored one (Bergou 2010,
/// §4.1). [`RodState::material_frames`] gives the resulting material frames.
#[derive(Debug, Clone, PartialEq)]
pub struct RodState {
    pub(crate) nodes: Vec<Vector3<f64>>,
    pub(crate) theta: Vec<f64>,
    pub(crate) ref_tangent: Vec<Vector3<f64>>,
    pub(crate) ref_d1: Vec<Vector3<f64>>,
    /// The reference twist `m_ref` \[rad\] of each vertex `i = 1..N−1` (slot 0 unused), the
    /// last value the state was rebased with. `atan2` gives `m_ref` only modulo 2π; the energy
    /// takes the branch nearest this value, so that `m_ref` stays continuous along a motion as
    /// in Bergou et al. 2010, §4.1, where it is updated incrementally. Without it, a clamp
    /// whose director turns more than π from the transported reference of its neighbour (a tip
    /// rolled about its own axis) would wrap `m_ref` by 2π, change the rod's total twist by a
    /// full turn and snap it to another equilibrium (test
    /// `tests/issue_14_reference_twist_wrap.rs`).
    pub(crate) ref_twist: Vec<f64>,
    pub(crate) base: Pose,
    pub(crate) tip: Pose,
}

/// A user-given starting configuration: centreline points and material frames.
///
/// The points are the `N + 1` node positions in the world frame, at the arc lengths
/// [`DiscreteRod::node_arc_length`] (`(k − ½)·h`, so the first and last lie half an edge outside the
/// wire); the frames are the `N` edge material frames (world from body, x axis along the
/// tangent, y and z the bending axes of `c2` and `c3`) at [`DiscreteRod::edge_arc_length`] (`j·h`).
/// The end points and frames are overwritten by the clamps.
#[derive(Debug, Clone, PartialEq)]
pub struct InitialGuess {
    /// Node positions \[m\], world frame, `N + 1` of them.
    pub points: Vec<Point3<f64>>,
    /// Edge material frames, world from body, `N` of them.
    pub frames: Vec<UnitQuaternion<f64>>,
}

impl InitialGuess {
    /// Samples a continuous shape `s ↦ pose` (world from body frame at arc length `s` \[m\],
    /// measured from the base clamp point, x axis along the tangent) at the rod's nodes and
    /// edges. `shape` is called for `s` in `[−h/2, L + h/2]`; outside `[0, L]` it may
    /// extrapolate or clamp, since the end nodes are set by the clamps anyway.
    ///
    /// # Example
    /// ```
    /// use ftwire_sim::{InitialGuess, DiscreteRod, RodParams};
    /// use nalgebra::{Isometry3, Translation3, UnitQuaternion};
    /// let rod = DiscreteRod::new(RodParams::default().with_edges(10))?;
    /// let guess = InitialGuess::from_shape(&rod, |s| {
    ///     Isometry3::from_parts(Translation3::new(s, 0.0, 0.0), UnitQuaternion::identity())
    /// });
    /// assert_eq!(guess.points.len(), 11);
    /// assert_eq!(guess.frames.len(), 10);
    /// # Ok::<(), ftwire_sim::SimError>(())
    /// ```
    pub fn from_shape(rod: &DiscreteRod, mut shape: impl FnMut(f64) -> Pose) -> Self {
        let points = (0..rod.nodes())
            .map(|k| Point3::from(shape(rod.node_arc_length(k)).translation.vector))
            .collect();
        let frames = (0..rod.edges())
            .map(|j| shape(rod.edge_arc_length(j)).rotation)
            .collect();
        Self { points, frames }
    }
}

impl RodState {
    /// A straight, untwisted rod along the base clamp's x axis, clamped at `base` and at the
    /// base pose translated by `L` along that axis.
    pub(crate) fn straight(rod: &DiscreteRod, base: &Pose) -> Self {
        let t = base.rotation * Vector3::x();
        let d1 = base.rotation * Vector3::y();
        let o = base.translation.vector;
        let n = rod.edges();
        let nodes = (0..=n).map(|k| o + t * rod.node_arc_length(k)).collect();
        let mut tip = *base;
        tip.translation.vector += t * rod.params().length;
        Self {
            nodes,
            theta: vec![0.0; n],
            ref_tangent: vec![t; n],
            ref_d1: vec![d1; n],
            ref_twist: vec![0.0; n],
            base: *base,
            tip,
        }
    }

    /// A length-exact smooth guess between two clamps: the cubic Hermite curve with the clamp
    /// tangents (arms of a third of the chord), plus a bump `b·sin²(πu)·n` perpendicular to the
    /// chord (towards the side the tangents turn from, or along the softer bending direction for
    /// a straight chord), with `b` chosen so that the length is `L`. If the Hermite curve alone
    /// is already too long, its arms are shortened instead. The base director is
    /// parallel-transported along the curve and the remaining roll about the tip tangent is
    /// spread linearly over the material angles.
    pub(crate) fn hermite(rod: &DiscreteRod, base: &Pose, tip: &Pose) -> Self {
        let l = rod.params().length;
        let n = rod.edges();
        let (p0, p1) = (base.translation.vector, tip.translation.vector);
        let (t0, t1) = (base.rotation * Vector3::x(), tip.rotation * Vector3::x());
        let chord = p1 - p0;
        let dist = chord.norm();
        let axis = if dist > 1e-12 { chord / dist } else { t0 };
        let c = rod.params().stiffness;
        let soft = if c[1] <= c[2] {
            base.rotation * Vector3::z()
        } else {
            base.rotation * Vector3::y()
        };
        let side = {
            let d = t0 - t1;
            let d = d - axis * axis.dot(&d);
            if d.norm() > 1e-6 {
                d.normalize()
            } else {
                perpendicular(&axis, &soft)
            }
        };
        const SAMPLES: usize = 2048;
        let curve = |arm: f64, bump: f64| -> Vec<Vector3<f64>> {
            let (c1, c2) = (p0 + t0 * arm, p1 - t1 * arm);
            (0..=SAMPLES)
                .map(|i| {
                    let u = i as f64 / SAMPLES as f64;
                    let v = 1.0 - u;
                    let b = (std::f64::consts::PI * u).sin();
                    p0 * (v * v * v)
                        + c1 * (3.0 * v * v * u)
                        + c2 * (3.0 * v * u * u)
                        + p1 * (u * u * u)
                        + side * (bump * b * b)
                })
                .collect()
        };
        let length =
            |pts: &[Vector3<f64>]| pts.windows(2).map(|w| (w[1] - w[0]).norm()).sum::<f64>();
        let full_arm = dist / 3.0;
        let (arm, bump) = if length(&curve(full_arm, 0.0)) >= l {
            let (mut lo, mut hi) = (0.0, full_arm);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if length(&curve(mid, 0.0)) < l {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            (0.5 * (lo + hi), 0.0)
        } else {
            let (mut lo, mut hi) = (0.0, l);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if length(&curve(full_arm, mid)) < l {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            (full_arm, 0.5 * (lo + hi))
        };
        let pts = curve(arm, bump);
        let mut cum = vec![0.0; pts.len()];
        for i in 1..pts.len() {
            cum[i] = cum[i - 1] + (pts[i] - pts[i - 1]).norm();
        }
        let scale = l / cum[cum.len() - 1].max(f64::MIN_POSITIVE);
        let at = |s: f64| -> Vector3<f64> {
            let s = (s / scale).clamp(0.0, cum[cum.len() - 1]);
            let i = cum.partition_point(|&c| c < s).clamp(1, pts.len() - 1);
            let span = (cum[i] - cum[i - 1]).max(f64::MIN_POSITIVE);
            let f = ((s - cum[i - 1]) / span).clamp(0.0, 1.0);
            pts[i - 1] * (1.0 - f) + pts[i] * f
        };
        let mut state = Self::straight(rod, base);
        for k in 1..n {
            state.nodes[k] = at(rod.node_arc_length(k));
        }
        state.apply_clamps(rod, base, tip);
        // Space-parallel transport of the base director, then spread the roll at the tip.
        let mut d1 = base.rotation * Vector3::y();
        let mut t_prev = t0;
        for j in 0..n {
            let t = (state.nodes[j + 1] - state.nodes[j]).normalize();
            d1 = perpendicular(&t, &transport_f64(&t_prev, &t, &d1));
            state.ref_tangent[j] = t;
            state.ref_d1[j] = d1;
            t_prev = t;
        }
        let tip_d1 = tip.rotation * Vector3::y();
        let last = state.ref_d1[n - 1];
        let roll = last.cross(&tip_d1).dot(&t1).atan2(last.dot(&tip_d1));
        for j in 1..n - 1 {
            state.theta[j] = roll * rod.edge_arc_length(j) / l;
        }
        state.apply_clamps(rod, base, tip);
        // Chords of a curved guess are shorter than h by (hκ)²/24: restore the lengths.
        state.project_lengths(rod.edge_length());
        state
    }

    /// A state from a user guess (end nodes and frames replaced by the clamps).
    pub(crate) fn from_guess(
        rod: &DiscreteRod,
        guess: &InitialGuess,
        base: &Pose,
        tip: &Pose,
    ) -> Result<Self, SimError> {
        let n = rod.edges();
        if guess.points.len() != n + 1 {
            return Err(SimError::GuessSize {
                what: "points",
                got: guess.points.len(),
                expected: n + 1,
            });
        }
        if guess.frames.len() != n {
            return Err(SimError::GuessSize {
                what: "frames",
                got: guess.frames.len(),
                expected: n,
            });
        }
        for p in &guess.points {
            ensure_finite("initial guess point", p.coords.as_slice())?;
        }
        for q in &guess.frames {
            ensure_finite("initial guess frame", q.coords.as_slice())?;
        }
        let nodes: Vec<Vector3<f64>> = guess.points.iter().map(|p| p.coords).collect();
        let mut ref_tangent = Vec::with_capacity(n);
        let mut ref_d1 = Vec::with_capacity(n);
        for j in 0..n {
            let e = nodes[j + 1] - nodes[j];
            let len = e.norm();
            if len.is_nan() || len <= 1e-9 * rod.edge_length() {
                return Err(SimError::DegenerateGuess { edge: j });
            }
            let t = e / len;
            ref_tangent.push(t);
            ref_d1.push(perpendicular(&t, &(guess.frames[j] * Vector3::y())));
        }
        let mut state = Self {
            nodes,
            theta: vec![0.0; n],
            ref_tangent,
            ref_d1,
            ref_twist: vec![0.0; n],
            base: *base,
            tip: *tip,
        };
        state.apply_clamps(rod, base, tip);
        state.rebase();
        state.project_lengths(rod.edge_length());
        Ok(state)
    }

    /// Places the two clamped end edges (nodes, tangents, directors, angles) at the clamp poses.
    pub(crate) fn apply_clamps(&mut self, rod: &DiscreteRod, base: &Pose, tip: &Pose) {
        let n = rod.edges();
        let half = 0.5 * rod.edge_length();
        for (pose, (a, b), j) in [(base, (0, 1), 0), (tip, (n - 1, n), n - 1)] {
            let t = pose.rotation * Vector3::x();
            let o = pose.translation.vector;
            self.nodes[a] = o - t * half;
            self.nodes[b] = o + t * half;
            self.ref_tangent[j] = t;
            self.ref_d1[j] = pose.rotation * Vector3::y();
            self.theta[j] = 0.0;
        }
        self.base = *base;
        self.tip = *tip;
    }

    /// Moves every reference frame to its edge's current tangent by time-parallel transport
    /// (Bergou 2010, §4.1), and records the reference twists on their continuous branch (see
    /// `RodState::ref_twist`). The material frames, and hence the energy, do not change.
    pub(crate) fn rebase(&mut self) {
        for j in 0..self.theta.len() {
            let t = (self.nodes[j + 1] - self.nodes[j]).normalize();
            let d1 = transport_f64(&self.ref_tangent[j], &t, &self.ref_d1[j]);
            self.ref_d1[j] = perpendicular(&t, &d1);
            self.ref_tangent[j] = t;
        }
        for i in 1..self.theta.len() {
            let (t0, t1) = (&self.ref_tangent[i - 1], &self.ref_tangent[i]);
            let carried = transport_f64(t0, t1, &self.ref_d1[i - 1]);
            let d1 = &self.ref_d1[i];
            let raw = carried.cross(d1).dot(t1).atan2(carried.dot(d1));
            self.ref_twist[i] = raw + nearest_turns(raw, self.ref_twist[i]);
        }
    }

    /// Number of edges.
    pub fn edges(&self) -> usize {
        self.theta.len()
    }

    /// The centreline: `N + 1` node positions \[m\] in the world frame, at arc lengths
    /// `(k − ½)·h` from the base clamp point (the first and last lie inside the grippers).
    pub fn centreline(&self) -> Vec<Point3<f64>> {
        self.nodes.iter().map(|x| Point3::from(*x)).collect()
    }

    /// The physical wire, from the base clamp point to the tip clamp point \[m\], world frame:
    /// the base clamp point (arc length 0), the interior nodes `1..N−1` (arc lengths
    /// `(k − ½)·h`), then the tip clamp point (arc length `L`); `N + 1` points in all. Unlike
    /// [`RodState::centreline`], it leaves out the two ghost nodes that lie half an edge inside
    /// the grippers.
    pub fn wire_centreline(&self) -> Vec<Point3<f64>> {
        let n = self.nodes.len();
        let mut points = Vec::with_capacity(n);
        points.push(Point3::from(self.base.translation.vector));
        points.extend(self.nodes[1..n - 1].iter().map(|x| Point3::from(*x)));
        points.push(Point3::from(self.tip.translation.vector));
        points
    }

    /// The material frame of each of the `N` edges, world from body: columns `(t, m1, m2)`, the
    /// tangent and the bending axes of `c2` and `c3`, at arc length `j·h`.
    pub fn material_frames(&self) -> Vec<Rotation3<f64>> {
        (0..self.theta.len())
            .map(|j| {
                let t = (self.nodes[j + 1] - self.nodes[j]).normalize();
                let d1 = perpendicular(
                    &t,
                    &transport_f64(&self.ref_tangent[j], &t, &self.ref_d1[j]),
                );
                let d2 = t.cross(&d1);
                let (s, c) = self.theta[j].sin_cos();
                let m1 = d1 * c + d2 * s;
                let m2 = t.cross(&m1);
                Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[t, m1, m2]))
            })
            .collect()
    }

    /// The base clamp pose (world from clamp).
    pub fn base(&self) -> &Pose {
        &self.base
    }

    /// The tip clamp pose (world from clamp).
    pub fn tip(&self) -> &Pose {
        &self.tip
    }

    /// Largest node distance \[m\] between two states of the same rod.
    pub fn max_distance(&self, other: &RodState) -> f64 {
        self.nodes
            .iter()
            .zip(&other.nodes)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max)
    }

    /// Projects the free nodes `2..=N−2` so that edges `1..=N−2` have length `h`. Leaves the state
    /// unchanged if the projection does not converge (e.g. clamps pulled taut).
    ///
    /// A predictor that moves nodes independently stretches the edges to second order in the
    /// step (an edge turned by α grows by α²/2), and with the stiff stretching energy that error
    /// dominates the first Newton iterations. Before Newton starts, the continuation therefore
    /// projects the predicted free nodes onto the constraint set `|e_j| = h` with the smallest
    /// displacement (fast projection, Goldenthal et al. 2007): Gauss–Newton steps
    /// `Δx = −Jᵀ (J Jᵀ)⁻¹ C` with a tridiagonal `J Jᵀ`.
    pub(crate) fn project_lengths(&mut self, h: f64) {
        let n = self.edges();
        if n < 4 {
            return;
        }
        let mut x = self.nodes.clone();
        let m = n - 2; // constraints on edges 1..=N−2
        for _ in 0..20 {
            let t: Vec<Vector3<f64>> = (1..=m).map(|j| (x[j + 1] - x[j]).normalize()).collect();
            let c: Vec<f64> = (1..=m).map(|j| (x[j + 1] - x[j]).norm() - h).collect();
            let worst = c.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
            if worst < 1e-12 * h {
                break;
            }
            // J Jᵀ: constraint k (edge k+1) touches nodes k+1 (free if k ≥ 1) and k+2 (free if k ≤ m−2).
            let free = |node: usize| (2..=n - 2).contains(&node);
            let mut diag = vec![0.0; m];
            let mut off = vec![0.0; m.saturating_sub(1)];
            for k in 0..m {
                let (a, b) = (k + 1, k + 2);
                diag[k] = f64::from(u8::from(free(a))) + f64::from(u8::from(free(b)));
                if k + 1 < m {
                    // Constraints k and k+1 share node k+2: ∂C_k/∂x = t_k, ∂C_{k+1}/∂x = −t_{k+1}.
                    off[k] = -t[k].dot(&t[k + 1]);
                }
            }
            // Thomas algorithm for (J Jᵀ) λ = C.
            let mut cp = vec![0.0; m];
            let mut dp = vec![0.0; m];
            let mut ok = true;
            for k in 0..m {
                let lower = if k > 0 { off[k - 1] } else { 0.0 };
                let denom = diag[k] - lower * if k > 0 { cp[k - 1] } else { 0.0 };
                if denom.is_nan() || denom.abs() <= 1e-12 {
                    ok = false;
                    break;
                }
                cp[k] = if k + 1 < m { off[k] / denom } else { 0.0 };
                dp[k] = (c[k] - lower * if k > 0 { dp[k - 1] } else { 0.0 }) / denom;
            }
            if !ok {
                return;
            }
            let mut lambda = dp;
            for k in (0..m.saturating_sub(1)).rev() {
                lambda[k] -= cp[k] * lambda[k + 1];
            }
            // Δx = −Jᵀ λ on free nodes.
            for k in 0..m {
                let (a, b) = (k + 1, k + 2);
                if free(a) {
                    x[a] += t[k] * lambda[k];
                }
                if free(b) {
                    x[b] -= t[k] * lambda[k];
                }
            }
            if x.iter().any(|v| !v.iter().all(|c| c.is_finite())) {
                return;
            }
        }
        let moved = x
            .iter()
            .zip(&self.nodes)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        let worst = (1..=m)
            .map(|j| ((x[j + 1] - x[j]).norm() - h).abs())
            .fold(0.0, f64::max);
        if worst < 1e-6 * h && moved < 0.1 * h * n as f64 {
            self.nodes = x;
            self.rebase();
        }
    }
}

/// The multiple of 2π that, added to the angle `raw`, comes nearest to `previous`.
pub(crate) fn nearest_turns(raw: f64, previous: f64) -> f64 {
    let turn = std::f64::consts::TAU;
    turn * ((previous - raw) / turn).round()
}
