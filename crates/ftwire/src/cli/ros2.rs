//! Arguments of `ftwire ros2 <node>`: ftwire as ROS 2 nodes.

use clap::{Args, Subcommand};
use ftwire::args::{SeedArgs, SimSetupArgs, Vec6, parse_finite, parse_numbers};
use ftwire_lab::experiment::Gravity;

use crate::cli::groups::{CalibrationArgs, GravityInClampArgs, MountingArgs, NoiseModelArg, OnOff};
use crate::cli::identify::IdentifySettingsArgs;

/// `--qos`: the QoS of the wrench subscription.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SensorQosArg {
    /// Best effort (ROS 2's sensor_data profile).
    SensorData,
    /// Reliable.
    Reliable,
}

impl SensorQosArg {
    /// The node's setting.
    pub fn qos(self) -> ftwire_ros2::node::SensorQos {
        match self {
            Self::SensorData => ftwire_ros2::node::SensorQos::SensorData,
            Self::Reliable => ftwire_ros2::node::SensorQos::Reliable,
        }
    }
}

/// `ftwire ros2 <node>`.
#[derive(Debug, Clone, Args)]
pub struct Ros2Args {
    /// The node to run.
    #[command(subcommand)]
    pub node: Ros2Node,
}

/// The nodes.
#[derive(Debug, Clone, Subcommand)]
pub enum Ros2Node {
    /// The simulator as a ROS 2 robot: publishes the wrench, the gripper poses and the markers,
    /// and moves on `/wire/tip_target`.
    Sim(SimNodeArgs),
    /// The wire's shape from F/T at the sensor's rate.
    Estimate(EstimateNodeArgs),
    /// Identifies the held wire's c and L by the identification motion, and publishes them
    /// on /wire/identified.
    Identify(IdentifyNodeArgs),
    /// Steers the held wire to a goal configuration, or along a planned path, by the
    /// library's path tracker and its closed loop (eq. 13–14).
    Control(ControlNodeArgs),
}

const NODE_HELP: &str = "Every node logs what it subscribes to and publishes on stderr, refuses \
    (and counts) a message in another frame or with a value that is not finite, ends after \
    --duration or on Ctrl-C, and then prints one JSON summary line on stdout: the messages \
    received, published and refused (by reason), and the node's own counts. DDS discovery \
    uses UDP multicast on the machine's interfaces; run the nodes in a network namespace \
    with only the loopback device (`unshare -n`, lo up with multicast and a 224.0.0.0/4 \
    route) to keep them off the network.\n\n\
    Exit codes: 0 ended after --duration or a signal, 2 bad input (a setting, the wire, the \
    calibration or the mounting), 1 the wire cannot be placed at --start.";

/// Options every node takes.
#[derive(Debug, Clone, Args)]
pub struct NodeArgs {
    /// Run this long, then end cleanly [s] [default: until Ctrl-C].
    #[arg(long, value_name = "S", value_parser = parse_finite)]
    pub duration: Option<f64>,
    /// The DDS domain, 0 to 232 [default: ROS_DOMAIN_ID, else 0].
    #[arg(long, value_name = "N")]
    pub domain_id: Option<u16>,
}

