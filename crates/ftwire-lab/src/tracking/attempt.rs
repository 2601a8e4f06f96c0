//! What one tracking attempt did, leg by leg, scored on the simulator's truth.

use serde::Serialize;

/// What one tracking attempt did, scored on the simulator's truth.
#[derive(Debug, Clone, Serialize)]
pub struct Attempt {
    /// `closed_loop` or `open_loop`.
    pub mode: &'static str,
    /// How it ended: a controller outcome's name, or `done` for a finished roll-out.
    pub outcome: String,
    /// Moves commanded.
    pub steps: usize,
    /// The true wire touched an obstacle at a rest.
    pub touched: bool,
    /// The collision detector flagged a move (it stopped the motion, or the retreat took the
    /// wire back and the leg went on).
    pub detected: bool,
    /// Retreats after a detection (`TrackingPolicy::max_retreats` at most): each moved the
    /// second gripper back one move and ran the leg again.
    pub retreats: usize,
    /// Legs undone after the controller stopped them as diverged, on a sensor fault, or (under
    /// `increment` and `absolute` noise, `TrackingPolicy::reruns_unreachable`) at a waypoint
    /// out of the arms' reach or on a second detection after a retreat
    /// (`TrackingPolicy::escalates`) (`TrackingPolicy::max_undos` at most): each moved the
    /// second gripper back to the leg's start and ran the leg again.
    pub undone: usize,
    /// Intermediate waypoints passed over because the arms could not reach them (the closed
    /// loop moves on to the next; two in a row end the attempt).
    pub skipped: usize,
    /// Whether the closed loop moved both grippers by one translation to reach the goal
    /// (`ftwire_plan::relocation`; at most once an attempt).
    pub relocated: bool,
    /// `‖a_true − a_g‖` at the end \[normalised\] (the simulator's wrench).
    pub final_error: f64,
    /// The whole path was executed: every leg ended by reaching its waypoint or, between
    /// waypoints and on the last leg, by the iteration limit, or passed over an intermediate
    /// waypoint out of the arms' reach ([`Attempt::skipped`]) (closed loop); every move made
    /// (open loop).
    pub completed: bool,
    /// Ended within `TrackingPolicy::success_epsilon` of the goal (true wrench).
    pub at_goal: bool,
    /// Success by `TrackingPolicy::success_rule`: completed and never touched, and at the
    /// goal when `TrackingPolicy::success_needs_goal`.
    pub success: bool,
    /// The true shape against `Φ(γ_A(i/N))` at each waypoint reached \[mm\].
    pub shape_mm: Vec<f64>,
    /// The true centreline (world frame) at each rest, for figures.
    #[serde(skip)]
    pub centrelines: Vec<Vec<[f64; 3]>>,
    /// The true configuration (the simulator's base wrench) at the start and at each rest
    /// \[N·m, N\], for figures.
    #[serde(skip)]
    pub a_true: Vec<[f64; 6]>,
    /// Every leg the closed loop ran, in order, reruns included (empty for the open loop).
    #[serde(skip)]
    pub legs: Vec<Leg>,
}

/// One leg of the closed loop as it ran: what `waypoints.csv` lists.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Leg {
    /// The waypoint it steered to (1: the first after the start).
    pub waypoint: usize,
    /// Moves it made.
    pub moves: usize,
    /// How it ended: the controller outcome's name.
    pub outcome: String,
    /// The true shape against the waypoint's when it ended \[mm\].
    pub shape_mm: f64,
    /// Whether [`Attempt::shape_mm`] (Table IV) scores it: not when the leg was run again
    /// (after a retreat, an undo or a relocation) or its waypoint was passed over.
    pub scored: bool,
    /// The true wire touched an obstacle at one of its rests.
    pub touched: bool,
}

impl Attempt {
    /// An attempt of `mode` that has not run yet.
    pub(super) fn new(mode: &'static str) -> Self {
        Self {
            mode,
            outcome: String::new(),
            steps: 0,
            touched: false,
            detected: false,
            retreats: 0,
            undone: 0,
            skipped: 0,
            relocated: false,
            final_error: f64::NAN,
            completed: false,
            at_goal: false,
            success: false,
            shape_mm: Vec::new(),
            centrelines: Vec::new(),
            a_true: Vec::new(),
            legs: Vec::new(),
        }
    }

    /// `success` or `failure` in words, saying when a success by the paper's rule (under
    /// `increment`/`absolute` noise) did not end at the goal.
    pub fn verdict(&self) -> &'static str {
        match (self.success, self.at_goal) {
            (true, true) => "success",
            (true, false) => "success by the paper's rule (no contact), not at the goal",
            (false, _) => "failure",
        }
    }
}
