//! The open-loop baselines of paper §IV-D, and the A-connectivity of a start–goal pair.
//!
//! - **Straight line in `A`:** `b(σ) = Γ(ā(σ))` along `ā(σ) = a_s + σ (a_g − a_s)`, at
//!   `σ = k / n`, rolled out with no feedback ([`straight_line_in_a`], [`roll_out`]).
//! - **Straight line in `B`:** `b(σ) = b_s exp(σ log(b_s⁻¹ b_g))` on SE(3)
//!   ([`straight_line_in_b`]; paper Fig. 7's dotted curve).

use ftwire_core::{Pose, Rig};
use ftwire_estimate::WireModel;
use ftwire_estimate::ft::FtCalibration;
use ftwire_rod::{Rod, se3};
use nalgebra::Vector6;

use crate::{ControlError, FtFeedback};

fn check_steps(steps: usize) -> Result<(), ControlError> {
    if steps == 0 {
        return Err(ControlError::NoSteps { steps });
    }
    Ok(())
}

/// The configurations `ā(k/n)`, `k = 0..=n`, of the straight line from `a_s` to `a_g`.
pub fn line_in_a(a_s: &Vector6<f64>, a_g: &Vector6<f64>, steps: usize) -> Vec<Vector6<f64>> {
    (0..=steps)
        .map(|k| a_s + (a_g - a_s) * (k as f64 / steps.max(1) as f64))
        .collect()
}

/// The poses `Γ(ā(k/n))`, `k = 0..=n`, of the straight line in `A` (second gripper relative to
/// the base clamp).
///
/// # Errors
/// [`ControlError::NoSteps`] for `steps = 0`; [`ControlError::Model`] when the model cannot be
/// solved on the line.
///
/// # Example
/// ```
/// use ftwire_control::open_loop::straight_line_in_a;
/// use ftwire_estimate::{KirchhoffModel, WireModel};
/// use ftwire_core::WireParams;
/// use nalgebra::Vector6;
/// let model = KirchhoffModel::new(WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015)?);
/// let (a_s, a_g) = (Vector6::new(0.0, 0.2, 0.1, -0.5, 0.3, 0.0), Vector6::new(0.0, 0.3, 0.1, -0.4, 0.3, 0.0));
/// let poses = straight_line_in_a(&model, &a_s, &a_g, 10)?;
/// assert_eq!(poses.len(), 11);
/// assert!((poses[10].translation.vector - model.tip(&a_g)?.translation.vector).norm() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn straight_line_in_a<M: WireModel>(
    model: &M,
    a_s: &Vector6<f64>,
    a_g: &Vector6<f64>,
    steps: usize,
) -> Result<Vec<Pose>, ControlError> {
    check_steps(steps)?;
    line_in_a(a_s, a_g, steps)
        .iter()
        .map(|a| model.tip(a).map_err(ControlError::from))
        .collect()
}

/// The poses `b_s exp(σ log(b_s⁻¹ b_g))` at `σ = k / n`, `k = 0..=n`: the straight line (the
/// screw motion) from `b_s` to `b_g` on SE(3).
///
/// # Errors
/// [`ControlError::NoSteps`] for `steps = 0`.
pub fn straight_line_in_b(b_s: &Pose, b_g: &Pose, steps: usize) -> Result<Vec<Pose>, ControlError> {
    check_steps(steps)?;
    let xi = se3::log(&(b_s.inverse() * b_g));
    Ok((0..=steps)
        .map(|k| b_s * se3::exp(&(xi * (k as f64 / steps as f64))))
        .collect())
}

/// Whether `a_s` and `a_g` are A-connected: `ā(σ) ∈ A_free` (stable, no self-intersection) at
/// `checks + 1` evenly spaced `σ ∈ [0, 1]`.
///
/// # Errors
/// [`ControlError::NoSteps`] for `checks = 0`; [`ControlError::Rod`] for a non-finite input.
pub fn a_connected(
    rod: &Rod,
    a_s: &Vector6<f64>,
    a_g: &Vector6<f64>,
    checks: usize,
) -> Result<bool, ControlError> {
    check_steps(checks)?;
    for a in line_in_a(a_s, a_g, checks) {
        match rod.solve(&a, ftwire_rod::DEFAULT_NODES) {
            Ok(solution) if solution.is_free() => {}
            Ok(_) | Err(ftwire_rod::RodError::OutsideA { .. }) => return Ok(false),
            Err(e) => return Err(e.into()),
        }
    }
    Ok(true)
}

/// What an open-loop roll-out did.
#[derive(Debug, Clone, PartialEq)]
pub struct RollOut {
    /// Moves completed.
    pub moves: usize,
    /// `ã` measured after each completed move (only recorded, never fed back), when a
    /// feedback was given and the measurement succeeded.
    pub measured: Vec<Option<Vector6<f64>>>,
    /// The move that failed and the rig's message, if one did (the roll-out stops there).
    pub failed: Option<(usize, String)>,
}

/// Commands the second gripper through `poses` (relative to the base clamp, the first one
/// skipped: it is the start) with no feedback on the wire; `feedback`, if given, only records
/// `ã` after each move. `observe(rig, k)` is called after move `k`.
///
/// The first move goes to `poses[1]` from wherever the rig starts; every later move applies the
/// plan's increment `δb_k = poses[k]⁻¹ poses[k+1]` to the pose the robot reports,
/// `b_{k+1} = b_k δb_k` (eq. 14 with the planned increments, as the paper rolls the open loop
/// out). A robot that reports the poses it was commanded (every noise model of
/// [`crate::NoisyRig`]) goes through the planned poses themselves; one that reports where an
/// error took it steps on from there, and its errors accumulate along the roll-out.
///
/// # Errors
/// [`ControlError::Rig`] when the rig cannot report its poses at the start; a failed move ends
/// the roll-out and is reported in [`RollOut::failed`].
pub fn roll_out<R: Rig, C: FtCalibration>(
    rig: &mut R,
    poses: &[Pose],
    feedback: Option<&FtFeedback<C>>,
    mut observe: impl FnMut(&R, usize),
) -> Result<RollOut, ControlError> {
    let rig_error = |e: R::Error| ControlError::Rig {
        message: e.to_string(),
    };
    let base = rig.gripper_poses().map_err(rig_error)?.base;
    let mut out = RollOut {
        moves: 0,
        measured: Vec::new(),
        failed: None,
    };
    // Where the last move was meant to end: the increments are the plan's from there.
    let mut last: Option<Pose> = None;
    for (k, target) in poses.iter().skip(1).enumerate() {
        let now = match rig.gripper_poses() {
            Ok(p) => p.relative(),
            Err(e) => {
                out.failed = Some((k, format!("the robot cannot report its pose: {e}")));
                break;
            }
        };
        let command = match last {
            Some(last) => now * (last.inverse() * target),
            None => *target,
        };
        if let Err(e) = rig.move_tip(base * command) {
            out.failed = Some((k, e.to_string()));
            break;
        }
        last = Some(*target);
        out.moves += 1;
        if let Some(feedback) = feedback {
            out.measured.push(feedback.measure(rig).ok().map(|m| m.a));
        }
        observe(rig, k);
    }
    Ok(out)
}