/// `ftwire ros2 sim`.
#[derive(Debug, Clone, Args)]
#[command(after_help = NODE_HELP)]
pub struct SimNodeArgs {
    /// Options every node takes.
    #[command(flatten)]
    pub node: NodeArgs,
    /// The true wire: a preset (nitinol-2mm-630, nitinol-3mm-910, nitinol-3mm-820,
    /// cable-3mm-920) or a wire file (TOML).
    #[arg(
        long,
        value_name = "PRESET|FILE.toml",
        default_value = "nitinol-3mm-820"
    )]
    pub wire: String,
    /// Gravity in the simulated world (`off`: the estimator's weightless model holds exactly).
    #[arg(long, value_parser = ftwire::args::named::<Gravity>(&Gravity::NAMES), default_value_t = Gravity::On)]
    pub gravity: Gravity,
    /// The start configuration a0 = τ1,τ2,τ3,f1,f2,f3 [N·m, N], base clamp frame: the second
    /// gripper starts at Γ(a0) of the weightless model [default: (0, 1, 0.5, −1, 0.5, 0) in
    /// the wire's units, torque c2/L and force c2/L²].
    #[arg(long, value_name = "T1,T2,T3,F1,F2,F3", allow_hyphen_values = true, value_parser = parse_numbers::<6>)]
    pub start: Option<Vec6>,
    /// F/T samples per second [Hz], 1 to 10000: the k-th is stamped k / rate.
    #[arg(long, value_name = "HZ", default_value_t = 1000.0, value_parser = parse_finite)]
    pub rate: f64,
    /// Tip poses per second on /wire/tip_pose [Hz], at most --rate.
    #[arg(long, value_name = "HZ", default_value_t = 100.0, value_parser = parse_finite)]
    pub pose_rate: f64,
    /// Marker frames and true centrelines per second on /wire/markers and /wire/truth [Hz],
    /// at most --rate.
    #[arg(long, value_name = "HZ", default_value_t = 10.0, value_parser = parse_finite)]
    pub marker_rate: f64,
    /// The first samples are read with nothing in the base gripper, as a robot tares its
    /// sensor before it picks the wire up (`ftwire ros2 estimate --tare`).
    #[arg(long, value_name = "N", default_value_t = 500)]
    pub tare_samples: u64,
    /// Longest wait for a subscriber to the wrench before the clock starts anyway [s].
    #[arg(long, value_name = "S", default_value_t = 10.0, value_parser = parse_finite)]
    pub wait_subscriber: f64,
    /// The root frame of the TF tree the sim publishes: /tf_static holds world → base clamp
    /// (once), /tf world → tip clamp (with each tip pose).
    #[arg(long, value_name = "FRAME", default_value = ftwire_ros2::node::tf::SIM_WORLD_FRAME)]
    pub tf_world_frame: String,
    /// The base clamp's TF frame (`ftwire ros2 estimate --base-frame`).
    #[arg(long, value_name = "FRAME", default_value = ftwire_ros2::node::tf::SIM_BASE_FRAME)]
    pub tf_base_frame: String,
    /// The second gripper's clamp TF frame (`ftwire ros2 estimate --tip-frame`).
    #[arg(long, value_name = "FRAME", default_value = ftwire_ros2::node::tf::SIM_TIP_FRAME)]
    pub tf_tip_frame: String,
    /// A box the wire can touch: centre and half extents cx,cy,cz,hx,hy,hz [m], in the base
    /// clamp frame, its edges along the frame's axes; repeat for more boxes [default: none].
    #[arg(long = "box", value_name = "CX,CY,CZ,HX,HY,HZ", allow_hyphen_values = true, value_parser = parse_numbers::<6>)]
    pub boxes: Vec<Vec6>,
    /// The seed of the sensor's and the markers' noise.
    #[command(flatten)]
    pub seed: SeedArgs,
    /// The simulated F/T sensor and rig (`--sensor`, `--rig`).
    #[command(flatten)]
    pub setup: SimSetupArgs,
}

