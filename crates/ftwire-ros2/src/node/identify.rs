//! `ftwire ros2 identify`: identifies the held wire's stiffnesses `c` and length `L` by the
//! library's identification motion, on a robot that speaks ROS 2.
//!
//! 1. **tare** from the first samples, and the start pose `b0` from the first tip pose
//!    ([`super::robot`]);
//! 2. **motion**: the seeded plan of `ftwire_estimate::identify::MotionPlan` from `b0` (small
//!    random moves near `b0`, each twisted about the wire's tangent at the tip, alternating in
//!    sign; `samples − 1` moves after the start), as `ftwire experiment identify` follows it in
//!    the simulator. Each pose is sent on `/wire/tip_target` and waited for;
//! 3. **rest**: at the start and after each move reached, the wrench is averaged over the rest
//!    and mapped to `ã` ([`super::robot`]), and `(ã, b̃)` (the reported pose) is pushed into
//!    the streaming identifier (`ftwire_logs::identification::identifier`: the template model, the
//!    swarm seeded by `seed`, exactly as `ftwire identify --log`) with the rest's time since
//!    the tare on the wrench stamps' clock: with a sensor drift in
//!    [`IdentifyNodeParams::config`]'s noise (`--sensor`), the bias every rest shares is
//!    estimated with the wire, as `ftwire identify --log --sensor` does;
//! 4. **identify**: run to completion; the estimate is published once as `std_msgs/String` JSON
//!    on [`IDENTIFIED_TOPIC`] (transient-local, so a late subscriber still gets it) and returned
//!    in the summary: `{c, length, c_std, length_std, covariance, interval95, chi2_per_dof,
//!    identified, flag, samples}`; `covariance` is of `(c1, c2, c3, L)` \[N·m², m\],
//!    `interval95` the 95 % interval of each.
//!
//! A target the robot refuses or does not reach within the timeout is counted (`unreached`)
//! and skipped; a sample the identifier refuses (outside `A`) is counted (`rejected`). With
//! fewer samples left than the identifier needs, the node ends with an error saying so.

use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use ftwire_estimate::identify::{Estimate, IdentifierParams, MotionPlan};
use ftwire_logs::identification::{flag_name, identifier};
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::SeedableRng;
use ros2_client::QosProfile;
use ros2_client::qos::{Durability, History, WhenFull};
use serde::Serialize;

use super::robot::{Halt, Robot, RobotCounts, RobotParams};
use super::{Log, NodeError, NodeSettings, publish};
use crate::msg::StringMsg;

/// The identified wire.
pub const IDENTIFIED_TOPIC: &str = "/wire/identified";

/// Most samples of one identification.
pub const MAX_SAMPLES: usize = 100;

/// How long the node stays up after publishing the estimate, for it to be delivered \[s\].
const LINGER: f64 = 0.5;

/// What the identification node does.
#[derive(Debug, Clone)]
pub struct IdentifyNodeParams {
    /// The sensor, the moves and the topics.
    pub robot: RobotParams,
    /// Samples: the start and `samples − 1` moves, 2 to [`MAX_SAMPLES`] (default 5).
    pub samples: usize,
    /// The twist of each move about the wire's tangent at the tip \[rad\] (default 40°).
    pub twist: f64,
    /// The seed of the motion plan and of the identifier's swarm.
    pub seed: u64,
    /// The identifier's settings (residual form, known relations).
    pub config: IdentifierParams,
}

/// The estimate as published.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identified {
    /// Stiffnesses `(c1, c2, c3)` \[N·m²\].
    pub c: [f64; 3],
    /// Length \[m\].
    pub length: f64,
    /// Standard deviations of `c` \[N·m²\].
    pub c_std: [f64; 3],
    /// Standard deviation of `L` \[m\].
    pub length_std: f64,
    /// Covariance of `(c1, c2, c3, L)` (then `λ` when identified).
    pub covariance: Option<Vec<Vec<f64>>>,
    /// The 95 % interval of each, in the covariance's order.
    pub interval95: Option<Vec<[f64; 2]>>,
    /// `χ²` per degree of freedom (about 1 for a fit as good as the noise allows).
    pub chi2_per_dof: f64,
    /// Whether the data identify the wire.
    pub identified: bool,
    /// Why not, when not.
    pub flag: Option<&'static str>,
    /// Samples used.
    pub samples: usize,
}

impl Identified {
    /// The published form of `estimate`.
    pub fn new(estimate: &Estimate) -> Self {
        Self {
            c: estimate.c,
            length: estimate.length,
            c_std: estimate.c_std,
            length_std: estimate.length_std,
            covariance: estimate.covariance.as_ref().map(|c| c.rows()),
            interval95: estimate.interval95(),
            chi2_per_dof: estimate.chi2_per_dof,
            identified: estimate.is_identified(),
            flag: flag_name(estimate.unidentified.as_ref()),
            samples: estimate.samples,
        }
    }
}

/// The end of a run: one JSON line.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IdentifySummary {
    /// `"identify"`.
    pub node: &'static str,
    /// What the robot side counted.
    #[serde(flatten)]
    pub counts: RobotCounts,
    /// Rests pushed into the identifier.
    pub samples: usize,
    /// Rests the identifier refused.
    pub rejected: u64,
    /// The estimate, once made.
    pub identified: Option<Identified>,
    /// The identification's own time \[s\].
    pub identify_s: f64,
}

