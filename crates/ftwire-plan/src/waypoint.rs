//! The waypoints of a plan as a tracker steers to them (`γ_A(i/N)`, with `Γ` and `Φ`), and
//! what the planning side knows about them: which are near an obstacle, their polish for
//! clearance, their expected touching landings, and a relocation of both grippers when the
//! arms cannot reach one.

use ftwire_core::{GripperPoses, Pose};
use ftwire_robot::{DualArmParams, DualArmTarget, Robot};
use ftwire_rod::{Rod, to_normalised};
use nalgebra::{Point3, Translation3, Vector3, Vector6};
use serde::Serialize;

use crate::{Checker, PlanError, PlanPolicy, Sample, Scene, ValidityParams, ZPoint};

/// The clearance \[m\] below which a waypoint's planned wire is near an obstacle: its surface
/// closer than this to a box or the floor ([`near_obstacles`]). A 3 mm wire through the middle
/// of the shipped passage's 50 mm gap is 23.5 mm from each box.
pub const NEAR_CLEARANCE: f64 = 0.025;

/// A waypoint of a planned path: the configuration and what the planning model makes of it.
#[derive(Debug, Clone, PartialEq)]
pub struct Waypoint {
    /// `a` \[N·m, N\], base clamp frame.
    pub a: Vector6<f64>,
    /// `Γ(a)`: the second gripper relative to the base clamp.
    pub tip: Pose,
    /// `Φ(a)`, world frame.
    pub centreline: Vec<Point3<f64>>,
}

/// `n + 1` waypoints `γ_A(i/n)` at equal steps of normalised arc length along `path`
/// (piecewise straight in `A`, every edge checked by the planner), with `Γ` and `Φ` of `rod`
/// (world frame, base clamp at `base`). The robot's reach is the controller's to check as it
/// moves, not re-solved here.
///
/// # Errors
/// [`PlanError::EmptyPath`] for no samples; [`PlanError::Rod`] when the model cannot solve a
/// waypoint.
pub fn waypoints_along(
    rod: &Rod,
    base: &Pose,
    path: &[Sample],
    n: usize,
) -> Result<Vec<Waypoint>, PlanError> {
    let wire = rod.wire();
    let a: Vec<Vector6<f64>> = path.iter().map(|s| s.config.a).collect();
    let mut cumulative = vec![0.0];
    for w in a.windows(2) {
        let d = (to_normalised(wire, &w[1]) - to_normalised(wire, &w[0])).norm();
        cumulative.push(cumulative.last().copied().unwrap_or(0.0) + d);
    }
    let total = cumulative.last().copied().unwrap_or(0.0);
    let n = n.max(1);
    let along = (0..=n)
        .map(|i| {
            let target = total * i as f64 / n as f64;
            let k = cumulative
                .windows(2)
                .position(|w| target <= w[1])
                .unwrap_or(cumulative.len().saturating_sub(2));
            let (Some(from), Some(to)) = (a.get(k), a.get(k + 1).or_else(|| a.get(k))) else {
                return Err(PlanError::EmptyPath);
            };
            let span = cumulative.get(k + 1).copied().unwrap_or(total) - cumulative[k];
            let t = if span > 0.0 {
                ((target - cumulative[k]) / span).clamp(0.0, 1.0)
            } else {
                0.0
            };
            Ok(from + (to - from) * t)
        })
        .collect::<Result<Vec<_>, PlanError>>()?;
    waypoints_at(rod, base, &along)
}

/// The waypoints at the configurations `a` (in order), with `Γ` and `Φ` of `rod` (world
/// frame, base clamp at `base`, `ValidityParams::default().nodes` nodes).
///
/// # Errors
/// [`PlanError::Rod`] when the model cannot solve one of them.
pub fn waypoints_at(
    rod: &Rod,
    base: &Pose,
    a: &[Vector6<f64>],
) -> Result<Vec<Waypoint>, PlanError> {
    a.iter()
        .map(|a| {
            let tip = rod.tip(a)?;
            let shape = rod.shape(a, ValidityParams::default().nodes)?;
            let centreline = shape
                .positions
                .iter()
                .map(|p| base * Point3::from(*p))
                .collect();
            Ok(Waypoint {
                a: *a,
                tip,
                centreline,
            })
        })
        .collect()
}