/// `ftwire ros2 estimate`.
#[derive(Debug, Clone, Args)]
#[command(after_help = NODE_HELP)]
pub struct EstimateNodeArgs {
    /// Options every node takes.
    #[command(flatten)]
    pub node: NodeArgs,
    /// The wire the shapes are solved for: a preset or a wire file (TOML), e.g. with the
    /// identified c and L.
    #[arg(
        long,
        value_name = "PRESET|FILE.toml",
        default_value = "nitinol-3mm-820"
    )]
    pub wire: String,
    /// The sensor and the tip pose.
    #[command(flatten)]
    pub sensor: SensorArgs,
    /// Points of each published shape, 2 to 10000.
    #[arg(long, value_name = "N", default_value_t = ftwire_rig::shape::DEFAULT_POINTS)]
    pub points: usize,
    /// Tared samples averaged before each estimate, 1 to 100000 (the noise of ã falls as
    /// 1/√N, at a delay of N/2 samples).
    #[arg(long, value_name = "N", default_value_t = 100)]
    pub window: usize,
    /// The tip pose from TF instead of --tip-pose-topic: the base clamp's frame in the TF tree
    /// (/tf, /tf_static), in which the tip frame's pose is looked up by composing the tree's
    /// edges; with --tip-frame (the sim publishes wire_base and wire_tip).
    #[arg(
        long,
        value_name = "FRAME",
        requires = "tip_frame",
        conflicts_with = "tip_pose_topic"
    )]
    pub base_frame: Option<String>,
    /// The second gripper's clamp frame in the TF tree; with --base-frame.
    #[arg(
        long,
        value_name = "FRAME",
        requires = "base_frame",
        conflicts_with = "tip_pose_topic"
    )]
    pub tip_frame: Option<String>,
    /// With --base-frame: a TF edge from /tf older than this before the newest wrench's stamp
    /// is stale, and the tip pose is then unknown (counted in the summary's `tf`) [s].
    #[arg(long, value_name = "S", default_value_t = ftwire_ros2::node::tf::DEFAULT_STALE, value_parser = parse_finite, requires = "base_frame")]
    pub tf_stale: f64,
    /// A true centreline (`nav_msgs/Path`, a simulator's /wire/truth) to measure the shapes
    /// against; the summary's `truth` [default: none].
    #[arg(long, value_name = "TOPIC")]
    pub truth_topic: Option<String>,
    /// A contact is the estimated shape's tip missing the reported tip pose by more than this
    /// [mm], checked at every estimate, beside the collision detector's check of each move
    /// [default: no such check].
    #[arg(long, value_name = "MM", value_parser = parse_finite)]
    pub contact_miss: Option<f64>,
    /// The rests, the bias observer and the collision detector.
    #[command(flatten)]
    pub observe: ObserveArgs,
    /// Error bars σ(s) on every shape (the status's `sigma_mm`, the `sigma` spheres of
    /// /wire/markers_viz, the summary's `sigma`), to first order from --sensor's data sheet:
    /// the window's noise, the tare's, and the drift since the tare, or once the bias observer
    /// has used a rest its estimate's covariance; with --gain-error and --model-error.
    #[arg(long, value_enum, default_value_t = OnOff::On)]
    pub error_bars: OnOff,
    /// The map's relative gain error per channel of ã, shared by every sample, in the error
    /// bars [% of the value, standard deviation]: a learnt calibration's accuracy against the
    /// sensor, or through the mounting alone the sensor's own gain and cross-talk (its data
    /// sheet's gain matrix less the identity) [default: 0].
    #[arg(long, value_name = "PCT", allow_hyphen_values = true, value_parser = parse_finite)]
    pub gain_error: Option<f64>,
    /// The model's own error against the wire per metre of arc length, in the error bars:
    /// σ_model(s) = E·s added in quadrature [m/m] [default: not counted].
    #[arg(long, value_name = "E", allow_hyphen_values = true, value_parser = parse_finite)]
    pub model_error: Option<f64>,
    /// Record every message received and published into this ROS 2 bag (MCAP storage, CDR
    /// messages with their `ros2msg` schemas), readable by Foxglove, Rerun and `ros2 bag`;
    /// `ftwire import mcap` reads its wrench and tip pose back into a log. An existing file is
    /// refused unless --force.
    #[arg(long, value_name = "OUT.mcap")]
    pub record: Option<std::path::PathBuf>,
    /// Replace an existing --record file.
    #[arg(long, requires = "record")]
    pub force: bool,
}

