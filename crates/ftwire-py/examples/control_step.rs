//! One step of `ftwire_control::Controller` computed by the Rust library alone: the reference
//! the Python bindings' `Controller.step` is compared with to the last digit
//! (`tests/test_control.py`).
//!
//! ```text
//! control_step C1 C2 C3 LENGTH RADIUS GAIN EPSILON A(6) GOAL(6) B(6)
//! ```
//!
//! Stiffnesses \[N·m²\], length and radius \[m\], the gain and ε; the measured configuration
//! and the goal, torque first \[N·m, N\], base clamp frame; the second gripper's pose now,
//! position \[m\] and rotation vector \[rad\]. Prints the next pose's homogeneous 4 × 4 matrix,
//! row-major, then the step's scale, one number a line (shortest round-trip form), or `none`
//! when no step passes the stability guard. Exit 2 on bad arguments.

use std::process::ExitCode;

use ftwire_control::{ControlParams, Controller};
use ftwire_core::{Pose, WireParams};
use ftwire_estimate::KirchhoffModel;
use ftwire_rod::{Load, Rod};
use nalgebra::{Translation3, UnitQuaternion, Vector3, Vector6};

/// The arguments' count: 7 numbers of the wire and controller, then 6 + 6 + 6.
const ARGUMENTS: usize = 25;

fn main() -> ExitCode {
    let numbers: Result<Vec<f64>, _> = std::env::args().skip(1).map(|s| s.parse()).collect();
    let numbers = match numbers {
        Ok(n) if n.len() == ARGUMENTS => n,
        _ => {
            eprintln!(
                "usage: control_step C1 C2 C3 LENGTH RADIUS GAIN EPSILON A(6) GOAL(6) B(6): \
                 {ARGUMENTS} numbers"
            );
            return ExitCode::from(2);
        }
    };
    match step(&numbers) {
        Ok(lines) => {
            println!("{lines}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("control_step: {e}");
            ExitCode::from(2)
        }
    }
}

/// The step for the numbers of the command line, as the lines to print.
fn step(n: &[f64]) -> Result<String, Box<dyn std::error::Error>> {
    let wire = WireParams::new([n[0], n[1], n[2]], n[3], n[4])?;
    let load = Load::none().with_natural_curvature(Vector3::zeros())?;
    let model = KirchhoffModel::from_rod(Rod::new(wire).with_load(load));
    let settings = ControlParams {
        gain: n[5],
        epsilon: n[6],
        ..ControlParams::default()
    };
    let controller = Controller::new(model, settings)?;
    let a = Vector6::from_column_slice(&n[7..13]);
    let goal = Vector6::from_column_slice(&n[13..19]);
    let b = Pose::from_parts(
        Translation3::new(n[19], n[20], n[21]),
        UnitQuaternion::from_scaled_axis(Vector3::new(n[22], n[23], n[24])),
    );
    Ok(match controller.plan_step(&a, &goal, &b)? {
        Some(plan) => {
            let m = plan.next_tip.to_homogeneous();
            let mut lines: Vec<String> = (0..4)
                .flat_map(|i| (0..4).map(move |k| (i, k)))
                .map(|(i, k)| format!("{:?}", m[(i, k)]))
                .collect();
            lines.push(format!("{:?}", plan.scale));
            lines.join("\n")
        }
        None => "none".to_owned(),
    })
}
