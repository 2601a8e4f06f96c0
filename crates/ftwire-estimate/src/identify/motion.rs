//! How the second gripper moves while a wire of unknown `c` and `L` is identified (paper
//! §IV-B: "the second gripper was randomly moved").
//!
//! From the start pose `b0` (the wire held in some stable shape), the plan is a seeded sequence
//! of poses `b_k = b0 M(δb_k)` (eq. 8–10), each a small random move **from `b0`** (not a random
//! walk, which would drift): a translation uniform in a ball of radius
//! [`MotionPlan::translation`] (default 5 mm) and a rotation about a uniform random axis by an
//! angle uniform in `[0, rotation]` (default 3°), followed by a **twist** of the gripper about
//! the wire's tangent at the tip (the x axis of `b0`) by [`MotionPlan::twist`] (default 40°),
//! `+` on odd moves and `−` on even ones, so that the first three samples straddle `b0`.
//!
//! Why the twist: the torsional stiffness `c1` shows in the data only through the torsional
//! moment along the wire. A start whose wire is nearly planar barely loads it, and a random 3°
//! rotation twists the tip by about 1.5° on average, so without a twist a few samples can
//! leave `c1` poorly determined. A twist `θ` adds the torsional moment `c1 θ / L`, a
//! normalised torque `θ c1/c2 ≈ 0.56` for 40° on any round wire, whatever its stiffness and
//! length: far above the noise, and far below twist buckling (Greenhill's load of a clamped
//! wire is a normalised torque of about 9).
//!
//! Why 40° rather than 20°: the sensor's noise and drift are fixed in newton-metres and the
//! twist's torque is `c1 θ / L`, so the softest, longest wires of the search box (`c2/L` of
//! tens of mN·m) get the least torque above the noise. Doubling the twist doubles that margin
//! on every wire alike (it is normalised), still at a fifteenth of Greenhill's load; the
//! measurements are in `docs/identify-soft-wires.md`.
//!
//! Why small, and why near `b0`:
//! - **the equilibrium branch**: a held wire can have several equilibria for one gripper pose;
//!   small moves near a stable configuration keep it on its branch (`Γ` is a local
//!   diffeomorphism there, paper §III-A), so every sample is explained by one connected piece
//!   of `A_stable` and no snap-through separates the data from the model;
//! - **the linearisation of eq. 12**: the paper's differential form is only first order in
//!   `δb`, so it needs small steps (its error grows with the step); the default absolute
//!   residual has no such limit, but gains nothing from large moves either;
//! - **signal-to-noise**: each move must still change the wrench well above the sensor's
//!   noise. Held wires are stiff to pull and soft to bend, so millimetres matter: on the 3 mm
//!   nitinol wire in a stable shape, the default moves change the normalised wrench
//!   (`J(L)⁻¹ δb`, torque in `c2/L`, force in `c2/L²`) by far more than the noise of a tared,
//!   averaged sensor (test `the_motion_plan_is_small_seeded_and_informative`); much smaller
//!   moves drown in the noise, much larger ones risk leaving the branch.
//!
//! The plan only returns poses; executing them (and checking reachability and collisions) is
//! the caller's job.

use ftwire_core::Pose;
use nalgebra::{Translation3, Unit, UnitQuaternion, Vector3};
use rand::{Rng, RngExt};

use crate::EstimateError;

/// A random identification motion near a start pose.
///
/// # Example
/// ```
/// use ftwire_core::Pose;
/// use ftwire_estimate::identify::MotionPlan;
/// use rand::SeedableRng;
/// let b0 = Pose::translation(0.5, 0.1, 0.0);
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
/// let poses = MotionPlan::default().poses(&b0, &mut rng);
/// assert_eq!(poses.len(), 6);
/// assert!(poses.iter().all(|b| (b.translation.vector - b0.translation.vector).norm() <= 5e-3));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionPlan {
    /// Number of poses after `b0` (default `6`; three samples identify a wire, the rest are
    /// margin for rejected or noisy ones).
    pub moves: usize,
    /// Largest translation from `b0` \[m\] (default `5e-3`).
    pub translation: f64,
    /// Largest random rotation from `b0` \[rad\] (default `3°`).
    pub rotation: f64,
    /// The twist about the wire's tangent at the tip (the x axis of `b0`) added to every move,
    /// alternating in sign \[rad\] (default `40°`; `0` for the paper's purely random moves).
    pub twist: f64,
}

impl Default for MotionPlan {
    fn default() -> Self {
        Self {
            moves: 6,
            translation: 5e-3,
            rotation: 3.0_f64.to_radians(),
            twist: 40.0_f64.to_radians(),
        }
    }
}

impl MotionPlan {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] unless both sizes are finite and positive and the
    /// rotation is below π.
    pub fn validate(&self) -> Result<(), EstimateError> {
        if !(self.translation.is_finite() && self.translation > 0.0) {
            return Err(EstimateError::BadIdentifySetting {
                field: "motion.translation",
                value: self.translation,
                allowed: "finite and > 0",
            });
        }
        if !(self.rotation > 0.0 && self.rotation < std::f64::consts::PI) {
            return Err(EstimateError::BadIdentifySetting {
                field: "motion.rotation",
                value: self.rotation,
                allowed: "in (0, π)",
            });
        }
        if !(self.twist.is_finite() && self.twist.abs() < std::f64::consts::FRAC_PI_2) {
            return Err(EstimateError::BadIdentifySetting {
                field: "motion.twist",
                value: self.twist,
                allowed: "in (−π/2, π/2)",
            });
        }
        Ok(())
    }

    /// The poses `b_1 … b_moves` of the second gripper relative to the base clamp, each a
    /// random move from `b0` in the body frame of `b0` (eq. 10), then twisted about the x axis
    /// of `b0` by `+twist` (moves 1, 3, …) or `−twist` (moves 2, 4, …).
    pub fn poses<R: Rng + ?Sized>(&self, b0: &Pose, rng: &mut R) -> Vec<Pose> {
        (0..self.moves)
            .map(|k| {
                let dx = unit_vector(rng) * self.translation * rng.random::<f64>().cbrt();
                let axis = Unit::new_normalize(unit_vector(rng));
                let angle = self.rotation * rng.random::<f64>();
                let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
                let twist = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), sign * self.twist);
                b0 * Pose::from_parts(
                    Translation3::from(dx),
                    UnitQuaternion::from_axis_angle(&axis, angle) * twist,
                )
            })
            .collect()
    }
}

/// A uniform random unit vector (rejection from the cube).
fn unit_vector<R: Rng + ?Sized>(rng: &mut R) -> Vector3<f64> {
    loop {
        let v = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        let n = v.norm();
        if n > 1e-3 && n <= 1.0 {
            return v / n;
        }
    }
}
