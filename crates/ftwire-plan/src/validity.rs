//! Validity of a configuration and of an edge: what `Z_free` means here.
//!
//! A configuration `z = (a, base)` (the wire's `a` and the base gripper's world pose) is valid
//! when all of these hold ([`Checker::sample`]):
//! - `a ∈ A_stable` (`det J(t)` keeps its sign on `(0, L]`, ftwire-rod's test) and the wire does
//!   not self-intersect ([`ftwire_rod::self_contact`]);
//! - with a [`ValidityParams::stability_margin`] `m > 0` (none by default), a step of `m` along
//!   each normalised axis of `a`, both ways, stays in `A_stable` too: 12 more stability tests,
//!   which keep a plan tracked under gripper noise away from the folds where the wire snaps;
//!   with a [`ValidityParams::stability_model`] (the tracking model, when it is not the
//!   planner's), `a` and those steps are stable under that model;
//! - the grippers are at most [`ValidityParams::max_span`] of the wire's length apart (no limit
//!   by default; a plan to be tracked under large execution noise keeps the wire slack);
//! - the centreline, a polyline of [`ValidityParams::nodes`] nodes in the world frame, keeps a
//!   clearance of at least [`ValidityParams::margin`] beyond the wire's radius from every box
//!   (segment–box distances by parry3d's GJK, through [`ftwire_robot::segment_box_distance`])
//!   and from the floor;
//! - both grippers are reachable (each arm's IK within joint limits, the torso held at the
//!   start's angle), seeded from the neighbouring configuration so that a path's joints are
//!   continuous; the arms' capsules do not meet each other, any box or the floor.
//!
//! The wire is not checked against the robot's own links: near the clamps it lies inside the
//! gripper capsules by construction.
//!
//! # Edges and their resolution
//!
//! An edge is the straight segment between two configurations (`a` linear, the base pose
//! linear in translation and spherical in rotation), checked at samples ([`Checker::edge`]):
//! 1. uniformly, at most [`ValidityParams::max_step`] apart in normalised `a` (and
//!    [`ValidityParams::max_base_step`] in base translation, [`ValidityParams::max_base_turn`] in
//!    base rotation); where the seeded IK cannot follow a step, the step is halved (down to an
//!    eighth), so the joints follow the motion continuously;
//! 2. then each interval between consecutive valid samples is bisected until
//!    - `det J(L)` has the same sign at both ends. The boundary of `A_stable` is where the first
//!      conjugate point reaches the tip, `det J(L) = 0`, so a crossing of the boundary between
//!      two samples changes the sign of `det J(L)` unless it is crossed twice within one step,
//!      which the bounded step of rule 1 makes unlikely;
//!    - no centreline node moves more than `2·c − margin`, `c` the smaller clearance of the two
//!      ends: a node moving straight then keeps at least half the margin in between;
//!    - no joint moves more than [`ValidityParams::max_joint_step`];
//!
//!    an interval that still fails these at [`ValidityParams::min_step`] makes the edge invalid.
//!
//! The test `found_paths_are_valid_at_a_finer_resolution` (tests/planner.rs) re-checks planned
//! paths at a quarter of the step.

use std::fmt;

use ftwire_core::Pose;
use ftwire_robot::{
    Arm, DualArmJoints, DualArmParams, DualArmTarget, EndFrame, IkTarget, LinkRadii, OrientedBox,
    ReachParams, Reachability, Robot, RobotError, point_box_distance, segment_box_distance,
};
use ftwire_rod::{Rod, from_normalised, to_normalised};
use nalgebra::{Point3, Vector6};

use crate::{PlanError, Scene};

