//! `PathTracker` on a rig that is not the simulator (the Kirchhoff model itself, see
//! `common`): it reaches the goal within the policy's tolerance, calls the observer at every
//! rest, and retreats after a detected contact as its policy allows.

mod common;

use common::{ModelRig, feedback, pair, wire};
use ftwire_control::open_loop::line_in_a;
use ftwire_control::{
    AnyPose, CollisionDetector, ControlError, NoiseModel, Outcome, PathTracker, RestKind, TrackEnd,
    Tracked, TrackingPolicy,
};
use ftwire_estimate::KirchhoffModel;
use ftwire_rod::to_normalised;
use nalgebra::Vector6;

/// The pair's straight line in `A`, start included, in `legs` legs.
fn path(legs: usize) -> Vec<Vector6<f64>> {
    let (a_s, a_g) = pair();
    line_in_a(&a_s, &a_g, legs)
}

fn tracker(noise: NoiseModel) -> PathTracker<KirchhoffModel> {
    PathTracker::new(
        KirchhoffModel::new(wire()),
        TrackingPolicy::for_noise(noise),
    )
}

/// Tracks `waypoints` on `rig`, counting the rests of each kind.
fn track(
    tracker: &PathTracker<KirchhoffModel>,
    rig: &mut ModelRig,
    waypoints: &[Vector6<f64>],
) -> (Tracked, Vec<RestKind>) {
    let mut rests = Vec::new();
    let tracked = tracker
        .track(rig, &feedback(), &mut AnyPose, waypoints, |_, rest| {
            rests.push(rest.kind);
        })
        .expect("tracks");
    (tracked, rests)
}

fn count(rests: &[RestKind], kind: RestKind) -> usize {
    rests.iter().filter(|&&k| k == kind).count()
}

#[test]
fn a_path_on_a_model_rig_ends_at_the_goal_within_the_policys_tolerance() {
    let waypoints = path(4);
    let mut rig = ModelRig::new(waypoints[0]);
    let tracker = tracker(NoiseModel::None);
    let (tracked, rests) = track(&tracker, &mut rig, &waypoints);
    assert!(tracked.completed, "{:?}", tracked.end);
    assert!(matches!(
        tracked.end,
        Some(TrackEnd::Leg(Outcome::Reached { .. }))
    ));
    // The true configuration (the rig's, which the tracker never saw) is at the goal.
    let goal = waypoints[4];
    let error = to_normalised(&wire(), &(rig.a - goal)).norm();
    let verdict = tracker.policy().judge(tracked.completed, false, error);
    assert!(verdict.success && verdict.at_goal, "true error {error}");
    assert!(error < tracker.policy().goal.epsilon + 1e-9, "{error}");
    // One leg a waypoint, each scored; the observer saw the start, every move, every end.
    assert_eq!(tracked.legs.len(), 4);
    assert_eq!(tracked.scored, vec![0, 1, 2, 3]);
    assert_eq!(
        tracked.legs.iter().map(|l| l.waypoint).collect::<Vec<_>>(),
        vec![1, 2, 3, 4]
    );
    assert_eq!(count(&rests, RestKind::Start), 1);
    assert_eq!(count(&rests, RestKind::Step), tracked.moves);
    assert_eq!(count(&rests, RestKind::LegEnd), 4);
    assert_eq!(rests.len(), 1 + tracked.moves + 4);
    assert_eq!(
        tracked.moves,
        tracked.legs.iter().map(|l| l.moves).sum::<usize>()
    );
    assert_eq!(tracked.residuals.len(), tracked.moves);
    assert_eq!(rig.moves, tracked.moves);
    // The estimate it last steered by is the measured goal.
    assert!(to_normalised(&wire(), &(tracked.last_estimate - goal)).norm() < 0.05);
}

#[test]
fn a_persistent_contact_is_retreated_from_as_often_as_the_policy_allows() {
    let waypoints = path(3);
    // A detector calibrated on the free path's residuals, as a robot's rehearsal does.
    let mut free = ModelRig::new(waypoints[0]);
    let (rehearsal, _) = track(&tracker(NoiseModel::Offset), &mut free, &waypoints);
    let detector = CollisionDetector::calibrate(
        &rehearsal.residuals,
        CollisionDetector::DEFAULT_MARGIN,
        CollisionDetector::DEFAULT_FLOOR,
    )
    .expect("enough residuals");
    // From the fourth move on, a contact pushes on the wire harder with every move.
    let mut rig = ModelRig::new(waypoints[0]);
    rig.contact = Some((4, Vector6::new(0.0, 0.0, 0.0, 0.5, -0.5, 0.5)));
    let armed = tracker(NoiseModel::Offset).with_detector(detector);
    let (tracked, rests) = track(&armed, &mut rig, &waypoints);
    let policy = armed.policy();
    assert!(tracked.detected);
    assert!(!tracked.completed);
    assert_eq!(tracked.retreats, policy.max_retreats);
    assert!(matches!(
        tracked.end,
        Some(TrackEnd::Leg(Outcome::CollisionDetected { .. }))
    ));
    // Each retreat is one move outside a leg, reported as such, and unscores its leg.
    assert_eq!(count(&rests, RestKind::Retreat), tracked.retreats);
    assert_eq!(
        tracked.moves,
        tracked.legs.iter().map(|l| l.moves).sum::<usize>() + tracked.retreats
    );
    let unscored = tracked.legs.iter().filter(|l| !l.scored).count();
    assert_eq!(unscored, tracked.retreats);
    assert_eq!(tracked.scored.len(), tracked.legs.len() - unscored);
}

#[test]
fn a_rig_that_refuses_a_move_ends_the_path_there() {
    let waypoints = path(3);
    let mut rig = ModelRig::new(waypoints[0]);
    rig.refuse_after = Some(5);
    let (tracked, rests) = track(&tracker(NoiseModel::None), &mut rig, &waypoints);
    assert!(!tracked.completed);
    assert!(matches!(
        tracked.end,
        Some(TrackEnd::Leg(Outcome::CommandFailed { .. }))
    ));
    assert_eq!(tracked.moves, 5);
    assert_eq!(count(&rests, RestKind::Step), 5);
}

#[test]
fn an_empty_path_is_refused() {
    let mut rig = ModelRig::new(pair().0);
    let err = tracker(NoiseModel::None)
        .track(&mut rig, &feedback(), &mut AnyPose, &[], |_, _| {})
        .expect_err("nothing to track");
    assert!(matches!(err, ControlError::EmptyPath));
    // A path of its start alone: nothing to do, nothing done.
    let (tracked, rests) = track(&tracker(NoiseModel::None), &mut rig, &[pair().0]);
    assert_eq!((tracked.moves, tracked.end, rests.len()), (0, None, 1));
}