/// For each waypoint, whether its planned wire (the surface at `rod`'s radius) comes within
/// [`NEAR_CLEARANCE`] of a box or the floor of `scene`.
///
/// # Errors
/// [`PlanError::Robot`] when the robot's description cannot be loaded.
pub fn near_obstacles(
    scene: &Scene,
    rod: &Rod,
    waypoints: &[Waypoint],
) -> Result<Vec<bool>, PlanError> {
    let checker = Checker::new(*rod, Robot::sda10f()?, scene, ValidityParams::default())?;
    Ok(waypoints
        .iter()
        .map(|w| checker.wire_clearance(&w.centreline).0 < NEAR_CLEARANCE)
        .collect())
}

/// What [`polish_waypoints`] did.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PolishOut {
    /// Interior waypoints moved.
    pub moved: usize,
    /// The smallest waypoint clearance before the polish \[mm\] (`null` when nothing was
    /// polished).
    pub min_clearance_before_mm: f64,
    /// As `min_clearance_before_mm`, after.
    pub min_clearance_after_mm: f64,
    /// The smallest landing clearance of an interior waypoint before the polish \[mm\]
    /// (`PlanPolicy::polish_params`; `null` when nothing was polished).
    pub min_landing_clearance_before_mm: f64,
    /// As `min_landing_clearance_before_mm`, after.
    pub min_landing_clearance_after_mm: f64,
    /// Whether every waypoint was valid under the tracking model's checker (else nothing was
    /// polished).
    pub valid: bool,
}

/// The waypoints of a path tracked with `rod` in `scene`, polished for clearance
/// ([`crate::polish_clearance`] with [`PlanPolicy::polish_params`] and a checker of `rod` with
/// [`PlanPolicy::validity`]): each interior waypoint whose landings come closer than the
/// target to a box is moved away from it, its legs kept in `Z_free`. Each waypoint's joints
/// continue the previous one's along their edge, or are solved afresh where that edge is
/// refused; when a waypoint is not valid at all under that checker, the waypoints are
/// returned as they are.
///
/// # Errors
/// [`PlanError::Robot`] when the robot cannot be loaded; the checker's and the polish's
/// errors; [`PlanError::Rod`] when the model cannot solve a polished waypoint.
pub fn polish_waypoints(
    scene: &Scene,
    rod: &Rod,
    policy: &PlanPolicy,
    waypoints: &[Waypoint],
) -> Result<(Vec<Waypoint>, PolishOut), PlanError> {
    let unpolished = PolishOut {
        moved: 0,
        min_clearance_before_mm: f64::NAN,
        min_clearance_after_mm: f64::NAN,
        min_landing_clearance_before_mm: f64::NAN,
        min_landing_clearance_after_mm: f64::NAN,
        valid: false,
    };
    // The checker's own model is the tracking one: `validity` keeps the margin on its folds
    // (`validity_tracked` would test the same model's stability twice).
    let checker = Checker::new(
        *rod,
        Robot::sda10f()?,
        scene,
        policy.validity(rod.wire().length()),
    )?;
    let mut chain: Vec<Sample> = Vec::with_capacity(waypoints.len());
    for w in waypoints {
        let config = ZPoint {
            a: w.a,
            base: scene.base,
        };
        let next = match chain.last() {
            None => checker.endpoint(&config),
            Some(prev) => checker
                .edge(prev, &config)
                .map(|e| e.end)
                .or_else(|_| checker.endpoint(&config)),
        };
        match next {
            Ok(sample) => chain.push(sample),
            Err(_) => return Ok((waypoints.to_vec(), unpolished)),
        }
    }
    let polished = crate::polish_clearance(&checker, &chain, &policy.polish_params())?;
    let a: Vec<Vector6<f64>> = polished.waypoints.iter().map(|s| s.config.a).collect();
    let out = PolishOut {
        moved: polished.moved,
        min_clearance_before_mm: 1e3 * polished.min_clearance.0,
        min_clearance_after_mm: 1e3 * polished.min_clearance.1,
        min_landing_clearance_before_mm: 1e3 * polished.min_score.0,
        min_landing_clearance_after_mm: 1e3 * polished.min_score.1,
        valid: true,
    };
    Ok((waypoints_at(rod, &scene.base, &a)?, out))
}

