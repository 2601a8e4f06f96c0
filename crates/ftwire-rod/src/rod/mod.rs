//! Solving the wire for a configuration `a` (paper §II-A): shape `q(t)`, costate `μ(t)`,
//! `Γ(a) = q(L)`, `J(L)`, `M(L)`, `det J(t)` along the wire, stability and self-intersection.
//!
//! [`Rod::solve`] does everything; the hot paths do less: [`Rod::shape`] (frames only),
//! [`Rod::jacobian`] (`J(L)`, tip and stability, no shape) and [`Rod::is_stable`] (stops at
//! the first sign change of `det J`). The shape at the nodes is interpolated from the
//! integrator's knots by the `shape` module.

use std::marker::PhantomData;

use ftwire_core::{Pose, WireParams};
use nalgebra::{Matrix6, Rotation3, Translation3, UnitQuaternion, Vector6};

#[cfg(target_arch = "x86_64")]
use crate::arith::Fused;
use crate::arith::{MulAdd, Separate};
use crate::integrator::{Integrator, Method, Workspace};
use crate::intersection::self_contact;
use crate::kirchhoff::{
    FrameArray, FrameJet, FrameState, FullArray, FullRhs, Kirchhoff, ShapeArray, ShapeRhs,
    frame_of, jacobian_of, shape_initial,
};
mod shape;

use crate::stability::{SignTracker, Stability};
use crate::{Load, RodError, validate_configuration};
use shape::orthonormalise;

pub use shape::Shape;
pub(crate) use shape::rotation_from_columns;

/// Default number of shape nodes (both ends included).
pub const DEFAULT_NODES: usize = 64;
/// Fewest shape nodes accepted (the two ends).
pub const MIN_NODES: usize = 2;
/// Most shape nodes accepted.
pub const MAX_NODES: usize = 1_000_000;

/// A wire and the settings to solve it: the model's entry point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rod {
    wire: WireParams,
    integrator: Integrator,
    load: Load,
}

/// `J(L)`, the tip pose and stability, without the shape ([`Rod::jacobian`]).
#[derive(Debug, Clone, PartialEq)]
pub struct JacobianSolution {
    /// `Γ(a) = q(L)`: the second gripper's clamp pose in the base clamp frame.
    pub tip: Pose,
    /// `J(L)`: `δb ≈ J(L) δa`, rows `(δω, δv)` (body twist at the tip), columns `δa`.
    pub jacobian: Matrix6<f64>,
    /// `M(L) = ∂μ(L)/∂a`.
    pub m: Matrix6<f64>,
    /// `μ(L)`: the internal wrench at the tip, body frame, torque first.
    pub costate_tip: Vector6<f64>,
    /// The stability test along the wire.
    pub stability: Stability,
}

/// Everything about one configuration ([`Rod::solve`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// The shape at the requested nodes.
    pub shape: Shape,
    /// `μ(t_i)` at the shape nodes (body frame, torque first).
    pub costate: Vec<Vector6<f64>>,
    /// Tip pose, `J(L)`, `M(L)` and stability.
    pub jacobian: JacobianSolution,
    /// Whether non-adjacent parts of the wire are closer than its diameter
    /// (see [`crate::intersection`]).
    pub self_intersecting: bool,
}

impl Solution {
    /// Whether `a ∈ A_free`: stable and free of self-intersection.
    pub fn is_free(&self) -> bool {
        self.jacobian.stability.stable && !self.self_intersecting
    }
}

impl Rod {
    /// A rod with the default integrator ([`Integrator::default`]).
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector6;
    /// use ftwire_rod::{Rod, WireParams};
    /// let rod = Rod::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
    /// // A small bending moment about z curls the wire toward +y.
    /// let shape = rod.shape(&Vector6::new(0.0, 0.0, 0.01, 0.0, 0.0, 0.0), 64)?;
    /// assert_eq!(shape.len(), 64);
    /// assert!(shape.positions[63].y > 0.0);
    /// # Ok::<(), ftwire_rod::RodError>(())
    /// ```
    #[must_use]
    pub fn new(wire: WireParams) -> Self {
        Self {
            wire,
            integrator: Integrator::default(),
            load: Load::none(),
        }
    }

