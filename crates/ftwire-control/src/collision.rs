//! Collision detection from F/T alone (paper §IV-E): a contact is a force the model does not
//! have, so after a contact the measured change of `ã` stops agreeing with the model's
//! prediction for the executed motion.
//!
//! **Prediction.** For a move of the second gripper by `Δ = b_i⁻¹ b_{i+1}` from the measured
//! `ã_i`, the model's answer is the `a` with `Γ(a) = Γ(ã_i) Δ`, found by Newton's method
//! ([`predicted_change`]) from the first-order guess `ã_i + J(L)⁻¹ δb` (eq. 11). The guess
//! alone errs by the square of the step, which on the controller's long first steps is larger
//! than a light contact.
//!
//! **Deviation.** Each move `i` has a deviation `e_i = N(ã_{i+1} − ã_i − δa_i)` in normalised
//! units (torque in `c2/L`, force in `c2/L²`) and a bound `β_i = ‖N J(L)⁻¹ S‖ ‖S⁻¹ δb_i‖`
//! ([`MoveCheck`]): to first order the largest change of `a` a motion of that size can make in
//! the model. On free motion `‖e_i‖` is sensor noise plus the model's error, and the model's
//! error is an error of `Γ` mapped through `J(L)⁻¹`: it grows with the motion and near the
//! model's folds, where `J(L)` is nearly singular and `β` is large. So the expected free
//! deviation is `floor + slope · β_i`, `floor` from the measured noise of `ã` and `slope`
//! from free motions.
//!
//! **Residual.** A contact's force usually builds up over several moves while the controller
//! keeps pushing, each move adding a little. The residual is therefore a cumulative test over
//! the last `w ≤ window` moves:
//!
//! ```text
//! r_k = max_w ‖Σ_{i>k−w} e_i‖ / (floor + slope Σ_{i>k−w} β_i)
//! ```
//!
//! Sensor noise telescopes in the sum (`Σ e_i` holds only the noise of its two ends), the
//! model's error grows at most as `Σ β_i`, and a persistent contact grows with `w`. `w = 1` is
//! the single move's normalised miss. The threshold on `r` is calibrated from free motions in
//! the same conditions ([`CollisionDetector::calibrate_moves`]), and is never below 1: a
//! deviation within the noise floor and the model's error is no evidence of a contact.

use ftwire_core::{Pose, WireParams};
use ftwire_estimate::WireModel;
use ftwire_rod::{se3, to_normalised};
use nalgebra::{Matrix6, Vector6};
use serde::Serialize;

use crate::ControlError;

/// Fewest finite free-motion residuals [`CollisionDetector::calibrate`] accepts.
pub const MIN_CALIBRATION_RESIDUALS: usize = 10;

/// The quantile of the free moves' `‖e‖ / β` that [`CollisionDetector::calibrate_moves`] takes
/// as the slope. `‖e‖ / β` is heavy-tailed (`β` spans orders of magnitude with the
/// conditioning of `J(L)`); its median left free motion near the model's folds above the
/// threshold, and its 95 % quantile delayed detections in the goal experiment (seeds 0 and 1,
/// gravity on and off).
pub const SLOPE_QUANTILE: f64 = 0.9;

/// Newton iterations of [`predicted_change`].
const NEWTON_ITERATIONS: usize = 8;
/// Convergence of [`predicted_change`]: `‖log(Γ(a)⁻¹ target)‖` (rad and m mixed; the wire's
/// length is of order 1 m).
const NEWTON_TOLERANCE: f64 = 1e-10;

/// `J(L)` in normalised units, `S J N⁻¹`: columns per normalised `δa` (times the torque or
/// force scale), rows `(δθ, δx / L)`.
pub(crate) fn normalised_jacobian(wire: &WireParams, jacobian: &Matrix6<f64>) -> Matrix6<f64> {
    let (ts, fs, l) = (wire.torque_scale(), wire.force_scale(), wire.length());
    let mut normalised = *jacobian;
    for c in 0..6 {
        let column = if c < 3 { ts } else { fs };
        for r in 0..6 {
            normalised[(r, c)] *= column;
            if r >= 3 {
                normalised[(r, c)] /= l;
            }
        }
    }
    normalised
}