/// The expected number of touching landings of one pass along `waypoints` tracked with `rod`
/// in `scene`: the sum over the waypoints after the first of [`crate::touch_rate`] with the
/// policy's scatter (the same landings at every waypoint); 0 without a scatter.
///
/// # Errors
/// [`PlanError::Robot`] when the robot cannot be loaded; [`PlanError::Rod`] when the model
/// refuses a waypoint.
pub fn expected_touches(
    scene: &Scene,
    rod: &Rod,
    policy: &PlanPolicy,
    waypoints: &[Waypoint],
) -> Result<f64, PlanError> {
    let Some(scatter) = policy.scatter else {
        return Ok(0.0);
    };
    let checker = Checker::new(
        *rod,
        Robot::sda10f()?,
        scene,
        policy.validity(rod.wire().length()),
    )?;
    waypoints.iter().skip(1).try_fold(0.0, |sum, w| {
        let config = ZPoint {
            a: w.a,
            base: scene.base,
        };
        crate::touch_rate(&checker, &config, &scatter).map(|rate| sum + rate)
    })
}

/// A base gripper pose from which the arms reach the goal again when the goal (or a leg's
/// start) is out of their reach: the current base `poses.base` moved by one translation of
/// `steps` \[m\] along a world axis (shortest first, +x, +y, +z, −x, −y, −z), which leaves the
/// wire's configuration and the sensor's gravity direction unchanged. A candidate must keep
/// `a_goal` valid in `scene` with the policy's margins ([`PlanPolicy::validity`]: `rod`'s wire
/// clear there and halfway, the planned goal pose reachable with the planner's coarse torso
/// sweep, the arms clear), and two relative poses must be reachable from it with that sweep:
/// the current one and the one the robot will command at the goal, `Γ(a_goal) · Γ(a_now)⁻¹ ·
/// b`, the current command `b` carried by the model's step from the measured `a_now` (which
/// holds the grasp offset the robot cannot see). `None` when no candidate does.
///
/// # Errors
/// [`PlanError::Robot`] when the robot cannot be loaded; the checker's errors;
/// [`PlanError::Rod`] when the model cannot solve `a_now` or `a_goal`.
pub fn relocation(
    scene: &Scene,
    policy: &PlanPolicy,
    rod: &Rod,
    poses: &GripperPoses,
    a_now: &Vector6<f64>,
    a_goal: &Vector6<f64>,
    steps: &[f64],
) -> Result<Option<Pose>, PlanError> {
    let robot = Robot::sda10f()?;
    let checker = Checker::new(
        *rod,
        robot.clone(),
        scene,
        policy.validity(rod.wire().length()),
    )?;
    let now = poses.relative();
    let at_goal = rod.tip(a_goal)? * rod.tip(a_now)?.inverse() * now;
    let moved = |t: Vector3<f64>| {
        Pose::from_parts(
            Translation3::from(poses.base.translation.vector + t),
            poses.base.rotation,
        )
    };
    let clear = |base: Pose| checker.endpoint(&ZPoint { a: *a_goal, base }).is_ok();
    let coarse = DualArmParams::default();
    for &step in steps {
        for axis in 0..6 {
            let mut t = Vector3::zeros();
            t[axis % 3] = if axis < 3 { step } else { -step };
            let base = moved(t);
            if !(clear(base) && clear(moved(0.5 * t))) {
                continue;
            }
            let reaches = |relative: Pose| {
                let target = DualArmTarget {
                    world_from_base: Pose::identity(),
                    base_gripper: base,
                    relative,
                };
                robot.dual_arm_ik(&target, None, &coarse).is_ok()
            };
            if reaches(now) && reaches(at_goal) {
                return Ok(Some(base));
            }
        }
    }
    Ok(None)
}