/// Settings of the validity checks (public fields + `Default`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ValidityParams {
    /// Clearance \[m\] the wire's surface keeps from every obstacle and the floor (default
    /// `0.005`).
    pub margin: f64,
    /// Centreline nodes of the wire–obstacle test, both ends included (default `64`).
    pub nodes: usize,
    /// Largest step between edge samples in normalised `a` (default `0.25`).
    pub max_step: f64,
    /// Smallest step of the bisection in normalised `a` (default `0.25 / 64`).
    pub min_step: f64,
    /// Largest step between edge samples in base translation \[m\] (default `0.01`).
    pub max_base_step: f64,
    /// Largest step between edge samples in base rotation \[rad\] (default `0.05`).
    pub max_base_turn: f64,
    /// Largest change of any joint between edge samples \[rad\] (default `0.2`).
    pub max_joint_step: f64,
    /// Clearances are computed exactly up to this value \[m\] and reported as it beyond
    /// (default `0.1`).
    pub clearance_cap: f64,
    /// The arms' capsule radii (default [`LinkRadii::default`]).
    pub radii: LinkRadii,
    /// The seeded IK's budget and tolerances (default: 40 iterations, 1e-6 m and rad).
    pub reach: ReachParams,
    /// Largest distance between the grippers' clamps as a fraction of the wire's length, in
    /// `(0, 1]` (default `1.0`: whatever the model allows). Below 1 it keeps the wire slack
    /// enough that a gripper landing a few centimetres off its pose neither pulls it taut nor
    /// tears it (`ftwire experiment passage` under the paper's noise).
    pub max_span: f64,
    /// Distance in normalised `a` that every configuration keeps from the boundary of
    /// `A_stable` (default `0`: none, the paper's `A_free`): a step of this length along any
    /// of the six normalised axes, either way, must stay stable under the checker's model.
    /// Above 0 it keeps a plan tracked under gripper noise, whose moves scatter `a` by units,
    /// from being pushed over a fold onto another equilibrium (`ftwire experiment track` under
    /// the paper's noise). Each checked configuration then costs 12 stability tests more.
    pub stability_margin: f64,
    /// The model whose `A_stable` [`ValidityParams::stability_margin`] is measured in, and
    /// which must hold every configuration stable too, when it is not the planner's (default
    /// `None`: the planner's). A plan made with the weightless model and tracked with the
    /// wire's loaded one keeps its margin on the loaded model's folds, where the true, heavy
    /// wire snaps.
    pub stability_model: Option<Rod>,
}

impl Default for ValidityParams {
    fn default() -> Self {
        Self {
            margin: 0.005,
            nodes: 64,
            max_step: 0.25,
            min_step: 0.25 / 64.0,
            max_base_step: 0.01,
            max_base_turn: 0.05,
            max_joint_step: 0.2,
            clearance_cap: 0.1,
            radii: LinkRadii::default(),
            reach: ReachParams {
                max_iterations: 40,
                ..ReachParams::default()
            },
            max_span: 1.0,
            stability_margin: 0.0,
            stability_model: None,
        }
    }
}

/// A configuration in `Z = A × Q`: the wire's `a` and the base gripper's pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ZPoint {
    /// `a` \[N·m, N\], torque first, base clamp frame.
    pub a: Vector6<f64>,
    /// World from the base gripper's clamp frame.
    pub base: Pose,
}

impl ZPoint {
    /// The point a fraction `s ∈ [0, 1]` along the straight edge to `to`: `a` linear, the base
    /// translation linear and its rotation spherical.
    /// The ends are returned exactly (`s ≤ 0`: `self`, `s ≥ 1`: `to`).
    pub fn interpolate(&self, to: &ZPoint, s: f64) -> ZPoint {
        if s <= 0.0 {
            return *self;
        }
        if s >= 1.0 {
            return *to;
        }
        ZPoint {
            a: self.a + (to.a - self.a) * s,
            base: self.base.lerp_slerp(&to.base, s),
        }
    }
}

