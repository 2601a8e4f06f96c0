//! The simulator's truth at a tracked wire's rests: whether it touches an obstacle (the one
//! definition every experiment scores), its centreline and base wrench, and the log the
//! closed loop's observer keeps of them.

use ftwire_control::{Rest, RestKind, Tracked};
use ftwire_estimate::shape::{DEFAULT_METRIC_SAMPLES, centreline_distance};
use ftwire_plan::Waypoint;
use ftwire_sim::SimRig;
use nalgebra::{Point3, Vector3, Vector6};

use super::attempt::{Attempt, Leg};
use crate::error::LabError;

/// The one definition of a touch, the lab's (every experiment that scores one shares it).
pub use crate::experiment::rig::{CONTACT_FORCE, touches};

/// Truth of the rig at a rest: contact, centreline, base wrench.
pub(super) struct Truth {
    pub(super) touched: bool,
    pub(super) centreline: Vec<Point3<f64>>,
    pub(super) a: Vector6<f64>,
}

pub(super) fn truth_of(rig: &SimRig) -> Truth {
    let equilibrium = rig.equilibrium();
    Truth {
        touched: touches(&equilibrium.contact_forces),
        centreline: equilibrium.wire_centreline(),
        a: equilibrium.base_wrench.to_vector(),
    }
}

/// The simulator's truth at the rests of one closed-loop attempt (the tracker's observer).
pub(super) struct TruthLog<'w> {
    waypoints: &'w [Waypoint],
    /// The true wire touched an obstacle at some rest.
    pub(super) touched: bool,
    pub(super) centrelines: Vec<Vec<[f64; 3]>>,
    a_true: Vec<[f64; 6]>,
    /// Per leg (`Tracked::legs`): touched at one of its moves, and the shape error at its end.
    leg_touched: Vec<bool>,
    leg_shape_mm: Vec<f64>,
    /// The first shape error that could not be scored.
    error: Option<LabError>,
}

impl<'w> TruthLog<'w> {
    /// An empty log of an attempt along `waypoints`.
    pub(super) fn new(waypoints: &'w [Waypoint]) -> Self {
        Self {
            waypoints,
            touched: false,
            centrelines: Vec::new(),
            a_true: Vec::new(),
            leg_touched: Vec::new(),
            leg_shape_mm: Vec::new(),
            error: None,
        }
    }

    pub(super) fn record(&mut self, rig: &SimRig, rest: &Rest<'_>) {
        let truth = truth_of(rig);
        self.touched |= truth.touched;
        match rest.kind {
            RestKind::Start => {}
            RestKind::LegEnd => {
                let planned = self.waypoints.get(rest.waypoint).map(|w| &w.centreline);
                let scored = planned
                    .ok_or_else(|| LabError::no_answer("a leg to no waypoint"))
                    .and_then(|planned| shape_mm(&truth.centreline, planned));
                match scored {
                    Ok(mm) => self.leg_shape_mm.push(mm),
                    Err(e) => {
                        self.leg_shape_mm.push(f64::NAN);
                        self.error.get_or_insert(e);
                    }
                }
                return;
            }
            RestKind::Step => {
                if self.leg_touched.len() <= rest.leg {
                    self.leg_touched.resize(rest.leg + 1, false);
                }
                self.leg_touched[rest.leg] |= truth.touched;
                self.centrelines.push(to_points(&truth.centreline));
            }
            RestKind::Retreat | RestKind::Undo | RestKind::Relocation => {
                self.centrelines.push(to_points(&truth.centreline));
            }
        }
        self.a_true.push(truth.a.into());
    }

    /// The attempt of `tracked` with this truth.
    pub(super) fn attempt(self, tracked: &Tracked) -> Result<Attempt, LabError> {
        if let Some(e) = self.error {
            return Err(e);
        }
        let shape = |k: usize| self.leg_shape_mm.get(k).copied().unwrap_or(f64::NAN);
        let legs = tracked
            .legs
            .iter()
            .enumerate()
            .map(|(k, leg)| Leg {
                waypoint: leg.waypoint,
                moves: leg.moves,
                outcome: leg.outcome.name().to_owned(),
                shape_mm: shape(k),
                scored: leg.scored,
                touched: self.leg_touched.get(k).copied().unwrap_or(false),
            })
            .collect();
        Ok(Attempt {
            outcome: tracked
                .end
                .as_ref()
                .map_or(String::new(), ToString::to_string),
            steps: tracked.moves,
            touched: self.touched,
            detected: tracked.detected,
            retreats: tracked.retreats,
            undone: tracked.undone,
            skipped: tracked.skipped,
            relocated: tracked.relocated,
            completed: tracked.completed,
            shape_mm: tracked.scored.iter().map(|&k| shape(k)).collect(),
            centrelines: self.centrelines,
            a_true: self.a_true,
            legs,
            ..Attempt::new("closed_loop")
        })
    }
}

pub(super) fn to_points(centreline: &[Point3<f64>]) -> Vec<[f64; 3]> {
    centreline.iter().map(|p| [p.x, p.y, p.z]).collect()
}

/// Mean distance \[mm\] between two centrelines (world frame).
pub(super) fn shape_mm(truth: &[Point3<f64>], planned: &[Point3<f64>]) -> Result<f64, LabError> {
    let a: Vec<Vector3<f64>> = truth.iter().map(|p| p.coords).collect();
    let b: Vec<Vector3<f64>> = planned.iter().map(|p| p.coords).collect();
    centreline_distance(&a, &b, DEFAULT_METRIC_SAMPLES)
        .map(|d| 1e3 * d)
        .map_err(|e| LabError::no_answer(format!("the shape error: {e}")))
}