/// What the detector keeps of one move.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MoveCheck {
    /// `e = N(ã_after − ã_before − δa)`: the measured change less the model's \[normalised\].
    pub deviation: Vector6<f64>,
    /// `d = ‖N δa‖`: the size of the predicted change \[normalised\].
    pub step: f64,
    /// `‖N J(L)⁻¹ S‖ ‖S⁻¹ δb‖`: to first order, the largest change of `a` a motion of this
    /// size can make in the model from `ã_before` (`S` scales translation by the wire's
    /// length), large near the model's folds, where a small error of the model moves `a` far
    /// \[normalised\]; at least `step`, and `step` when unknown.
    pub bound: f64,
}

impl MoveCheck {
    /// The check of a move from `before` to `after` (measured) whose predicted change is
    /// `predicted_da`.
    pub fn new(
        wire: &WireParams,
        before: &Vector6<f64>,
        after: &Vector6<f64>,
        predicted_da: &Vector6<f64>,
    ) -> Self {
        let step = to_normalised(wire, predicted_da).norm();
        Self {
            deviation: to_normalised(wire, &(after - before - predicted_da)),
            step,
            bound: step,
        }
    }

    /// The check of a move of the second gripper by `motion = b_i⁻¹ b_{i+1}` from `before`
    /// to `after` (measured), with the model's Newton prediction ([`predicted_change`], from
    /// `first_order`) and the bound from `J(L)` at `before`.
    pub fn of_move<M: WireModel>(
        model: &M,
        before: &Vector6<f64>,
        after: &Vector6<f64>,
        motion: &Pose,
        first_order: &Vector6<f64>,
    ) -> Self {
        let wire = model.wire();
        let predicted = predicted_change(model, before, motion, first_order);
        let mut check = Self::new(wire, before, after, &predicted);
        if let Ok(solution) = model.jacobian(before) {
            let l = wire.length();
            let normalised = normalised_jacobian(wire, &solution.jacobian);
            let smallest = normalised.singular_values().min();
            let xi = se3::log(motion);
            let db = Vector6::new(xi[0], xi[1], xi[2], xi[3] / l, xi[4] / l, xi[5] / l);
            let bound = db.norm() / smallest;
            if bound.is_finite() {
                check.bound = bound.max(check.step);
            }
        }
        check
    }

    /// The miss `‖e‖` \[normalised\].
    pub fn miss(&self) -> f64 {
        self.deviation.norm()
    }
}

/// A calibrated contact test on the cumulative residual of the last moves (see the module
/// docs).
///
/// # Example
/// ```
/// use ftwire_control::{CollisionDetector, MoveCheck};
/// use nalgebra::Vector6;
/// let free = [0.1, 0.2, 0.15, 0.05, 0.3, 0.12, 0.2, 0.1, 0.08, 0.25];
/// let detector = CollisionDetector::calibrate(&free, 2.0, 0.05)?;
/// assert!((detector.threshold() - 0.6).abs() < 1e-12);
/// assert!(detector.is_contact(0.9));
/// assert!(!detector.is_contact(0.3));
/// // Without a slope or window, the residual is the last miss over the floor.
/// let deviation = Vector6::new(0.0, 0.0, 0.0, 0.03, 0.0, 0.04);
/// let moved = MoveCheck { deviation, step: 1.0, bound: 1.0 };
/// assert!((detector.residual(&[moved]) - 1.0).abs() < 1e-12);
/// # Ok::<(), ftwire_control::ControlError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CollisionDetector {
    threshold: f64,
    floor: f64,
    slope: f64,
    window: usize,
}