    /// The same rod under a distributed load (weight per length, rest strains; see
    /// [`crate::load`]). Every solve honours it; with [`Load::none`] (the default) the
    /// unloaded solver runs, bit for bit as without this call.
    ///
    /// # Example
    /// ```
    /// use nalgebra::{Vector3, Vector6};
    /// use ftwire_rod::{Load, Rod, WireParams};
    /// let rod = Rod::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
    /// let a = Vector6::new(0.0, 0.0, 0.01, 0.0, 0.0, 0.0);
    /// assert_eq!(rod.with_load(Load::none()).solve(&a, 16)?, rod.solve(&a, 16)?);
    /// let bent = Load::none().with_natural_curvature(Vector3::new(0.0, 0.0, 1.0))?;
    /// assert!(rod.with_load(bent).tip(&a)?.translation.y > rod.tip(&a)?.translation.y);
    /// # Ok::<(), ftwire_rod::RodError>(())
    /// ```
    #[must_use]
    pub fn with_load(self, load: Load) -> Self {
        Self { load, ..self }
    }

    /// The distributed load ([`Load::none`] unless set by [`Rod::with_load`]).
    pub fn load(&self) -> &Load {
        &self.load
    }

    /// The same rod with other integration settings.
    #[must_use]
    pub fn with_integrator(self, integrator: Integrator) -> Self {
        Self { integrator, ..self }
    }

    /// The wire.
    pub fn wire(&self) -> &WireParams {
        &self.wire
    }

    /// The integration settings.
    pub fn integrator(&self) -> &Integrator {
        &self.integrator
    }

    fn model(&self, a: &Vector6<f64>) -> Result<Kirchhoff, RodError> {
        validate_configuration(a)?;
        Ok(Kirchhoff::new(self.wire.c(), a))
    }

    /// The number of integration steps used for a model.
    fn steps_for(&self, model: &Kirchhoff) -> usize {
        self.integrator
            .steps_for(model.turning_scale() * self.wire.length())
    }

    /// The number of integration steps the solver uses for `a` (fixed, or adapted to `a`; see
    /// [`Integrator::adaptive`]). Also the number of grid points of the stability test.
    ///
    /// # Errors
    /// As [`Rod::solve`].
    pub fn steps_for_configuration(&self, a: &Vector6<f64>) -> Result<usize, RodError> {
        if !self.load.is_none() {
            return self.loaded_steps(a);
        }
        Ok(self.steps_for(&self.model(a)?))
    }

    fn check_nodes(nodes: usize) -> Result<(), RodError> {
        if nodes < MIN_NODES {
            return Err(RodError::TooFewNodes {
                nodes,
                min: MIN_NODES,
            });
        }
        if nodes > MAX_NODES {
            return Err(RodError::TooManyNodes {
                nodes,
                max: MAX_NODES,
            });
        }
        Ok(())
    }

    /// Integrates `q` and `J` over the grid, tracking `det J`. Pushes the frame jets at the
    /// start and at the grid points into `knots` if given. Stops early at the first sign
    /// change if asked.
    ///
    /// Runs the AVX2+FMA build of the loop when the CPU has it ([`crate::arith`]).
    fn integrate_full(
        &self,
        model: &Kirchhoff,
        knots: Option<&mut Vec<FrameJet>>,
        record_det: bool,
        early_exit: bool,
    ) -> (FullArray, SignTracker<48>) {
        #[cfg(target_arch = "x86_64")]
        if crate::arith::fast_path() {
            // SAFETY: `fast_path` has checked that this CPU supports AVX2 and FMA, the only
            // requirement of the `#[target_feature]` function.
            #[allow(unsafe_code)]
            return unsafe { self.integrate_full_fma(model, knots, record_det, early_exit) };
        }
        let jet = |f: &FrameArray| model.frame_jet(f);
        self.integrate_full_with::<Separate>(model, knots, record_det, early_exit, jet)
    }