/// Why a configuration or an edge is not in `Z_free`.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Invalid {
    /// The model refused `a` (outside `A`, not finite, or the integration diverged).
    Model(String),
    /// `a ∉ A_stable` (of the planner's model, or of [`ValidityParams::stability_model`]).
    Unstable,
    /// `a ∈ A_stable`, but a step of [`ValidityParams::stability_margin`] along a normalised
    /// axis leaves it.
    NearBoundary {
        /// The margin (normalised).
        margin: f64,
        /// The axis (0–5: torque first) and direction (`±1`) of the first unstable step.
        axis: usize,
        /// `+1.0` or `-1.0`.
        sign: f64,
    },
    /// The wire touches itself.
    SelfIntersecting,
    /// The grippers are farther apart than [`ValidityParams::max_span`] allows.
    Taut {
        /// Their distance \[m\].
        span: f64,
        /// The largest allowed \[m\].
        limit: f64,
    },
    /// The wire comes closer than the margin to an obstacle.
    WireCollision {
        /// The obstacle's name (`floor` for the floor).
        obstacle: String,
        /// The wire surface's clearance \[m\] (negative: penetration).
        clearance: f64,
    },
    /// An arm cannot reach its gripper pose from the neighbouring joints.
    Unreachable {
        /// The arm.
        arm: Arm,
    },
    /// The arms' capsules meet.
    ArmsCollide,
    /// An arm's capsules meet an obstacle.
    ArmObstacle {
        /// The arm.
        arm: Arm,
        /// The obstacle's name (`floor` for the floor).
        obstacle: String,
    },
    /// An edge could not be resolved to the required resolution (it crosses the stability
    /// boundary, or moves the wire or a joint too far within the smallest step).
    Unresolved {
        /// Which rule failed.
        rule: &'static str,
    },
}

impl fmt::Display for Invalid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Model(m) => write!(f, "the wire model refused it: {m}"),
            Self::Unstable => write!(f, "a is not in A_stable (det J changes sign)"),
            Self::NearBoundary { margin, axis, sign } => write!(
                f,
                "a is within {margin} (normalised) of A_stable's boundary: a step of {} along \
                 normalised axis {axis} leaves it (stability_margin)",
                sign * margin
            ),
            Self::SelfIntersecting => write!(f, "the wire intersects itself"),
            Self::Taut { span, limit } => write!(
                f,
                "the grippers are too far apart ({:.1} mm; max_span allows {:.1} mm)",
                span * 1e3,
                limit * 1e3
            ),
            Self::WireCollision {
                obstacle,
                clearance,
            } => write!(
                f,
                "the wire is {:.1} mm from {obstacle} (clearance below the margin)",
                clearance * 1e3
            ),
            Self::Unreachable { arm } => write!(f, "the {arm:?} arm cannot reach its gripper pose"),
            Self::ArmsCollide => write!(f, "the arms collide"),
            Self::ArmObstacle { arm, obstacle } => {
                write!(f, "the {arm:?} arm collides with {obstacle}")
            }
            Self::Unresolved { rule } => write!(f, "edge unresolved at the smallest step: {rule}"),
        }
    }
}

/// A valid configuration with what the checks computed.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// The configuration.
    pub config: ZPoint,
    /// World from the second gripper's clamp frame (`base · Γ(a)`).
    pub tip: Pose,
    /// Joint angles of the robot reaching both grippers.
    pub joints: DualArmJoints,
    /// The wire surface's clearance from the nearest obstacle \[m\], capped at
    /// [`ValidityParams::clearance_cap`].
    pub clearance: f64,
    /// `det J(L)`.
    pub det_j: f64,
    /// The centreline in the world frame ([`ValidityParams::nodes`] nodes).
    pub centreline: Vec<Point3<f64>>,
}

/// An edge found valid ([`Checker::edge`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Edge {
    /// The sample at the edge's end (its joints continue the start's).
    pub end: Sample,
    /// The smallest clearance over the edge's samples \[m\].
    pub min_clearance: f64,
    /// How many configurations were checked.
    pub samples: usize,
}

/// The validity checker of one scene, wire and robot.
#[derive(Debug, Clone)]
pub struct Checker {
    rod: Rod,
    robot: Robot,
    boxes: Vec<(String, OrientedBox)>,
    floor: Option<f64>,
    params: ValidityParams,
}

