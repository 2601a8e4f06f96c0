//! Retreat after a detected contact (beyond the paper): back along the run's last poses to the
//! last configuration where the wire again agrees with what was measured there before.

use ftwire_core::WireParams;
use ftwire_core::{Pose, Rig};
use ftwire_estimate::ft::FtCalibration;
use ftwire_rod::to_normalised;
use nalgebra::Vector6;
use serde::Serialize;

use crate::{ControlError, FtFeedback, Run};

/// The result of [`retreat`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Retreat {
    /// Index of the pose retreated to: 0 is the run's start, `k` the pose after step `k − 1`.
    pub to_pose: usize,
    /// Whether the `ã` measured there agrees with the one recorded on the way out.
    pub agreed: bool,
    /// Moves made.
    pub moves: usize,
    /// `‖ã − ã_recorded‖` at the last pose, normalised.
    pub mismatch: f64,
}

/// Moves the second gripper back through the poses of `run`, from the last pose before its
/// final step down to its start, measuring `ã` at each, and stops at the first pose whose
/// `ã` is within `tolerance` (normalised units) of the `ã` recorded there on the way out.
///
/// # Errors
/// [`ControlError::BadSetting`] for a bad tolerance; [`ControlError::Rig`] when the rig fails
/// a move or the F/T pipeline fails a measurement.
pub fn retreat<R: Rig, C: FtCalibration>(
    rig: &mut R,
    feedback: &FtFeedback<C>,
    run: &Run,
    wire: &WireParams,
    tolerance: f64,
) -> Result<Retreat, ControlError> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(ControlError::BadSetting {
            name: "tolerance",
            value: tolerance,
            allowed: "a finite number > 0",
        });
    }
    let rig_error = |message: String| ControlError::Rig { message };
    let base = rig
        .gripper_poses()
        .map_err(|e| rig_error(e.to_string()))?
        .base;
    // Pose k and the ã recorded there: the start, then after each step.
    let mut poses: Vec<(Pose, Vector6<f64>)> = vec![(run.start_tip, run.start)];
    poses.extend(run.steps.iter().map(|s| (s.tip, s.measured)));
    // The last pose is the one the contact was detected at: leave it.
    let last = poses.len().saturating_sub(1);
    let mut result = Retreat {
        to_pose: last,
        agreed: false,
        moves: 0,
        mismatch: f64::NAN,
    };
    for k in (0..last).rev() {
        let (pose, recorded) = poses[k];
        rig.move_tip(base * pose)
            .map_err(|e| rig_error(format!("retreating to pose {k}: {e}")))?;
        let measured = feedback
            .measure(rig)
            .map_err(|e| rig_error(format!("measuring at pose {k}: {e}")))?;
        result.moves += 1;
        result.to_pose = k;
        result.mismatch = to_normalised(wire, &(measured.a - recorded)).norm();
        if result.mismatch <= tolerance {
            result.agreed = true;
            break;
        }
    }
    Ok(result)
}