    /// [`Rod::integrate_full`] compiled for AVX2 and FMA: DOP853 runs the explicit kernel of
    /// [`crate::simd`], the other methods the generic step.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn integrate_full_fma(
        &self,
        model: &Kirchhoff,
        knots: Option<&mut Vec<FrameJet>>,
        record_det: bool,
        early_exit: bool,
    ) -> (FullArray, SignTracker<48>) {
        let jet = |f: &FrameArray| {
            let (m, _) = model.costate(&FrameState::from_slice(f));
            crate::simd::frame_jet(model.inv_c(), model.n0(), f, m.into())
        };
        if self.integrator.method() != Method::Dop853 {
            return self.integrate_full_with::<Fused>(model, knots, record_det, early_exit, jet);
        }
        let (h, steps) = self.grid_of(model);
        let mut tracker = SignTracker::new(h, steps, record_det);
        let mut at_point = grid_points(&mut tracker, knots, jet, model, early_exit);
        let grid = self.integrator.grid(h, steps);
        let (inv_c, m0, n0) = (model.inv_c(), model.m0(), model.n0());
        let y = crate::simd::integrate_full(inv_c, m0, n0, grid, &mut at_point);
        drop(at_point);
        (y, tracker)
    }

    /// The grid of a model: the step `L / steps` and `steps`.
    fn grid_of(&self, model: &Kirchhoff) -> (f64, usize) {
        let steps = self.steps_for(model);
        (self.wire.length() / steps as f64, steps)
    }

    #[inline(always)]
    fn integrate_full_with<A: MulAdd>(
        &self,
        model: &Kirchhoff,
        knots: Option<&mut Vec<FrameJet>>,
        record_det: bool,
        early_exit: bool,
        jet: impl Fn(&FrameArray) -> FrameJet,
    ) -> (FullArray, SignTracker<48>) {
        let (h, steps) = self.grid_of(model);
        let mut tracker = SignTracker::new(h, steps, record_det);
        let mut at_point = grid_points(&mut tracker, knots, jet, model, early_exit);
        let mut y: FullArray = FrameState::initial();
        let f = FullRhs::<A> {
            model,
            arith: PhantomData,
        };
        let mut work = Workspace::new();
        for (step, grid_point) in self.integrator.grid(h, steps) {
            self.integrator
                .step_in_place::<A, 48>(&mut y, step, f, &mut work);
            if let Some(index) = grid_point
                && !at_point(index, &y)
            {
                break;
            }
        }
        drop(at_point);
        (y, tracker)
    }

    /// Integrates `q` and `m` (the [`ShapeArray`] state) over `steps` uniform steps (the first
    /// in substeps, as [`Rod::integrate_full`]), pushing the frame jets at the grid points into
    /// `knots`; returns the final state. AVX2+FMA when the CPU has it.
    fn integrate_shape(
        &self,
        model: &Kirchhoff,
        a: &Vector6<f64>,
        steps: usize,
        knots: &mut Vec<FrameJet>,
    ) -> ShapeArray {
        #[cfg(target_arch = "x86_64")]
        if crate::arith::fast_path() {
            // SAFETY: as in `integrate_full`.
            #[allow(unsafe_code)]
            return unsafe { self.integrate_shape_fma(model, a, steps, knots) };
        }
        self.integrate_shape_with::<Separate>(model, a, steps, knots)
    }

    /// [`Rod::integrate_shape`] compiled for AVX2 and FMA: DOP853 runs the explicit kernel of
    /// [`crate::simd`], the other methods the generic step.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn integrate_shape_fma(
        &self,
        model: &Kirchhoff,
        a: &Vector6<f64>,
        steps: usize,
        knots: &mut Vec<FrameJet>,
    ) -> ShapeArray {
        if self.integrator.method() != Method::Dop853 {
            return self.integrate_shape_with::<Fused>(model, a, steps, knots);
        }
        let h = self.wire.length() / steps as f64;
        let grid = self.integrator.grid(h, steps);
        crate::simd::integrate_shape(model.inv_c(), model.n0(), &shape_initial(a), grid, knots)
    }

    #[inline(always)]
    fn integrate_shape_with<A: MulAdd>(
        &self,
        model: &Kirchhoff,
        a: &Vector6<f64>,
        steps: usize,
        knots: &mut Vec<FrameJet>,
    ) -> ShapeArray {
        let h = self.wire.length() / steps as f64;
        let mut y = shape_initial(a);
        knots.push(model.shape_jet(&y));
        let f = ShapeRhs::<A> {
            model,
            arith: PhantomData,
        };
        let mut work = Workspace::new();
        for (step, grid_point) in self.integrator.grid(h, steps) {
            self.integrator
                .step_in_place::<A, 16>(&mut y, step, f, &mut work);
            if grid_point.is_some() {
                knots.push(model.shape_jet(&y));
            }
        }
        y
    }

    fn jacobian_solution(
        &self,
        a: &Vector6<f64>,
        model: &Kirchhoff,
        y: &FullArray,
        tracker: SignTracker<48>,
    ) -> Result<JacobianSolution, RodError> {
        let frame = FrameState::from_slice(y);
        let tip = pose_of(&frame);
        let jacobian = jacobian_of(y);
        if !(jacobian.iter().all(|v| v.is_finite())
            && tip.translation.vector.iter().all(|v| v.is_finite()))
        {
            return Err(RodError::Diverged {
                a: (*a).into(),
                steps: self.steps_for(model),
            });
        }
        let costate_tip = model.costate6(&frame);
        let m = crate::m_matrix(&tip, &costate_tip, &jacobian);
        Ok(JacobianSolution {
            tip,
            jacobian,
            m,
            costate_tip,
            stability: tracker.finish(),
        })
    }

    /// Solves everything for `a`: the shape at `nodes` nodes, `μ` at the nodes, the tip pose
    /// `Γ(a)`, `J(L)`, `M(L)`, `det J` along the grid, stability and self-intersection.
    ///
    /// Self-intersection is tested on the returned shape, or on [`DEFAULT_NODES`] nodes if
    /// fewer were asked for.
    ///
    /// # Errors
    /// [`RodError::Core`] for a non-finite `a` or a non-finite [`Load`] field,
    /// [`RodError::OutsideA`] for `a ∉ A`, [`RodError::TooFewNodes`]/[`RodError::TooManyNodes`],
    /// [`RodError::Diverged`] if the integration overflows.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector6;
    /// use ftwire_rod::{Rod, WireParams};
    /// let rod = Rod::new(WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015)?);
    /// let solution = rod.solve(&Vector6::new(0.0, 0.2, 0.1, -0.5, 0.3, 0.0), 64)?;
    /// assert_eq!(solution.shape.len(), 64);
    /// // The last node is the tip Γ(a).
    /// let tip = solution.jacobian.tip.translation.vector;
    /// assert!((solution.shape.positions[63] - tip).norm() < 1e-12);
    /// # Ok::<(), ftwire_rod::RodError>(())
    /// ```
    pub fn solve(&self, a: &Vector6<f64>, nodes: usize) -> Result<Solution, RodError> {
        Self::check_nodes(nodes)?;
        if !self.load.is_none() {
            return self.loaded_solve(a, nodes);
        }
        let model = self.model(a)?;
        let mut knots = Vec::with_capacity(self.steps_for(&model) + 1);
        let (y, tracker) = self.integrate_full(&model, Some(&mut knots), true, false);
        let jacobian = self.jacobian_solution(a, &model, &y, tracker)?;
        let shape = self.shape_from_knots(&knots, nodes);
        let self_intersecting = if nodes >= DEFAULT_NODES {
            self_contact(&shape.positions, shape.spacing(), self.wire.radius()).is_some()
        } else {
            let dense = self.shape_from_knots(&knots, DEFAULT_NODES);
            self_contact(&dense.positions, dense.spacing(), self.wire.radius()).is_some()
        };
        let costate = shape
            .positions
            .iter()
            .zip(&shape.rotations)
            .map(|(p, r)| {
                model.costate6(&FrameState {
                    r: *r.matrix(),
                    p: *p,
                })
            })
            .collect();
        Ok(Solution {
            shape,
            costate,
            jacobian,
            self_intersecting,
        })
    }

    /// The shape only (frames at `nodes` nodes): the cheapest solve.
    ///
    /// # Errors
    /// As [`Rod::solve`].
    pub fn shape(&self, a: &Vector6<f64>, nodes: usize) -> Result<Shape, RodError> {
        Self::check_nodes(nodes)?;
        if !self.load.is_none() {
            return self.loaded_shape(a, nodes);
        }
        let model = self.model(a)?;
        let steps = self.steps_for(&model);
        let mut knots = Vec::with_capacity(steps + 1);
        let y = self.integrate_shape(&model, a, steps, &mut knots);
        if !y.iter().all(|v| v.is_finite()) {
            return Err(RodError::Diverged {
                a: (*a).into(),
                steps,
            });
        }
        Ok(self.shape_from_knots(&knots, nodes))
    }

    /// The shape at `nodes` nodes from the frame jets at the grid points
    /// ([`shape::from_knots`]: septic Hermite dense output).
    pub(crate) fn shape_from_knots(&self, knots: &[FrameJet], nodes: usize) -> Shape {
        shape::from_knots(self.wire().length(), knots, nodes)
    }

    /// `Γ(a) = q(L)`: the second gripper's pose for configuration `a` (frames only).
    ///
    /// # Errors
    /// As [`Rod::solve`].
    pub fn tip(&self, a: &Vector6<f64>) -> Result<Pose, RodError> {
        let shape = self.shape(a, MIN_NODES)?;
        shape.pose(1).ok_or(RodError::TooFewNodes {
            nodes: 1,
            min: MIN_NODES,
        })
    }

    /// `J(L)`, `M(L)`, the tip pose and the full stability record, without the shape.
    ///
    /// # Errors
    /// As [`Rod::solve`].
    pub fn jacobian(&self, a: &Vector6<f64>) -> Result<JacobianSolution, RodError> {
        if !self.load.is_none() {
            return self.loaded_jacobian(a);
        }
        let model = self.model(a)?;
        let (y, tracker) = self.integrate_full(&model, None, true, false);
        self.jacobian_solution(a, &model, &y, tracker)
    }

    /// Whether `a ∈ A_stable`, stopping at the first sign change of `det J`.
    ///
    /// # Errors
    /// [`RodError::Core`] for a non-finite `a` or [`Load`] field, [`RodError::OutsideA`] for
    /// `a ∉ A`.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector6;
    /// use ftwire_rod::{Rod, WireParams};
    /// let rod = Rod::new(WireParams::new([1.0, 1.0, 1.0], 1.0, 0.001)?);
    /// // Compressed beyond the clamped–clamped Euler load 4π² c2 / L² ≈ 39.5 N: buckled.
    /// assert!(rod.is_stable(&Vector6::new(0.0, 0.0, 1e-4, -30.0, 0.0, 0.0))?);
    /// assert!(!rod.is_stable(&Vector6::new(0.0, 0.0, 1e-4, -50.0, 0.0, 0.0))?);
    /// # Ok::<(), ftwire_rod::RodError>(())
    /// ```
    pub fn is_stable(&self, a: &Vector6<f64>) -> Result<bool, RodError> {
        if !self.load.is_none() {
            return self.loaded_is_stable(a);
        }
        let model = self.model(a)?;
        let (_, tracker) = self.integrate_full(&model, None, false, true);
        Ok(tracker.finish().stable)
    }
}