impl Checker {
    /// A checker for `scene`'s obstacles with this wire model and robot.
    ///
    /// # Errors
    /// [`PlanError::InvalidParameter`] for a non-positive or non-finite setting, or
    /// `min_step > max_step`, or fewer than 2 nodes.
    pub fn new(
        rod: Rod,
        robot: Robot,
        scene: &Scene,
        params: ValidityParams,
    ) -> Result<Self, PlanError> {
        PlanError::check_positive(&[
            ("margin", params.margin),
            ("max_step", params.max_step),
            ("min_step", params.min_step),
            ("max_base_step", params.max_base_step),
            ("max_base_turn", params.max_base_turn),
            ("max_joint_step", params.max_joint_step),
            ("clearance_cap", params.clearance_cap),
        ])?;
        if !(params.max_span.is_finite() && params.max_span > 0.0 && params.max_span <= 1.0) {
            return Err(PlanError::InvalidParameter {
                name: "max_span",
                value: params.max_span,
                allowed: "a fraction of the wire's length in (0, 1]",
            });
        }
        if !(params.stability_margin.is_finite() && params.stability_margin >= 0.0) {
            return Err(PlanError::InvalidParameter {
                name: "stability_margin",
                value: params.stability_margin,
                allowed: "a finite value >= 0 (normalised; 0: none)",
            });
        }
        if params.min_step > params.max_step {
            return Err(PlanError::InvalidParameter {
                name: "min_step",
                value: params.min_step,
                allowed: "at most max_step",
            });
        }
        if params.nodes < 2 {
            return Err(PlanError::InvalidParameter {
                name: "nodes",
                value: params.nodes as f64,
                allowed: "at least 2",
            });
        }
        Ok(Self {
            rod,
            robot,
            boxes: scene
                .boxes
                .iter()
                .map(|b| (b.name.clone(), b.geometry))
                .collect(),
            floor: scene.floor,
            params,
        })
    }

    /// The wire model.
    pub fn rod(&self) -> &Rod {
        &self.rod
    }

    /// The robot.
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// The settings.
    pub fn params(&self) -> &ValidityParams {
        &self.params
    }

    /// Checks an endpoint (a start or goal) from scratch: both arms' IK with restarts and a
    /// torso search, then [`Checker::sample`] seeded from that solution.
    ///
    /// # Errors
    /// The reason the configuration is not in `Z_free`.
    pub fn endpoint(&self, config: &ZPoint) -> Result<Sample, Invalid> {
        let wire = self.wire(config)?;
        let target = DualArmTarget {
            world_from_base: Pose::identity(),
            base_gripper: config.base,
            relative: config.base.inverse() * wire.tip,
        };
        let params = DualArmParams {
            radii: self.params.radii,
            ..DualArmParams::default()
        };
        let joints = self
            .robot
            .dual_arm_ik(&target, None, &params)
            .map_err(|e| match e {
                // Every torso angle failed for the base gripper's arm: it is the one out of reach.
                RobotError::DualArmUnreachable {
                    torsos_tried,
                    left_failures,
                    ..
                } if left_failures == torsos_tried => Invalid::Unreachable { arm: Arm::Left },
                RobotError::DualArmUnreachable { collisions, .. } if collisions > 0 => {
                    Invalid::ArmsCollide
                }
                _ => Invalid::Unreachable { arm: Arm::Right },
            })?;
        self.finish(config, wire, &joints)
    }

    /// Checks one configuration, the arms' IK seeded from `seed` (a neighbour's joints; the
    /// torso stays at the seed's angle).
    ///
    /// # Errors
    /// The reason the configuration is not in `Z_free`.
    pub fn sample(&self, config: &ZPoint, seed: &DualArmJoints) -> Result<Sample, Invalid> {
        let wire = self.wire(config)?;
        self.finish(config, wire, seed)
    }