impl CollisionDetector {
    /// Default margin over the free-motion residuals.
    pub const DEFAULT_MARGIN: f64 = 2.0;
    /// Default floor of the residual's denominator \[normalised units\].
    pub const DEFAULT_FLOOR: f64 = 0.01;
    /// Default window of the cumulative residual \[moves\] of
    /// [`CollisionDetector::calibrate_moves`].
    pub const DEFAULT_WINDOW: usize = 4;

    /// A detector with a given threshold on the residual and a denominator floor (normalised
    /// units), with no slope and a window of one move: the residual is the last miss over the
    /// floor.
    ///
    /// # Errors
    /// [`ControlError::BadSetting`] unless both are finite and positive.
    pub fn new(threshold: f64, floor: f64) -> Result<Self, ControlError> {
        for (name, value) in [("threshold", threshold), ("floor", floor)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(ControlError::BadSetting {
                    name,
                    value,
                    allowed: "a finite number > 0",
                });
            }
        }
        Ok(Self {
            threshold,
            floor,
            slope: 0.0,
            window: 1,
        })
    }

    /// The detector a controller without one records its residuals with: threshold 1, the
    /// default floor, no slope, a window of one move.
    pub fn uncalibrated() -> Self {
        Self {
            threshold: 1.0,
            floor: Self::DEFAULT_FLOOR,
            slope: 0.0,
            window: 1,
        }
    }

    /// The same detector with the model's error per unit of the bound `β` (`slope`, ≥ 0) and
    /// a window of `window` (≥ 1) moves.
    ///
    /// # Errors
    /// [`ControlError::BadSetting`] for a negative or non-finite slope or a zero window.
    pub fn with_model_error(self, slope: f64, window: usize) -> Result<Self, ControlError> {
        if !(slope.is_finite() && slope >= 0.0) {
            return Err(ControlError::BadSetting {
                name: "slope",
                value: slope,
                allowed: "a finite number ≥ 0",
            });
        }
        if window == 0 {
            return Err(ControlError::BadSetting {
                name: "window",
                value: 0.0,
                allowed: "at least 1 move",
            });
        }
        Ok(Self {
            slope,
            window,
            ..self
        })
    }

    /// Calibrates the threshold as `margin` times the largest of the finite `residuals`
    /// measured on free motion (non-finite ones are ignored), with no slope and a window of
    /// one move.
    ///
    /// # Errors
    /// [`ControlError::TooFewResiduals`] with fewer than [`MIN_CALIBRATION_RESIDUALS`] finite
    /// residuals; [`ControlError::BadSetting`] for a margin below 1 or a bad floor.
    pub fn calibrate(residuals: &[f64], margin: f64, floor: f64) -> Result<Self, ControlError> {
        Self::new(1.0, floor)?.with_threshold_from(residuals, 1.0, margin)
    }

    /// As [`CollisionDetector::calibrate`], from the `quantile` (in `(0, 1]`) of the finite
    /// residuals instead of the largest: free motions of a real wire can hold rare events the
    /// model does not have either (a snap to another equilibrium branch), which would otherwise
    /// set the threshold.
    ///
    /// # Errors
    /// As [`CollisionDetector::calibrate`], and [`ControlError::BadSetting`] for a quantile
    /// outside `(0, 1]`.
    pub fn calibrate_quantile(
        residuals: &[f64],
        quantile: f64,
        margin: f64,
        floor: f64,
    ) -> Result<Self, ControlError> {
        Self::new(1.0, floor)?.with_threshold_from(residuals, quantile, margin)
    }

    /// Floor of the residual's denominator over the median noise of `ã` at rest, in standard
    /// errors, of [`CollisionDetector::from_free_moves`].
    pub const FLOOR_SIGMAS: f64 = 5.0;
    /// Quantile of the free residuals the threshold is set from, of
    /// [`CollisionDetector::from_free_moves`].
    pub const FREE_QUANTILE: f64 = 0.95;

    /// The detector calibrated on free motions, as the goal experiment and `ftwire ros2
    /// estimate` calibrate it: its floor [`CollisionDetector::FLOOR_SIGMAS`] times the median
    /// of `noise_levels` (the norm of `ã`'s standard error at rest, normalised;
    /// [`CollisionDetector::DEFAULT_FLOOR`] when that is not a positive number), its slope and
    /// threshold from `free_moves` (one slice per free motion, in order):
    /// [`CollisionDetector::calibrate_moves`] at [`CollisionDetector::FREE_QUANTILE`] with
    /// the default margin. Returns the detector and its floor \[normalised\].
    ///
    /// # Errors
    /// [`ControlError::TooFewResiduals`] when the moves hold fewer than
    /// [`MIN_CALIBRATION_RESIDUALS`] finite residuals.
    pub fn from_free_moves(
        noise_levels: &[f64],
        free_moves: &[&[MoveCheck]],
    ) -> Result<(Self, f64), ControlError> {
        let floor = Self::FLOOR_SIGMAS * ftwire_core::stats::median(noise_levels);
        let floor = if floor.is_finite() && floor > 0.0 {
            floor
        } else {
            Self::DEFAULT_FLOOR
        };
        let detector =
            Self::calibrate_moves(free_moves, Self::FREE_QUANTILE, Self::DEFAULT_MARGIN, floor)?;
        Ok((detector, floor))
    }

    /// Calibrates the whole detector on the moves of free motions (one slice per motion, in
    /// order), with `floor` set from the measured noise of `ã` (see the module docs): the slope
    /// is the [`SLOPE_QUANTILE`] of `‖e_i‖ / β_i` over the moves whose bound `β_i` is at least
    /// the floor (the model's error per unit of motion), the window
    /// [`CollisionDetector::DEFAULT_WINDOW`], and the threshold `margin` times the `quantile`
    /// of the free residuals, but at least 1.
    ///
    /// # Errors
    /// As [`CollisionDetector::calibrate_quantile`].
    pub fn calibrate_moves(
        motions: &[&[MoveCheck]],
        quantile: f64,
        margin: f64,
        floor: f64,
    ) -> Result<Self, ControlError> {
        let probe = Self::new(1.0, floor)?;
        check_quantile(quantile)?;
        let mut per_motion: Vec<f64> = motions
            .iter()
            .flat_map(|moves| moves.iter())
            .filter(|m| m.bound >= floor && m.miss().is_finite())
            .map(|m| m.miss() / m.bound)
            .collect();
        let slope = quantile_of(&mut per_motion, SLOPE_QUANTILE).unwrap_or(0.0);
        let probe = probe.with_model_error(slope, Self::DEFAULT_WINDOW)?;
        let residuals: Vec<f64> = motions
            .iter()
            .flat_map(|moves| (1..=moves.len()).map(|k| probe.residual(&moves[..k])))
            .collect();
        let calibrated = probe.with_threshold_from(&residuals, quantile, margin)?;
        Ok(Self {
            threshold: calibrated.threshold.max(1.0),
            ..calibrated
        })
    }

    /// This detector with its threshold `margin` times the `quantile` of the finite
    /// `residuals`.
    fn with_threshold_from(
        self,
        residuals: &[f64],
        quantile: f64,
        margin: f64,
    ) -> Result<Self, ControlError> {
        if !(margin.is_finite() && margin >= 1.0) {
            return Err(ControlError::BadSetting {
                name: "margin",
                value: margin,
                allowed: "a finite number ≥ 1",
            });
        }
        check_quantile(quantile)?;
        let mut finite: Vec<f64> = residuals
            .iter()
            .copied()
            .filter(|r| r.is_finite())
            .collect();
        if finite.len() < MIN_CALIBRATION_RESIDUALS {
            return Err(ControlError::TooFewResiduals {
                got: finite.len(),
                needed: MIN_CALIBRATION_RESIDUALS,
            });
        }
        let level = quantile_of(&mut finite, quantile).unwrap_or(0.0);
        Ok(Self {
            threshold: (margin * level).max(f64::MIN_POSITIVE),
            ..self
        })
    }

    /// The threshold on the residual.
    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    /// The floor of the residual's denominator \[normalised units\].
    pub fn floor(&self) -> f64 {
        self.floor
    }

    /// The model's error per unit of the bound `β` \[-\].
    pub fn slope(&self) -> f64 {
        self.slope
    }

    /// The window of the cumulative residual \[moves\].
    pub fn window(&self) -> usize {
        self.window
    }

    /// Whether a residual means a contact.
    pub fn is_contact(&self, residual: f64) -> bool {
        // A non-finite residual is no agreement with the model either.
        residual.is_nan() || residual > self.threshold
    }

    /// The residual of the last of `moves` (see the module docs); `0` without moves.
    pub fn residual(&self, moves: &[MoveCheck]) -> f64 {
        let mut sum = Vector6::zeros();
        let mut bounds = 0.0;
        let mut worst = 0.0_f64;
        for m in moves.iter().rev().take(self.window) {
            sum += m.deviation;
            bounds += m.bound;
            let r = sum.norm() / (self.floor + self.slope * bounds);
            if r.is_nan() {
                return f64::NAN;
            }
            worst = worst.max(r);
        }
        worst
    }

    /// The first of `moves` (0-based) at which this detector fires.
    pub fn first_alarm(&self, moves: &[MoveCheck]) -> Option<usize> {
        (1..=moves.len())
            .find(|&k| self.is_contact(self.residual(&moves[..k])))
            .map(|k| k - 1)
    }
}