/// What the Jacobian paths do at the grid points: push the frame jet into `knots` (if given;
/// the jet at `t = 0` is pushed here, at once), and `det J` with its Taylor series into
/// `tracker` (which tests the step since the previous grid point too); the returned closure
/// takes the grid point's index and state, and says whether to go on (not after the first
/// sign change, if `early_exit`).
#[inline(always)]
fn grid_points<'a>(
    tracker: &'a mut SignTracker<48>,
    mut knots: Option<&'a mut Vec<FrameJet>>,
    jet: impl Fn(&FrameArray) -> FrameJet + 'a,
    model: &'a Kirchhoff,
    early_exit: bool,
) -> impl FnMut(usize, &FullArray) -> bool + 'a {
    if let Some(k) = knots.as_deref_mut() {
        k.push(jet(&FrameState::initial()));
    }
    move |index, y| {
        if let Some(k) = knots.as_deref_mut() {
            k.push(jet(&frame_of(y)));
        }
        tracker.push(index, y, model) || !early_exit
    }
}

fn pose_of(q: &FrameState) -> Pose {
    let r = Rotation3::from_matrix_unchecked(orthonormalise(&q.r));
    Pose::from_parts(
        Translation3::from(q.p),
        UnitQuaternion::from_rotation_matrix(&r),
    )
}