/// What `ftwire ros2 estimate` does at each rest of the second gripper and on each move
/// between two rests.
#[derive(Debug, Clone, Args)]
pub struct ObserveArgs {
    /// A rest: the reported tip pose stays within this distance of where the still period
    /// began [mm] …
    #[arg(long, value_name = "MM", default_value_t = 1.0, value_parser = parse_finite)]
    pub rest_tolerance_mm: f64,
    /// … and within this angle [degrees] …
    #[arg(long, value_name = "DEG", default_value_t = 1.0, value_parser = parse_finite)]
    pub rest_tolerance_deg: f64,
    /// … for this long [s]: then the tared samples from --rest-settle on are averaged into
    /// one rest's ã, with the mean tip pose.
    #[arg(long, value_name = "S", default_value_t = 0.5, value_parser = parse_finite)]
    pub rest_dwell: f64,
    /// The first seconds of a rest, left out of its average while the robot settles [s].
    #[arg(long, value_name = "S", default_value_t = 0.1, value_parser = parse_finite)]
    pub rest_settle: f64,
    /// Estimate the F/T sensor's bias drift at each rest from the model and the reported tip
    /// pose (`ftwire_control::BiasObserver`, as the simulator experiments' closed loop) and
    /// take it out of every later ã before its shape; `off` shapes the tared ã alone.
    #[arg(long, value_enum, default_value_t = OnOff::On)]
    pub bias_observer: OnOff,
    /// The sensor's noise and drift, for the bias observer's settings: a preset of the
    /// simulated sensor (distorted, undistorted, real-like) or a sensor file (TOML, the keys
    /// of `ftwire init`'s example; give the data sheet's noise and drift) [default:
    /// distorted, the simulated default sensor].
    #[arg(long, value_name = "PRESET|FILE.toml")]
    pub sensor: Option<String>,
    /// How the reported tip pose errs, for the bias observer: `none`, it is where the gripper
    /// is to the robot's repeatability (each rest is also fused with it); `offset`, off by a
    /// constant unknown calibration error (10 mm / 3°); `absolute`, off anew at every rest
    /// (no observer then).
    #[arg(long, value_enum, default_value_t = NoiseModelArg::None)]
    pub pose_error: NoiseModelArg,
    /// The first N moves between rests are free of contact and calibrate the collision
    /// detector, as `ftwire experiment goal` calibrates it (floor from the rests' noise,
    /// slope and threshold from the moves); from then on a move whose residual exceeds the
    /// threshold is a contact. At least 10; 0: no detector.
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub collision_calibration: usize,
}

const MOVING_HELP: &str = "The node tares on the first --tare samples (the sim streams them \
    with an empty gripper), sends each target pose on --target-topic, waits until a tip pose \
    within --reach-mm and --reach-deg of it arrives (at most --move-timeout), skips \
    --settle-samples, and averages --rest-samples tared samples (taken again, at most three \
    times, while the means of the rest's halves differ by more than 5 standard errors); the \
    mean goes through --calibration or --mounting to ã. It ends by itself when its task is \
    done, after --duration, or on Ctrl-C, and prints one JSON summary line on stdout. Run it \
    in a network namespace with only the loopback device to keep DDS off the network.\n\n\
    Exit codes: 0 done (or ended by --duration or a signal), 2 bad input, 1 the task could not \
    be finished (identify: too few samples reached).";