fn check_quantile(quantile: f64) -> Result<(), ControlError> {
    if quantile > 0.0 && quantile <= 1.0 {
        Ok(())
    } else {
        Err(ControlError::BadSetting {
            name: "quantile",
            value: quantile,
            allowed: "a quantile in (0, 1]",
        })
    }
}

/// The `quantile` of `values` (sorted in place): the `⌈q n⌉`-th smallest; `None` when empty.
fn quantile_of(values: &mut [f64], quantile: f64) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    let k = ((quantile * values.len() as f64).ceil() as usize).clamp(1, values.len().max(1));
    values.get(k - 1).copied()
}

/// The miss of one move: `‖N(after − before − δa_pred)‖` in normalised units.
pub fn miss(
    wire: &WireParams,
    before: &Vector6<f64>,
    after: &Vector6<f64>,
    predicted_da: &Vector6<f64>,
) -> f64 {
    MoveCheck::new(wire, before, after, predicted_da).miss()
}

/// The model's first-order prediction `δa = J(L)⁻¹ δb` for a commanded `δb` (eq. 11), or
/// `None` when `J(L)` is singular.
pub fn predicted_delta_a(jacobian: &Matrix6<f64>, delta_b: &Vector6<f64>) -> Option<Vector6<f64>> {
    jacobian.lu().solve(delta_b)
}

