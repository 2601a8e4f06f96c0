//! The controller on a rig where the model is exact: convergence, every outcome, bad input,
//! determinism, and the first-order prediction the controller and the detector rely on.

mod common;

use common::{ModelRig, feedback, pair, settings, wire};
use ftwire_control::open_loop::{a_connected, roll_out, straight_line_in_a, straight_line_in_b};
use ftwire_control::{
    AnyPose, CollisionDetector, ControlError, ControlParams, Controller, MoveCheck, NoiseModel,
    NoiseParams, NoisyRig, Outcome, Reach, ReachCheck, retreat,
};
use ftwire_core::{Pose, WireParams};
use ftwire_estimate::{EstimateError, KirchhoffModel, WireModel};
use ftwire_rod::perturbation::{apply, delta_b};
use ftwire_rod::{JacobianSolution, Rod, Shape, from_normalised, to_normalised};
use nalgebra::{Vector3, Vector6};

fn controller() -> Controller<KirchhoffModel> {
    controller_with(settings())
}

fn controller_with(settings: ControlParams) -> Controller<KirchhoffModel> {
    Controller::new(KirchhoffModel::new(wire()), settings).expect("valid settings")
}

#[test]
fn the_pair_is_a_connected() {
    let (a_s, a_g) = pair();
    assert!(a_connected(&Rod::new(wire()), &a_s, &a_g, 20).expect("solves"));
}