#[cfg(test)]
mod tests {
    use super::shape::{from_knots_with, interpolate_rows};
    use super::*;
    use crate::arith::Fused;
    use crate::sampling::Sampler;
    use nalgebra::Matrix3;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// The dispatched loops (AVX2+FMA on a CPU that has them) and the portable ones agree to
    /// rounding: same grid, same stability record, frames, `J` and shape within 1e-12, or
    /// within ten times what rounding alone does to that configuration if that is more, on a
    /// round wire and on one with three different stiffnesses (where every coefficient of the
    /// Jacobian's rate is nonzero). (On a CPU without AVX2 and FMA, or with `FTWIRE_NO_SIMD`
    /// set, both sides are the portable loops, and the test says so.)
    #[test]
    fn fast_and_portable_paths_agree() {
        if !crate::arith::fast_path() {
            eprintln!("fast_and_portable_paths_agree: no AVX2+FMA path here, both sides portable");
        }
        let wires = [
            WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid"),
            WireParams::new([1.3, 1.0, 0.6], 1.0, 0.001).expect("valid"),
        ];
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let sampler = Sampler::default();
        for wire in wires.into_iter().flat_map(|w| std::iter::repeat_n(w, 40)) {
            let rod = Rod::new(wire);
            let a = sampler.sample_a(&rod, &mut rng);
            let model = rod.model(&a).expect("in A");
            let (mut k_fast, mut k_plain) = (Vec::new(), Vec::new());
            let (y_fast, t_fast) = rod.integrate_full(&model, Some(&mut k_fast), true, false);
            let (y_plain, t_plain) =
                rod.integrate_full_with::<Separate>(&model, Some(&mut k_plain), true, false, |f| {
                    model.frame_jet(f)
                });
            let scale = y_plain.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            // Rounding alone moves the state this much here: the same generic loop with fused
            // multiply–adds (up to a few 1e-12 of the largest entry on the anisotropic wire,
            // where `J` grows large; a wrong term in a rate moves it by orders of magnitude
            // more).
            let (y_fused, _) = rod
                .integrate_full_with::<Fused>(&model, None, false, false, |f| model.frame_jet(f));
            let rounding = y_fused
                .iter()
                .zip(&y_plain)
                .fold(0.0f64, |m, (f, p)| m.max((f - p).abs() / scale));
            let tol = (10.0 * rounding).max(1e-12);
            for (f, p) in y_fast.iter().zip(&y_plain) {
                assert!((f - p).abs() <= tol * scale, "a = {a}: {f} vs {p}");
            }
            // The knots' jets, each order of derivative relative to its own size.
            assert_eq!(k_fast.len(), k_plain.len());
            for (f, p) in k_fast.iter().zip(&k_plain) {
                for (df, dp) in f.d.iter().zip(&p.d) {
                    let scale = dp.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                    for (x, y) in df.iter().zip(dp) {
                        assert!((x - y).abs() <= tol * scale, "a = {a}: {x} vs {y}");
                    }
                }
            }
            let (s_fast, s_plain) = (t_fast.finish(), t_plain.finish());
            assert_eq!(s_fast.stable, s_plain.stable, "a = {a}");
            assert_eq!(s_fast.det_j.len(), s_plain.det_j.len());
            let shape_fast = rod.shape_from_knots(&k_fast, 64);
            let shape_plain =
                from_knots_with(wire.length(), &k_plain, 64, interpolate_rows::<Separate>);
            for (f, p) in shape_fast.positions.iter().zip(&shape_plain.positions) {
                assert!((f - p).norm() <= tol * wire.length(), "a = {a}");
            }
            for (f, p) in shape_fast.rotations.iter().zip(&shape_plain.rotations) {
                assert!((f.matrix() - p.matrix()).amax() <= tol, "a = {a}");
                let defect = f.matrix().transpose() * f.matrix() - Matrix3::identity();
                assert!(defect.amax() <= 1e-14, "a = {a}: RᵀR − I = {defect}");
            }
            let steps = rod.steps_for(&model);
            let (mut kf, mut kp) = (Vec::new(), Vec::new());
            let yf = rod.integrate_shape(&model, &a, steps, &mut kf);
            let yp = rod.integrate_shape_with::<Separate>(&model, &a, steps, &mut kp);
            assert_eq!(kf.len(), kp.len());
            let scale = yp.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            for (f, p) in yf.iter().zip(&yp) {
                assert!((f - p).abs() <= tol * scale, "a = {a}: {f} vs {p}");
            }
            for (f, p) in kf.iter().zip(&kp) {
                assert!((f.frame().p - p.frame().p).norm() <= tol * wire.length());
                assert!((f.frame().r - p.frame().r).amax() <= tol);
                // The derivatives too (each order relative to its own size).
                for (df, dp) in f.d.iter().zip(&p.d).skip(1) {
                    let scale = dp.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                    for (x, y) in df.iter().zip(dp) {
                        assert!((x - y).abs() <= tol * scale, "a = {a}: {x} vs {y}");
                    }
                }
            }
            // The shape path runs the Jacobian path's grid; the two formulations (m integrated,
            // μ by closed form) give frames that agree to the accuracy requirement.
            assert_eq!(kf.len(), k_fast.len());
            for (f, j) in kf.iter().zip(&k_fast) {
                let (f, j) = (f.frame(), j.frame());
                assert!((f.p - j.p).norm() <= 1e-6 * wire.length(), "a = {a}");
                assert!((f.r - j.r).amax() <= 1e-6, "a = {a}");
            }
        }
    }
}