/// How a node reads the F/T sensor and the tip pose.
#[derive(Debug, Clone, Args)]
pub struct SensorArgs {
    /// The learnt calibration (`--calibration`).
    #[command(flatten)]
    pub calibration: CalibrationArgs,
    /// The sensor's mounting (`--mounting`); without --calibration the raw readings go through
    /// the mounting alone. A tool's weight cannot be taken out (a wrench carries no gravity).
    #[command(flatten)]
    pub mounting: MountingArgs,
    /// Gravity in the base clamp frame (`--gravity-in-clamp`): the loaded model, with the
    /// wire's weight.
    #[command(flatten)]
    pub gravity: GravityInClampArgs,
    /// The wrench subscription's QoS: sensor-data (best effort: matches a best-effort driver
    /// and a reliable one) or reliable (matches only a reliable publisher).
    #[arg(long, value_enum, default_value_t = SensorQosArg::SensorData)]
    pub qos: SensorQosArg,
    /// Samples of the tare: the first N received are the sensor's reading with nothing in the
    /// gripper (0: no tare). A calibration whose input is raw (`calibrate --log`'s) takes
    /// each reading as it comes, offset and all: no tare before it [default: 500, and 0 with a
    /// calibration whose input is raw or a mounting with a tool]
    #[arg(long, value_name = "N")]
    pub tare: Option<usize>,
    /// The sensor's rate [Hz], to count the samples lost from the stamps k / rate.
    #[arg(long, value_name = "HZ", default_value_t = 1000.0, value_parser = parse_finite)]
    pub rate: f64,
    /// The F/T samples (`geometry_msgs/WrenchStamped`, frame ft_sensor).
    #[arg(long, value_name = "TOPIC", default_value = ftwire_ros2::node::WRENCH_TOPIC)]
    pub wrench_topic: String,
    /// The second gripper's pose relative to the base clamp (`geometry_msgs/PoseStamped`,
    /// frame wire_base).
    #[arg(long, value_name = "TOPIC", default_value = ftwire_ros2::node::TIP_POSE_TOPIC)]
    pub tip_pose_topic: String,
}

/// How a moving node reads the sensor and moves the robot.
#[derive(Debug, Clone, Args)]
pub struct RobotArgs {
    /// The sensor and the tip pose.
    #[command(flatten)]
    pub sensor: SensorArgs,
    /// Tared samples averaged at each rest, 10 to 100000 (the noise of ã falls as 1/√N).
    #[arg(long, value_name = "N", default_value_t = 400)]
    pub rest_samples: usize,
    /// Samples skipped after a target is reached, before the rest.
    #[arg(long, value_name = "N", default_value_t = 20)]
    pub settle_samples: usize,
    /// A target is reached when the reported tip is this close to it [mm].
    #[arg(long, value_name = "MM", default_value_t = 1.0, value_parser = parse_finite)]
    pub reach_mm: f64,
    /// … and turned this little from it [degrees].
    #[arg(long, value_name = "DEG", default_value_t = 1.0, value_parser = parse_finite)]
    pub reach_deg: f64,
    /// Longest wait for a target to be reached [s]; a target the robot refuses is never
    /// reached.
    #[arg(long, value_name = "S", default_value_t = 5.0, value_parser = parse_finite)]
    pub move_timeout: f64,
    /// Where targets go (`geometry_msgs/PoseStamped`, frame wire_base).
    #[arg(long, value_name = "TOPIC", default_value = ftwire_ros2::node::TIP_TARGET_TOPIC)]
    pub target_topic: String,
}

/// `ftwire ros2 identify`.
#[derive(Debug, Clone, Args)]
#[command(after_help = MOVING_HELP)]
pub struct IdentifyNodeArgs {
    /// Options every node takes.
    #[command(flatten)]
    pub node: NodeArgs,
    /// The sensor and the moves.
    #[command(flatten)]
    pub robot: RobotArgs,
    /// Samples: the start pose and N − 1 moves of the identification motion, 2 to 100.
    #[arg(long, value_name = "N", default_value_t = 5)]
    pub samples: usize,
    /// The twist of each move about the wire's tangent at the second gripper [degrees],
    /// alternating in sign (it makes the torsional stiffness c1 observable).
    #[arg(long, value_name = "DEG", default_value_t = 40.0, allow_hyphen_values = true, value_parser = parse_finite)]
    pub twist: f64,
    /// The residual form and the known relations.
    #[command(flatten)]
    pub settings: IdentifySettingsArgs,
    /// The sensor's data sheet, to model the bias every rest shares (the tare's offset and
    /// the drift since, on the wrench stamps' clock) and estimate it with the wire, as
    /// `ftwire identify --log --sensor` does: a preset of the simulated sensor (distorted,
    /// undistorted, real-like) or a sensor file (TOML, the keys of `ftwire init`'s example:
    /// noise_std, bias_random_walk, bias_time_constant). Without it the rests' errors are
    /// independent.
    #[arg(long, value_name = "PRESET|FILE.toml")]
    pub sensor: Option<String>,
    /// The seed of the motion plan and of the identifier's swarm.
    #[command(flatten)]
    pub seed: SeedArgs,
}