#[test]
fn converges_on_an_exact_model_rig() {
    let (a_s, a_g) = pair();
    let mut rig = ModelRig::new(a_s);
    let run = controller()
        .run(&mut rig, &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    let Outcome::Reached { error } = run.outcome else {
        panic!("not reached: {:?}", run.outcome);
    };
    assert!(error < 1e-3);
    // The true configuration is the goal, and the step count is what K = 0.2 gives.
    assert!(to_normalised(&wire(), &(rig.a - a_g)).norm() < 1e-3);
    assert!(
        (20..=60).contains(&run.steps.len()),
        "{} steps",
        run.steps.len()
    );
    // On the exact model the detector's Newton prediction of every move is exact: the miss is
    // round-off, where the first-order guess `J⁻¹ δb` errs by the square of the step.
    for s in &run.steps {
        assert!(s.residual < 1.2, "residual {}", s.residual);
        assert!(s.miss < 1e-6, "miss {}", s.miss);
    }
    let first = &run.steps[0];
    let guess = to_normalised(
        &wire(),
        &(first.measured - first.a - first.plan.predicted_da),
    );
    assert!(guess.norm() > 1e3 * first.miss.max(1e-12));
}

/// Runs with `settle_radius` on a rig with noisy readings, one per seed: how many reached an
/// ε of 0.015 (normalised) and the mean true distance from the goal where those stopped.
fn settled_runs(settle_radius: f64, runs: u64) -> (usize, f64) {
    let (a_s, a_g) = pair();
    let w = wire();
    // 0.03 normalised units of noise per channel on one sample: 0.017 on the feedback's
    // 3-sample mean, about 0.04 in norm, well above ε.
    let std = from_normalised(&w, &Vector6::repeat(0.03));
    let settings = ControlParams {
        epsilon: 0.015,
        max_iterations: 120,
        settle_radius,
        settle_samples: 192,
        ..ControlParams::default()
    };
    let controller = Controller::new(KirchhoffModel::new(w), settings).expect("valid settings");
    let mut errors = Vec::new();
    for seed in 0..runs {
        let mut rig = ModelRig::new(a_s).with_noise(std, seed);
        let run = controller
            .run(&mut rig, &feedback(), &mut AnyPose, &a_g)
            .expect("runs");
        if matches!(run.outcome, Outcome::Reached { .. }) {
            errors.push(to_normalised(&w, &(rig.a - a_g)).norm());
        }
    }
    let mean = errors.iter().sum::<f64>() / errors.len().max(1) as f64;
    (errors.len(), mean)
}

#[test]
fn longer_rests_near_the_goal_let_the_loop_stop_at_a_small_epsilon() {
    // The feedback's own 3-sample mean is noisier than ε: a run without settling stops only
    // on a lucky reading, if at all. 64 times the samples within the settling radius cut the
    // noise by 8, and every run stops within ε of the goal in truth.
    let runs = 10;
    let (plain, _) = settled_runs(0.0, runs);
    let (settled, error) = settled_runs(0.25, runs);
    assert_eq!(settled, runs as usize, "settled runs that reached ε");
    assert!(plain < settled / 2, "{plain} plain runs reached ε");
    assert!(
        error < 0.015,
        "settled runs stopped {error:.4} from the goal"
    );
}

#[test]
fn the_first_order_prediction_matches_finite_moves() {
    // δb = J(L) δa (eq. 11) through eq. 8's M: the error of b M(J δa) against Γ(a + δa) is
    // second order in δa, which the controller's prediction and the detector rely on.
    let rod = Rod::new(wire());
    let (a, _) = pair();
    let j = rod.jacobian(&a).expect("solves");
    let direction = from_normalised(&wire(), &Vector6::new(0.3, -0.5, 0.2, 0.4, 0.1, -0.6));
    let mut previous = f64::INFINITY;
    for h in [1e-2, 5e-3, 2.5e-3] {
        let exact = rod.tip(&(a + direction * h)).expect("solves");
        let predicted = apply(&j.tip, &(j.jacobian * direction * h));
        let miss = delta_b(&predicted, &exact).norm();
        assert!(miss < previous / 3.0, "h = {h}: {miss} after {previous}");
        previous = miss;
    }
}

#[test]
fn the_iteration_limit_ends_a_run() {
    let (a_s, a_g) = pair();
    let controller = controller_with(ControlParams {
        max_iterations: 3,
        ..settings()
    });
    let run = controller
        .run(&mut ModelRig::new(a_s), &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    assert!(matches!(run.outcome, Outcome::IterationLimit { error } if error > 0.1));
    assert_eq!(run.steps.len(), 3);
}

/// Reachable for the first `n` queries, then not.
struct ReachFor(usize);

impl ReachCheck for ReachFor {
    fn check(&mut self, _relative: &Pose) -> Reach {
        if self.0 == 0 {
            return Reach::Unreachable("out of reach".into());
        }
        self.0 -= 1;
        Reach::Reachable
    }
}

#[test]
fn an_unreachable_pose_stops_the_run_before_moving_there() {
    let (a_s, a_g) = pair();
    let mut rig = ModelRig::new(a_s);
    let run = controller()
        .run(&mut rig, &feedback(), &mut ReachFor(3), &a_g)
        .expect("runs");
    assert!(matches!(run.outcome, Outcome::Unreachable { step: 2, .. }));
    assert_eq!(rig.moves, 2);
}

/// Reachable within `radius` \[m\] of the first queried pose (the start), as an arm near a
/// joint limit.
struct ReachWithin {
    radius: f64,
    start: Option<Pose>,
}

impl ReachCheck for ReachWithin {
    fn check(&mut self, relative: &Pose) -> Reach {
        let start = *self.start.get_or_insert(*relative);
        let moved = (relative.translation.vector - start.translation.vector).norm();
        if moved <= self.radius {
            Reach::Reachable
        } else {
            Reach::Unreachable(format!("{moved} m from the start"))
        }
    }
}

#[test]
fn an_unreachable_step_is_halved_until_the_robot_can_reach_it() {
    let (a_s, a_g) = pair();
    let mut rig = ModelRig::new(a_s);
    let controller = controller();
    let start = ftwire_core::Rig::gripper_poses(&rig)
        .expect("poses")
        .relative();
    let full = controller
        .plan_step(&a_s, &a_g, &start)
        .expect("solves")
        .expect("stable");
    let reach_full = (full.next_tip.translation.vector - start.translation.vector).norm();
    // The full first step is out of reach, its half is not.
    let mut reach = ReachWithin {
        radius: 0.6 * reach_full,
        start: None,
    };
    let run = controller
        .run(&mut rig, &feedback(), &mut reach, &a_g)
        .expect("runs");
    let first = run.steps.first().expect("the run moves");
    assert!((first.plan.scale - 0.5 * full.scale).abs() < 1e-12);
    assert!((first.plan.predicted_da - 0.5 * full.predicted_da).norm() < 1e-12);
    assert!(rig.moves >= 2, "{} moves, {:?}", rig.moves, run.outcome);
}

/// The exact model, except that nothing but the listed configurations is stable.
#[derive(Clone)]
struct OnlyStableAt(KirchhoffModel, Vec<Vector6<f64>>);

impl WireModel for OnlyStableAt {
    fn wire(&self) -> &WireParams {
        self.0.wire()
    }
    fn with_wire(&self, wire: WireParams) -> Self {
        Self(self.0.with_wire(wire), self.1.clone())
    }
    fn weight_per_length(&self) -> Vector3<f64> {
        self.0.weight_per_length()
    }
    fn with_weight_per_length(&self, w: Vector3<f64>) -> Result<Self, EstimateError> {
        Ok(Self(self.0.with_weight_per_length(w)?, self.1.clone()))
    }
    fn tip(&self, a: &Vector6<f64>) -> Result<Pose, EstimateError> {
        self.0.tip(a)
    }
    fn jacobian(&self, a: &Vector6<f64>) -> Result<JacobianSolution, EstimateError> {
        self.0.jacobian(a)
    }
    fn shape(&self, a: &Vector6<f64>, nodes: usize) -> Result<Shape, EstimateError> {
        self.0.shape(a, nodes)
    }
    fn is_stable(&self, a: &Vector6<f64>) -> Result<bool, EstimateError> {
        Ok(self.1.contains(a))
    }
}

#[test]
fn a_predicted_instability_stops_the_run_without_moving() {
    let (a_s, a_g) = pair();
    // Stable where it stands, and every step toward the goal predicted out of A_stable.
    let model = OnlyStableAt(KirchhoffModel::new(wire()), vec![a_s, a_g]);
    let controller = Controller::new(model, settings()).expect("valid");
    let mut rig = ModelRig::new(a_s);
    let run = controller
        .run(&mut rig, &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    assert_eq!(run.outcome, Outcome::PredictedInstability { step: 0 });
    assert_eq!(rig.moves, 0);
}

#[test]
fn measured_outside_a_stable_the_controller_steps_back_toward_the_goal() {
    let (a_s, a_g) = pair();
    // The start is outside the model's A_stable (a noisy measurement, or a wire the model
    // calls unstable): the guard, which keeps a stable wire stable, does not strand it there.
    let model = OnlyStableAt(KirchhoffModel::new(wire()), vec![a_g]);
    let controller = Controller::new(model, settings()).expect("valid");
    let mut rig = ModelRig::new(a_s);
    let run = controller
        .run(&mut rig, &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    assert!(rig.moves > 0, "{:?}", run.outcome);
    let first = run.steps.first().expect("a step");
    assert!(
        controller.distance(&first.measured, &a_g) < controller.distance(&a_s, &a_g),
        "the first step moves toward the goal"
    );
}

#[test]
fn the_step_limits_and_the_stability_guard_bound_each_step() {
    let (a_s, a_g) = pair();
    let s = ControlParams {
        max_translation: 0.01,
        max_rotation: 0.02,
        ..settings()
    };
    let controller = Controller::new(KirchhoffModel::new(wire()), s).expect("valid");
    let plan = controller
        .plan_step(&a_s, &a_g, &Pose::identity())
        .expect("solves")
        .expect("stable");
    assert!(plan.delta_b.fixed_rows::<3>(0).norm() <= 0.02 + 1e-12);
    assert!(plan.delta_b.fixed_rows::<3>(3).norm() <= 0.01 + 1e-12);
    assert!(plan.scale < 1.0);
    assert!((plan.predicted_da - plan.scale * 0.2 * (a_g - a_s)).norm() < 1e-12);
}

fn calibrated_detector() -> CollisionDetector {
    let (a_s, a_g) = pair();
    let free = controller()
        .run(&mut ModelRig::new(a_s), &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    let residuals: Vec<f64> = free.steps.iter().map(|s| s.residual).collect();
    CollisionDetector::calibrate(&residuals, 2.0, 0.01).expect("enough residuals")
}

#[test]
fn a_contact_is_detected_at_once_and_the_retreat_finds_agreement() {
    let (a_s, a_g) = pair();
    let detector = calibrated_detector();
    let mut rig = ModelRig::new(a_s);
    // From move 5 on, a contact pushes 0.5 normalised units of force on the wire, growing.
    let push = from_normalised(&wire(), &Vector6::new(0.0, 0.0, 0.0, 0.5, -0.5, 0.0));
    rig.contact = Some((5, push));
    let controller = controller().with_detector(detector);
    let run = controller
        .run(&mut rig, &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    let Outcome::CollisionDetected { step, residual } = run.outcome else {
        panic!("not detected: {:?}", run.outcome);
    };
    assert_eq!(step, 4, "the move that made contact is detected");
    assert!(residual > detector.threshold());
    // Retreat: the contact stays while the rig has made ≥ 5 moves, so no pose agrees and the
    // retreat goes back to the start; a rig whose contact clears on the way back agrees.
    rig.contact = None;
    let back = retreat(&mut rig, &feedback(), &run, &wire(), 1e-3).expect("retreats");
    assert!(back.agreed);
    assert_eq!(back.to_pose, 4);
    assert_eq!(back.moves, 1);
}

#[test]
fn a_quantile_calibration_ignores_rare_outliers() {
    let mut residuals = vec![0.1; 99];
    residuals.push(50.0);
    let all = CollisionDetector::calibrate(&residuals, 2.0, 0.01).expect("enough");
    assert!((all.threshold() - 100.0).abs() < 1e-12);
    let robust =
        CollisionDetector::calibrate_quantile(&residuals, 0.95, 2.0, 0.01).expect("enough");
    assert!((robust.threshold() - 0.2).abs() < 1e-12);
    assert!(CollisionDetector::calibrate_quantile(&residuals, 0.0, 2.0, 0.01).is_err());
    assert!(CollisionDetector::calibrate(&residuals[..5], 2.0, 0.01).is_err());
}

#[test]
fn a_free_motion_gives_no_false_alarm() {
    let (a_s, a_g) = pair();
    let controller = controller().with_detector(calibrated_detector());
    let run = controller
        .run(&mut ModelRig::new(a_s), &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    assert!(matches!(run.outcome, Outcome::Reached { .. }));
}

#[test]
fn sensor_and_rig_faults_are_outcomes() {
    let (a_s, a_g) = pair();
    let mut rig = ModelRig::new(a_s);
    rig.dropout_after = Some(2);
    let run = controller()
        .run(&mut rig, &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    assert!(matches!(run.outcome, Outcome::SensorFault { step: 2, .. }));

    let mut rig = ModelRig::new(a_s);
    rig.refuse_after = Some(1);
    let run = controller()
        .run(&mut rig, &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    assert!(matches!(
        run.outcome,
        Outcome::CommandFailed { step: 1, .. }
    ));
    assert_eq!(rig.moves, 1);

    let mut rig = ModelRig::new(a_s);
    rig.zeros_after = Some(1);
    let run = controller()
        .run(&mut rig, &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    assert!(
        matches!(run.outcome, Outcome::ModelFailed { step: 1, .. }),
        "{:?}",
        run.outcome
    );
}

#[test]
fn a_reading_that_runs_away_two_rests_in_a_row_stops_the_run_as_diverged() {
    let (a_s, a_g) = pair();
    // From the second move on, a wrench 20 normalised units larger at every move.
    let runaway = from_normalised(&wire(), &Vector6::new(0.0, 0.0, 0.0, 20.0, 0.0, 0.0));
    let rig = || ModelRig {
        contact: Some((2, runaway)),
        ..ModelRig::new(a_s)
    };
    let watching = controller_with(ControlParams {
        divergence: 5.0,
        ..settings()
    });
    let mut stopped = rig();
    let run = watching
        .run(&mut stopped, &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    // Beyond at the rests after moves 2 and 3: stopped there, after the third move (step 2).
    let Outcome::Diverged { step, error } = run.outcome else {
        panic!("not diverged: {:?}", run.outcome);
    };
    assert_eq!((step, stopped.moves), (2, 3));
    assert!(error > 5.0 + watching.distance(&run.start_estimate, &a_g));
    assert_eq!(run.outcome.name(), "diverged");
    // Off (the default), the same rig runs on.
    let mut unwatched = rig();
    let run = controller()
        .run(&mut unwatched, &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    assert!(!matches!(run.outcome, Outcome::Diverged { .. }));
    assert!(unwatched.moves > 3);
    // One rest beyond is noise the next step corrects: a reading thrown once does not stop
    // the run. (Short steps here, so that the move made on the thrown reading does not itself
    // carry the wire away.)
    let short = controller_with(ControlParams {
        divergence: 5.0,
        max_translation: 0.002,
        max_rotation: 0.01,
        max_iterations: 10,
        ..settings()
    });
    let mut thrown = ModelRig {
        spike: Some((2, runaway)),
        ..ModelRig::new(a_s)
    };
    let run = short
        .run(&mut thrown, &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    assert!(
        matches!(run.outcome, Outcome::IterationLimit { .. }),
        "{:?}",
        run.outcome
    );
    assert_eq!(thrown.moves, 10);
    let bad = Controller::new(
        KirchhoffModel::new(wire()),
        ControlParams {
            divergence: -1.0,
            ..settings()
        },
    );
    assert!(
        matches!(
            bad,
            Err(ControlError::BadSetting {
                name: "divergence",
                ..
            })
        ),
        "{bad:?}"
    );
}

#[test]
fn bad_input_is_refused_before_any_motion() {
    let (a_s, a_g) = pair();
    let mut rig = ModelRig::new(a_s);
    let mut goal = a_g;
    goal[4] = f64::NAN;
    let e = controller()
        .run(&mut rig, &feedback(), &mut AnyPose, &goal)
        .expect_err("non-finite goal");
    assert!(
        matches!(e, ControlError::NonFiniteGoal { index: 4, .. }),
        "{e}"
    );
    // Compressed far beyond the buckling load: not in A_stable.
    let buckled = from_normalised(&wire(), &Vector6::new(0.0, 0.0, 0.1, -80.0, 0.0, 0.0));
    let e = controller()
        .run(&mut rig, &feedback(), &mut AnyPose, &buckled)
        .expect_err("unstable goal");
    assert!(matches!(e, ControlError::GoalUnstable { .. }), "{e}");
    assert!(e.to_string().contains("A_stable"));
    let e = controller()
        .run(&mut rig, &feedback(), &mut ReachFor(0), &a_g)
        .expect_err("unreachable start");
    assert!(matches!(e, ControlError::UnreachableStart { .. }), "{e}");
    assert_eq!(rig.moves, 0);
    let e = Controller::new(
        KirchhoffModel::new(wire()),
        ControlParams {
            gain: 0.0,
            ..settings()
        },
    )
    .expect_err("zero gain");
    assert!(e.to_string().contains("gain"), "{e}");
}

#[test]
fn noisy_runs_are_deterministic_and_the_closed_loop_beats_the_offset() {
    let (a_s, a_g) = pair();
    let run_once = || {
        let rig = NoisyRig::new(
            ModelRig::new(a_s),
            NoiseModel::Offset,
            NoiseParams::default(),
            11,
        )
        .expect("valid");
        let mut rig = rig;
        let controller =
            Controller::new(KirchhoffModel::new(wire()), ControlParams::default()).expect("valid");
        let run = controller
            .run(&mut rig, &feedback(), &mut AnyPose, &a_g)
            .expect("runs");
        (run, rig.inner().a)
    };
    let (first, a_first) = run_once();
    let (second, a_second) = run_once();
    let trace = |run: &ftwire_control::Run| -> Vec<(Vector6<f64>, Vector6<f64>, f64)> {
        run.steps
            .iter()
            .map(|s| (s.a, s.measured, s.residual))
            .collect()
    };
    assert_eq!(first.outcome, second.outcome);
    assert_eq!(trace(&first), trace(&second));
    assert_eq!(a_first, a_second);
    // The closed loop removes the offset: the true configuration is at the goal.
    assert!(matches!(first.outcome, Outcome::Reached { .. }));
    assert!(to_normalised(&wire(), &(a_first - a_g)).norm() < 0.06);

    // The open loop cannot: it ends off the goal by the offset.
    let model = KirchhoffModel::new(wire());
    let poses = straight_line_in_a(&model, &a_s, &a_g, first.steps.len()).expect("solves");
    let mut rig = NoisyRig::new(
        ModelRig::new(a_s),
        NoiseModel::Offset,
        NoiseParams::default(),
        11,
    )
    .expect("valid");
    let out = roll_out(&mut rig, &poses, Some(&feedback()), |_, _| {}).expect("rolls out");
    assert_eq!(out.moves, poses.len() - 1);
    assert!(to_normalised(&wire(), &(rig.inner().a - a_g)).norm() > 0.2);
}

#[test]
fn open_loop_without_noise_reaches_the_goal_on_both_lines() {
    let (a_s, a_g) = pair();
    let model = KirchhoffModel::new(wire());
    let poses = straight_line_in_a(&model, &a_s, &a_g, 10).expect("solves");
    let mut rig = ModelRig::new(a_s);
    roll_out(&mut rig, &poses, Some(&feedback()), |_, _| {}).expect("rolls out");
    assert!(to_normalised(&wire(), &(rig.a - a_g)).norm() < 1e-6);

    let line = straight_line_in_b(&poses[0], &poses[10], 10).expect("steps");
    assert!(delta_b(&line[0], &poses[0]).norm() < 1e-12);
    assert!(delta_b(&line[10], &poses[10]).norm() < 1e-12);
    assert!(straight_line_in_b(&poses[0], &poses[10], 0).is_err());
}

#[test]
fn the_shape_stop_ends_a_run_at_the_first_shape_within_its_tolerance() {
    let (a_s, a_g) = pair();
    let model = KirchhoffModel::new(wire());
    let tolerance = 0.005;
    let shaped = Controller::new(
        model,
        ControlParams {
            epsilon: 1e-9,
            shape_tolerance: tolerance,
            ..ControlParams::default()
        },
    )
    .expect("valid settings");
    let mut rig = ModelRig::new(a_s);
    let run = shaped
        .run(&mut rig, &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    assert!(
        matches!(run.outcome, Outcome::Reached { .. }),
        "{:?}",
        run.outcome
    );
    let goal = model.shape(&a_g, 50).expect("solves").positions;
    let distance = |a: &Vector6<f64>| shaped.shape_distance(a, &goal).expect("solves");
    // Stopped where the shape holds, and not a step earlier.
    let last = run.last_estimate();
    assert!(distance(&last) < tolerance, "{}", distance(&last));
    let before = run
        .steps
        .iter()
        .rev()
        .nth(1)
        .map_or(run.start_estimate, |s| s.estimate);
    assert!(distance(&before) >= tolerance, "{}", distance(&before));
    // The model rig is exact: the true wire is where the model says.
    let truth = model.shape(&rig.a, 50).expect("solves").positions;
    let true_distance = ftwire_estimate::shape::centreline_distance(&truth, &goal, 50).expect("ok");
    assert!(true_distance < tolerance * 1.01, "{true_distance}");
    // ε alone runs on (the shape stop replaced it above).
    let plain = Controller::new(
        model,
        ControlParams {
            epsilon: 1e-9,
            ..ControlParams::default()
        },
    )
    .expect("valid settings")
    .run(&mut ModelRig::new(a_s), &feedback(), &mut AnyPose, &a_g)
    .expect("runs");
    assert!(plain.steps.len() > run.steps.len() + 5);
}

#[test]
fn a_bad_shape_tolerance_is_refused_by_name() {
    for value in [-0.001, f64::NAN, f64::INFINITY] {
        for (field, settings) in [
            (
                "shape_tolerance",
                ControlParams {
                    shape_tolerance: value,
                    ..ControlParams::default()
                },
            ),
            (
                "late_shape_tolerance",
                ControlParams {
                    late_shape_tolerance: value,
                    ..ControlParams::default()
                },
            ),
        ] {
            let err = Controller::new(KirchhoffModel::new(wire()), settings).expect_err("refused");
            assert!(
                matches!(err, ControlError::BadSetting { name, .. } if name == field),
                "{field}: {err:?}"
            );
        }
    }
}

#[test]
fn the_late_shape_stop_applies_from_its_step_on_and_never_before() {
    let (a_s, a_g) = pair();
    let model = KirchhoffModel::new(wire());
    let (tight, late, after) = (1e-12, 0.005, 3);
    let settings = ControlParams {
        epsilon: 1e-12,
        shape_tolerance: tight,
        late_shape_tolerance: late,
        late_after: after,
        ..ControlParams::default()
    };
    assert_eq!(settings.shape_stop_at(after - 1), tight);
    assert_eq!(settings.shape_stop_at(after), late);
    // Never tighter than the shape stop.
    let looser = ControlParams {
        shape_tolerance: 0.01,
        ..settings
    };
    assert_eq!(looser.shape_stop_at(after), 0.01);
    let controller = Controller::new(model, settings).expect("valid settings");
    let goal = model.shape(&a_g, 50).expect("solves").positions;
    let distance = |a: &Vector6<f64>| controller.shape_distance(a, &goal).expect("solves");
    let run = controller
        .run(&mut ModelRig::new(a_s), &feedback(), &mut AnyPose, &a_g)
        .expect("runs");
    assert!(
        matches!(run.outcome, Outcome::Reached { .. }),
        "{:?}",
        run.outcome
    );
    // Stopped at the first estimate from step `after` on within the late stop.
    let estimates: Vec<Vector6<f64>> = std::iter::once(run.start_estimate)
        .chain(run.steps.iter().map(|s| s.estimate))
        .collect();
    let stop = estimates.len() - 1;
    assert!(stop >= after, "stopped at step {stop}");
    assert!(distance(&estimates[stop]) < late);
    for (k, a) in estimates.iter().enumerate().take(stop).skip(after) {
        assert!(distance(a) >= late, "step {k}: {}", distance(a));
    }
    // The tight stop alone runs on past it.
    let tight_only = Controller::new(
        model,
        ControlParams {
            late_shape_tolerance: 0.0,
            ..settings
        },
    )
    .expect("valid settings")
    .run(&mut ModelRig::new(a_s), &feedback(), &mut AnyPose, &a_g)
    .expect("runs");
    assert!(tight_only.steps.len() > run.steps.len());
}

/// The detector from free moves: its floor five times the median noise (the default when the
/// noise is unknown), its threshold above every free residual but an outlier's, and too few
/// moves refused.
#[test]
fn a_detector_from_free_moves_takes_its_floor_from_the_noise() {
    let moves: Vec<MoveCheck> = (0..40)
        .map(|i| {
            let e = 0.002 * f64::from(i % 7);
            MoveCheck {
                deviation: Vector6::new(e, 0.0, 0.0, 0.0, 0.0, 0.0),
                step: 0.05,
                bound: 0.05,
            }
        })
        .collect();
    let (detector, floor) =
        CollisionDetector::from_free_moves(&[0.004, 0.002, f64::NAN, 0.003], &[&moves])
            .expect("forty free moves calibrate a detector");
    assert!((floor - CollisionDetector::FLOOR_SIGMAS * 0.003).abs() < 1e-15);
    assert!(detector.threshold() >= 1.0);
    assert!(!detector.is_contact(detector.residual(&moves)));
    let (_, unknown) = CollisionDetector::from_free_moves(&[], &[&moves]).expect("calibrated");
    assert_eq!(unknown, CollisionDetector::DEFAULT_FLOOR);
    assert!(matches!(
        CollisionDetector::from_free_moves(&[0.003], &[&moves[..3]]),
        Err(ControlError::TooFewResiduals { .. })
    ));
}