/// The model's change of `a` for the second gripper's motion `motion = b_i⁻¹ b_{i+1}` (in
/// the clamp frame of `b_i`) from `a`: [`configuration_at`] `Γ(a) motion`, from
/// `a + first_order` (see the module docs). Falls back to `first_order` when the model cannot
/// be solved or Newton does not converge.
pub fn predicted_change<M: WireModel>(
    model: &M,
    a: &Vector6<f64>,
    motion: &Pose,
    first_order: &Vector6<f64>,
) -> Vector6<f64> {
    let Ok(start) = model.tip(a) else {
        return *first_order;
    };
    configuration_at(model, &(a + first_order), &(start * motion))
        .map_or(*first_order, |next| next - a)
}

/// The configuration whose `Γ` is `target`, by Newton's method on `log(Γ(a)⁻¹ target) = 0`
/// from `guess`: `None` when the model cannot be solved on the way, `J(L)` is singular, or the
/// iteration does not converge (it stops below `1e-10`, rad and m mixed; after its last
/// iteration it accepts `1e-6`).
pub fn configuration_at<M: WireModel>(
    model: &M,
    guess: &Vector6<f64>,
    target: &Pose,
) -> Option<Vector6<f64>> {
    let mut next = *guess;
    for _ in 0..NEWTON_ITERATIONS {
        let solution = model.jacobian(&next).ok()?;
        let r = se3::log(&(solution.tip.inverse() * target));
        if !r.iter().all(|v| v.is_finite()) {
            return None;
        }
        if r.norm() < NEWTON_TOLERANCE {
            return Some(next);
        }
        next += solution.jacobian.lu().solve(&r)?;
    }
    // Accept a nearly converged answer; a diverging one is no answer.
    let tip = model.tip(&next).ok()?;
    (se3::log(&(tip.inverse() * target)).norm() < 1e-6).then_some(next)
}