/// `ftwire ros2 control`.
#[derive(Debug, Clone, Args)]
#[command(after_help = MOVING_HELP)]
pub struct ControlNodeArgs {
    /// Options every node takes.
    #[command(flatten)]
    pub node: NodeArgs,
    /// The sensor and the moves.
    #[command(flatten)]
    pub robot: RobotArgs,
    /// The wire the controller's model is of: a preset or a wire file (TOML), e.g. with the
    /// identified c and L.
    #[arg(
        long,
        value_name = "PRESET|FILE.toml",
        default_value = "nitinol-3mm-820"
    )]
    pub wire: String,
    /// The goal configuration a_g = τ1,τ2,τ3,f1,f2,f3 [N·m, N], base clamp frame; in the
    /// model's A_stable.
    #[arg(long, value_name = "T1,T2,T3,F1,F2,F3", allow_hyphen_values = true, value_parser = parse_numbers::<6>, conflicts_with = "scene", required_unless_present = "scene")]
    pub goal: Option<Vec6>,
    /// A scene (TOML): the path from its `start` to its `goal` is planned as `ftwire plan`
    /// does (RRT* in A_free, base gripper fixed) and steered along, waypoint by waypoint.
    /// Start the robot at the scene's start.
    #[arg(long, value_name = "FILE.toml")]
    pub scene: Option<std::path::PathBuf>,
    /// The planner's time budget with --scene [s].
    #[arg(long, value_name = "S", default_value_t = 2.0, value_parser = parse_finite)]
    pub time_budget: f64,
    /// The gain K of eq. 13, in (0, 1].
    #[arg(long, value_name = "K", default_value_t = 0.2, value_parser = parse_finite)]
    pub gain: f64,
    /// The goal is reached when ‖a_g − ã‖ is below this [normalised: torque in c2/L, force in
    /// c2/L²].
    #[arg(long, value_name = "EPS", default_value_t = 0.05, value_parser = parse_finite)]
    pub epsilon: f64,
    /// A waypoint of a planned path is passed within this [normalised].
    #[arg(long, value_name = "EPS", default_value_t = 0.2, value_parser = parse_finite)]
    pub waypoint_epsilon: f64,
    /// Largest translation of one step [mm].
    #[arg(long, value_name = "MM", default_value_t = 50.0, value_parser = parse_finite)]
    pub max_step_mm: f64,
    /// Largest rotation of one step [degrees].
    #[arg(long, value_name = "DEG", default_value_t = 17.0, value_parser = parse_finite)]
    pub max_step_deg: f64,
    /// Most steps, over the whole path, before the run ends without the goal.
    #[arg(long, value_name = "N", default_value_t = 100)]
    pub max_steps: usize,
    /// A contact is the model's tip at ã missing the reported tip pose by more than this [mm]:
    /// the run stops there [default: no contact check].
    #[arg(long, value_name = "MM", value_parser = parse_finite)]
    pub contact_miss: Option<f64>,
    /// A true centreline (`nav_msgs/Path`, a simulator's /wire/truth): the summary's `truth`
    /// is the last one against the goal's model shape.
    #[arg(long, value_name = "TOPIC")]
    pub truth_topic: Option<String>,
}