    /// The wire's checks: stability, self-intersection, clearance.
    fn wire(&self, config: &ZPoint) -> Result<WireState, Invalid> {
        let model = |e: ftwire_rod::RodError| Invalid::Model(e.to_string());
        let solution = self
            .rod
            .solve(&config.a, self.params.nodes)
            .map_err(model)?;
        if !solution.jacobian.stability.stable {
            return Err(Invalid::Unstable);
        }
        self.keeps_stability_margin(&config.a)?;
        if solution.self_intersecting {
            return Err(Invalid::SelfIntersecting);
        }
        let span = solution.jacobian.tip.translation.vector.norm();
        let limit = self.params.max_span * self.rod.wire().length();
        if span > limit {
            return Err(Invalid::Taut { span, limit });
        }
        let centreline = world_centreline(config, &solution.shape.positions);
        let (clearance, nearest) = self.wire_clearance(&centreline);
        if clearance < self.params.margin {
            return Err(Invalid::WireCollision {
                obstacle: self.obstacle_name(nearest),
                clearance,
            });
        }
        Ok(WireState {
            tip: config.base * solution.jacobian.tip,
            det_j: solution.jacobian.jacobian.determinant(),
            clearance,
            centreline,
        })
    }

    /// Whether `a` (stable under the planner's model) is stable under
    /// [`ValidityParams::stability_model`] too, and every step of
    /// [`ValidityParams::stability_margin`] along a normalised axis from it stays stable under
    /// that model (the planner's when none is set; no steps with the margin 0).
    fn keeps_stability_margin(&self, a: &Vector6<f64>) -> Result<(), Invalid> {
        let model = match &self.params.stability_model {
            Some(model) => {
                if !model.is_stable(a).unwrap_or(false) {
                    return Err(Invalid::Unstable);
                }
                model
            }
            None => &self.rod,
        };
        let margin = self.params.stability_margin;
        if margin <= 0.0 {
            return Ok(());
        }
        let wire = model.wire();
        let scale = from_normalised(wire, &Vector6::repeat(1.0));
        for axis in 0..6 {
            for sign in [1.0, -1.0] {
                let mut moved = *a;
                moved[axis] += sign * margin * scale[axis];
                if !model.is_stable(&moved).unwrap_or(false) {
                    return Err(Invalid::NearBoundary { margin, axis, sign });
                }
            }
        }
        Ok(())
    }

    /// The robot's checks on a wire found valid, the IK seeded from `seed`.
    fn finish(
        &self,
        config: &ZPoint,
        wire: WireState,
        seed: &DualArmJoints,
    ) -> Result<Sample, Invalid> {
        let joints = self.reach(config.base, wire.tip, seed)?;
        self.arms_clear(&joints)?;
        Ok(Sample {
            config: *config,
            tip: wire.tip,
            joints,
            clearance: wire.clearance,
            det_j: wire.det_j,
            centreline: wire.centreline,
        })
    }