#[cfg(test)]
mod tests {
    use super::*;
    use ftwire_estimate::KirchhoffModel;
    use ftwire_rod::from_normalised;

    fn wire() -> WireParams {
        WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid wire")
    }

    fn check(deviation: [f64; 6], step: f64) -> MoveCheck {
        MoveCheck {
            deviation: Vector6::from_column_slice(&deviation),
            step,
            bound: step,
        }
    }

    #[test]
    fn noise_telescopes_in_the_window_and_a_persistent_deviation_adds_up() {
        let detector = CollisionDetector::new(2.0, 0.1)
            .and_then(|d| d.with_model_error(0.0, 4))
            .expect("valid");
        // The noise of one rest enters two consecutive moves with opposite signs.
        let n = [0.05, -0.03, 0.02, 0.04, 0.0, -0.05];
        let minus = n.map(|v| -v);
        let noisy: Vec<MoveCheck> = (0..8)
            .map(|i| check(if i % 2 == 0 { n } else { minus }, 0.0))
            .collect();
        for k in 1..=noisy.len() {
            let r = detector.residual(&noisy[..k]);
            assert!(r < 1.0, "move {k}: {r}");
        }
        // 0.08 per move in one direction, below the single-move threshold of 0.2, is caught
        // once three moves have added up.
        let mut moves = noisy;
        moves.extend((0..4).map(|_| check([0.0, 0.0, 0.0, 0.08, 0.0, 0.0], 0.0)));
        assert!(detector.residual(&moves[..9]) < detector.threshold());
        assert_eq!(detector.first_alarm(&moves), Some(10));
        // A window of one move never sees it.
        let single = CollisionDetector::new(2.0, 0.1).expect("valid");
        assert_eq!(single.first_alarm(&moves), None);
    }

    #[test]
    fn the_expected_deviation_grows_with_the_step() {
        let detector = CollisionDetector::new(2.0, 0.1)
            .and_then(|d| d.with_model_error(0.5, 1))
            .expect("valid");
        // The same miss is a contact on a small step and model error on a large one.
        let small = check([0.0, 0.3, 0.0, 0.0, 0.0, 0.0], 0.02);
        let large = check([0.0, 0.3, 0.0, 0.0, 0.0, 0.0], 1.0);
        assert!(detector.is_contact(detector.residual(&[small])));
        assert!(!detector.is_contact(detector.residual(&[large])));
        assert!((detector.residual(&[large]) - 0.5).abs() < 1e-12);
        assert!(detector.residual(&[]) == 0.0);
        let broken = check([f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0], 0.1);
        assert!(detector.is_contact(detector.residual(&[broken])));
    }