impl IdentifyNodeParams {
    fn validate(&self) -> Result<MotionPlan, NodeError> {
        if !(2..=MAX_SAMPLES).contains(&self.samples) {
            return Err(NodeError::BadSetting {
                setting: "--samples",
                value: self.samples.to_string(),
                allowed: "2 to 100 samples (the start and samples − 1 moves)",
            });
        }
        let plan = MotionPlan {
            moves: self.samples - 1,
            twist: self.twist,
            ..MotionPlan::default()
        };
        plan.validate().map_err(|_| NodeError::BadSetting {
            setting: "--twist",
            value: self.twist.to_degrees().to_string(),
            allowed: "a twist in (−90°, 90°)",
        })?;
        Ok(plan)
    }
}

/// Runs the identification (module docs) until it is done, `settings.duration` ends or `stop`
/// is set.
///
/// # Errors
/// [`NodeError`] for bad settings or ROS 2 entities that cannot be created;
/// [`NodeError::Incomplete`] when stopped before the estimate, or with too few samples for
/// one.
pub fn run(
    params: &IdentifyNodeParams,
    settings: NodeSettings,
    stop: &AtomicBool,
    log: Log<'_>,
) -> Result<IdentifySummary, NodeError> {
    settings.validate()?;
    let plan = params.validate()?;
    let mut robot = Robot::new(
        "ftwire_identify",
        &params.robot,
        settings.domain_id,
        settings.duration,
    )?;
    let qos = QosProfile::publisher_default()
        .reliability_reliable(WhenFull::DEFAULT)
        .durability(Durability::TransientLocal)
        .history(History::KeepLast { depth: 1 });
    let identified_pub = robot
        .node()
        .publisher::<StringMsg>(IDENTIFIED_TOPIC, &qos)?;
    log(&format!(
        "identify: domain {}; subscribed to {} and {}; publishing {} and {IDENTIFIED_TOPIC}; {} \
         samples of {} F/T samples each, twist {:.0}°, seed {}",
        settings.domain_id,
        params.robot.wrench_topic,
        params.robot.tip_pose_topic,
        params.robot.target_topic,
        params.samples,
        params.robot.rest_samples,
        params.twist.to_degrees(),
        params.seed
    ));
    let stopped = || NodeError::Incomplete("identify: stopped before the estimate".to_owned());
    let b0 = robot.wait_ready(stop)?.map_err(|_| stopped())?;
    log(&format!(
        "identify: tared; start pose at ({:.4}, {:.4}, {:.4}) m",
        b0.translation.vector.x, b0.translation.vector.y, b0.translation.vector.z
    ));
    let mut rng = ChaCha8Rng::seed_from_u64(params.seed);
    let poses = plan.poses(&b0, &mut rng);
    let mut id = identifier(&[], &params.config, params.seed)?;
    let (mut pushed, mut rejected) = (0_usize, 0_u64);
    let mut since = f64::NEG_INFINITY;
    for k in 0..=poses.len() {
        if k > 0 {
            match robot.move_to(&poses[k - 1], stop)? {
                Ok(t) => since = t,
                Err(Halt::Stopped) => return Err(stopped()),
                Err(Halt::Timeout) => {
                    log(&format!(
                        "identify: move {k} not reached within {} s; skipped",
                        params.robot.move_timeout
                    ));
                    continue;
                }
            }
        }
        let rest = robot.rest(since, stop)?.map_err(|_| stopped())?;
        match id.push_at(rest.since_tare.max(0.0), rest.a, rest.tip) {
            Ok(()) => {
                pushed += 1;
                log(&format!(
                    "identify: sample {pushed} at move {k}, {:.3} s after the tare: ã = {:?}{}",
                    rest.since_tare,
                    rest.a.as_slice(),
                    if rest.settled { "" } else { " (unsettled)" }
                ));
            }
            Err(e) => {
                rejected += 1;
                log(&format!("identify: sample at move {k} refused: {e}"));
            }
        }
    }
    let clock = Instant::now();
    let estimate = id.run_to_completion().map_err(|e| {
        NodeError::Incomplete(format!(
            "identify: no estimate from {pushed} samples ({} of {} moves unreached, {rejected} \
             refused): {e}",
            robot.counts.unreached,
            poses.len()
        ))
    })?;
    let identify_s = clock.elapsed().as_secs_f64();
    let identified = Identified::new(&estimate);
    log(&format!(
        "identify: c = {:?} N·m², L = {:.4} m, χ²/dof {:.2}, {} ({identify_s:.2} s)",
        identified.c,
        identified.length,
        identified.chi2_per_dof,
        identified.flag.unwrap_or("identified")
    ));
    let data = serde_json::to_string(&identified)
        .map_err(|e| NodeError::Incomplete(format!("identify: the estimate as JSON: {e}")))?;
    let counts = &mut robot.counts;
    publish(
        &identified_pub,
        StringMsg { data },
        "identified",
        &mut counts.published,
        &mut counts.publish_failed,
    );
    std::thread::sleep(Duration::from_secs_f64(LINGER));
    Ok(IdentifySummary {
        node: "identify",
        counts: robot.finish_counts(),
        samples: pushed,
        rejected,
        identified: Some(identified),
        identify_s,
    })
}