    /// Checks the straight edge from a valid sample to `to` at the resolution of the module
    /// docs. The end's wire checks (stability, self-intersection, clearance) run first, as
    /// they need no IK: the edge is valid or not as if its samples were checked in order.
    ///
    /// # Errors
    /// The reason the end's wire is not in `Z_free`, else the reason the first failing sample
    /// or interval is not.
    pub fn edge(&self, from: &Sample, to: &ZPoint) -> Result<Edge, Invalid> {
        let wire = self.rod.wire();
        let da = (to_normalised(wire, &to.a) - to_normalised(wire, &from.config.a)).norm();
        let dt = (to.base.translation.vector - from.config.base.translation.vector).norm();
        let dr = from.config.base.rotation.angle_to(&to.base.rotation);
        let steps = (da / self.params.max_step)
            .max(dt / self.params.max_base_step)
            .max(dr / self.params.max_base_turn)
            .ceil()
            .max(1.0);
        // The smallest bisection interval, as a fraction of the edge.
        let min_fraction = if da > 0.0 {
            (self.params.min_step / da).min(1.0 / steps)
        } else {
            1.0 / (steps * 64.0)
        };
        let step = 1.0 / steps;
        // The end's wire checks first (a model solve, no IK): an edge whose end is not in
        // Z_free is invalid whatever lies between, and an extension into a box or out of
        // A_stable is then rejected without the samples before it. The solve is kept for the
        // last sample.
        let mut end_wire = Some(self.wire(to)?);
        let mut state = EdgeState {
            samples: 0,
            min_clearance: from.clearance,
        };
        let mut prev = from.clone();
        let mut s_prev = 0.0;
        let mut h = step;
        while s_prev < 1.0 {
            let s = (s_prev + h).min(1.0);
            let checked = if s >= 1.0 {
                match end_wire.take() {
                    Some(wire) => self.finish(to, wire, &prev.joints),
                    None => self.sample(to, &prev.joints),
                }
            } else {
                self.sample(&from.config.interpolate(to, s), &prev.joints)
            };
            let next = match checked {
                Ok(next) => next,
                // The seeded IK follows the motion: a smaller step may reach what a long one
                // could not.
                Err(Invalid::Unreachable { .. }) if s - s_prev > step / 8.0 => {
                    h = 0.5 * (s - s_prev);
                    continue;
                }
                Err(e) => return Err(e),
            };
            state.samples += 1;
            self.resolve(
                from,
                to,
                (&prev, s_prev),
                (&next, s),
                min_fraction,
                &mut state,
            )?;
            prev = next;
            s_prev = s;
            h = (2.0 * h).min(step);
        }
        Ok(Edge {
            end: prev,
            min_clearance: state.min_clearance,
            samples: state.samples,
        })
    }

    /// Bisects the interval between two valid samples of the edge `from → to` until the rules
    /// of the module docs hold.
    fn resolve(
        &self,
        from: &Sample,
        to: &ZPoint,
        (a, sa): (&Sample, f64),
        (b, sb): (&Sample, f64),
        min_fraction: f64,
        state: &mut EdgeState,
    ) -> Result<(), Invalid> {
        state.min_clearance = state.min_clearance.min(b.clearance);
        let rule = self.interval_rule(a, b);
        let Some(rule) = rule else {
            return Ok(());
        };
        if sb - sa <= min_fraction {
            return Err(Invalid::Unresolved { rule });
        }
        let sm = 0.5 * (sa + sb);
        let mid = self.sample(&from.config.interpolate(to, sm), &a.joints)?;
        state.samples += 1;
        self.resolve(from, to, (a, sa), (&mid, sm), min_fraction, state)?;
        self.resolve(from, to, (&mid, sm), (b, sb), min_fraction, state)
    }