    #[test]
    fn calibration_on_moves_sets_slope_and_threshold_from_free_motion() {
        // Deviations of 0.2 β (one move in 20 at 0.4 β), β from 0.05 to 1, alternating signs.
        let floor = 0.1;
        let motion: Vec<MoveCheck> = (0..40)
            .map(|i| {
                let bound = 1.0 - 0.95 * f64::from(i) / 39.0;
                let excess = if i % 20 == 7 { 0.4 } else { 0.2 };
                let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
                check([0.0, 0.0, 0.0, sign * excess * bound, 0.0, 0.0], bound)
            })
            .collect();
        let detector =
            CollisionDetector::calibrate_moves(&[&motion], 0.9, 2.0, floor).expect("enough");
        assert!(
            (detector.slope() - 0.2).abs() < 1e-9,
            "{}",
            detector.slope()
        );
        assert_eq!(detector.window(), CollisionDetector::DEFAULT_WINDOW);
        assert_eq!(detector.first_alarm(&motion), None);
        // The rare moves set the threshold above 1.
        assert!(detector.threshold() > 1.0);
        assert!(CollisionDetector::calibrate_moves(&[&motion[..5]], 0.9, 2.0, floor).is_err());
        assert!(CollisionDetector::calibrate_moves(&[&motion], 0.0, 2.0, floor).is_err());
        // Free motion within the noise floor leaves the threshold at 1: a persistent deviation
        // of 0.3 floor per move is caught on its fourth move, a single one never.
        let quiet: Vec<MoveCheck> = (0..20)
            .map(|i| {
                let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
                check([0.0, sign * 0.02, 0.0, 0.0, 0.0, 0.0], 0.0)
            })
            .collect();
        let detector =
            CollisionDetector::calibrate_moves(&[&quiet], 0.95, 2.0, floor).expect("enough");
        assert!((detector.threshold() - 1.0).abs() < 1e-12);
        let mut pushed = quiet.clone();
        pushed.extend((0..4).map(|_| check([0.0, 0.0, 0.03, 0.0, 0.0, 0.0], 0.0)));
        assert_eq!(detector.first_alarm(&pushed), Some(23));
        let mut once = quiet;
        once.push(check([0.0, 0.0, 0.09, 0.0, 0.0, 0.0], 0.0));
        assert_eq!(detector.first_alarm(&once), None);
    }

    #[test]
    fn newton_predicts_a_finite_move_where_the_first_order_guess_errs() {
        let model = KirchhoffModel::new(wire());
        let a = from_normalised(&wire(), &Vector6::new(0.5, 2.0, 1.0, -2.0, 3.0, 0.5));
        let solution = model.jacobian(&a).expect("solves");
        // A large step of the controller's kind: the motion of a known δa.
        let da = from_normalised(&wire(), &Vector6::new(0.1, -0.4, 0.3, 0.5, -0.2, 0.4));
        let exact_tip = model.tip(&(a + da)).expect("solves");
        let motion = solution.tip.inverse() * exact_tip;
        let first_order = solution
            .jacobian
            .lu()
            .solve(&se3::log(&motion))
            .expect("regular");
        let newton = predicted_change(&model, &a, &motion, &first_order);
        let error = |p: &Vector6<f64>| to_normalised(&wire(), &(p - da)).norm();
        assert!(error(&first_order) > 1e-3, "{}", error(&first_order));
        assert!(error(&newton) < 1e-7, "{}", error(&newton));
        // The check of that move, measured exactly: no deviation, and the bound holds the step.
        let check = MoveCheck::of_move(&model, &a, &(a + da), &motion, &first_order);
        assert!(check.miss() < 1e-7);
        assert!(check.bound >= check.step);
        assert!(check.bound >= to_normalised(&wire(), &first_order).norm() * (1.0 - 1e-9));
        assert!((check.step - to_normalised(&wire(), &da).norm()).abs() < 1e-7);
    }

    #[test]
    fn a_prediction_the_model_cannot_make_falls_back_to_the_first_order_guess() {
        let model = KirchhoffModel::new(wire());
        let guess = Vector6::new(0.0, 1.0, 0.0, 0.0, 0.0, 0.0);
        let outside = Vector6::repeat(f64::NAN);
        assert_eq!(
            predicted_change(&model, &outside, &Pose::identity(), &guess),
            guess
        );
    }
}