    /// The first rule of the module docs that the interval between two samples breaks.
    fn interval_rule(&self, a: &Sample, b: &Sample) -> Option<&'static str> {
        if a.det_j.signum() != b.det_j.signum() {
            return Some("det J(L) changes sign (the stability boundary)");
        }
        let moved = a
            .centreline
            .iter()
            .zip(&b.centreline)
            .map(|(p, q)| (p - q).norm())
            .fold(0.0, f64::max);
        if moved > 2.0 * a.clearance.min(b.clearance) - self.params.margin {
            return Some("the wire moves farther than its clearance allows");
        }
        if joint_distance(&a.joints, &b.joints) > self.params.max_joint_step {
            return Some("a joint moves farther than max_joint_step");
        }
        None
    }

    /// The wire surface's clearance \[m\] (capped) at `config`, without the other checks: one
    /// shape solve of the checker's model.
    ///
    /// # Errors
    /// [`Invalid::Model`] when the model refuses `a`.
    pub fn clearance(&self, config: &ZPoint) -> Result<f64, Invalid> {
        let shape = self
            .rod
            .shape(&config.a, self.params.nodes)
            .map_err(|e| Invalid::Model(e.to_string()))?;
        Ok(self
            .wire_clearance(&world_centreline(config, &shape.positions))
            .0)
    }

    /// The wire surface's clearance (capped) and the index of the nearest obstacle (the
    /// boxes in order, then the floor).
    pub fn wire_clearance(&self, centreline: &[Point3<f64>]) -> (f64, usize) {
        let radius = self.rod.wire().radius();
        let cap = self.params.clearance_cap;
        let mut best = (cap, usize::MAX);
        for (i, (_, b)) in self.boxes.iter().enumerate() {
            for w in centreline.windows(2) {
                // Broad phase: the segment lies within half its length of its midpoint.
                let mid = nalgebra::center(&w[0], &w[1]);
                let half = 0.5 * (w[1] - w[0]).norm();
                if point_box_distance(&mid, b) - half - radius >= best.0 {
                    continue;
                }
                let d = segment_box_distance(&w[0], &w[1], b) - radius;
                if d < best.0 {
                    best = (d, i);
                }
            }
        }
        if let Some(h) = self.floor {
            for p in centreline {
                let d = p.z - h - radius;
                if d < best.0 {
                    best = (d, self.boxes.len());
                }
            }
        }
        best
    }

    fn obstacle_name(&self, index: usize) -> String {
        self.boxes
            .get(index)
            .map_or_else(|| "the floor".to_string(), |(n, _)| format!("{n:?}"))
    }

    /// Both arms' joints reaching the two clamp poses, seeded from `seed`.
    fn reach(&self, base: Pose, tip: Pose, seed: &DualArmJoints) -> Result<DualArmJoints, Invalid> {
        let solve = |arm: Arm, pose: Pose, q| {
            let target = IkTarget {
                arm,
                pose,
                torso: seed.torso,
                frame: EndFrame::Gripper,
            };
            match self.robot.reachability(&target, q, &self.params.reach) {
                Ok(Reachability::Reachable(q)) => Ok(q),
                _ => Err(Invalid::Unreachable { arm }),
            }
        };
        Ok(DualArmJoints {
            torso: seed.torso,
            left: solve(Arm::Left, base, &seed.left)?,
            right: solve(Arm::Right, tip, &seed.right)?,
        })
    }

    /// The arms clear of each other, the boxes and the floor.
    fn arms_clear(&self, joints: &DualArmJoints) -> Result<(), Invalid> {
        let radii = &self.params.radii;
        match self
            .robot
            .arms_collision(joints.torso, &joints.left, &joints.right, radii)
        {
            Ok(None) => {}
            Ok(Some(_)) => return Err(Invalid::ArmsCollide),
            Err(e) => return Err(Invalid::Model(e.to_string())),
        }
        for (arm, q) in [(Arm::Left, &joints.left), (Arm::Right, &joints.right)] {
            let caps = self
                .robot
                .arm_capsules(arm, joints.torso, q, radii)
                .map_err(|e| Invalid::Model(e.to_string()))?;
            for c in &caps {
                for (name, b) in &self.boxes {
                    if segment_box_distance(&c.a, &c.b, b) <= c.radius {
                        return Err(Invalid::ArmObstacle {
                            arm,
                            obstacle: format!("{name:?}"),
                        });
                    }
                }
                if let Some(h) = self.floor
                    && c.a.z.min(c.b.z) - c.radius <= h
                {
                    return Err(Invalid::ArmObstacle {
                        arm,
                        obstacle: "the floor".to_string(),
                    });
                }
            }
        }
        Ok(())
    }
}

/// The largest change of any joint (torso included) between two postures \[rad\].
pub fn joint_distance(x: &DualArmJoints, y: &DualArmJoints) -> f64 {
    (x.left - y.left)
        .amax()
        .max((x.right - y.right).amax())
        .max((x.torso - y.torso).abs())
}

/// What the wire's checks computed.
struct WireState {
    tip: Pose,
    det_j: f64,
    clearance: f64,
    centreline: Vec<Point3<f64>>,
}

/// Running totals of an edge check.
struct EdgeState {
    samples: usize,
    min_clearance: f64,
}

/// The model's centreline (base clamp frame) in the world frame of `config`'s base.
pub(crate) fn world_centreline(
    config: &ZPoint,
    positions: &[nalgebra::Vector3<f64>],
) -> Vec<Point3<f64>> {
    positions
        .iter()
        .map(|p| config.base * Point3::from(*p))
        .collect()
}
