//! The simulated rig of an experiment: the true wire between the grippers, the sensor, the
//! markers; and the measurements a real robot makes on it.

use ftwire_control::{BiasObserverParams, NoiseModel, NoiseParams};
use ftwire_core::{FtSample, GripperPoses, Pose, Rig};
use ftwire_estimate::ft::{FtCalibration, FtPipeline, Measurement, Mounting, RestAverage, Tare};
use ftwire_estimate::identify::MeasurementNoise;
use ftwire_rod::{Load, Rod};
use ftwire_sim::{BoxObstacle, RigParams, SimRig, Simulator, World};
use nalgebra::{Vector3, Vector6};

use super::{Gravity, ModelKind, SIM_EDGES};
use crate::error::{LabError, from_rod, from_sim};
use crate::initial_guess::kirchhoff_guess;
use crate::setup::SimSetup;
use crate::wire::WireSpec;

/// F/T samples averaged per rest period (0.1 s at the simulated sensor's 1 kHz): the noise of
/// the mean is a tenth of one sample's.
pub const SAMPLES_PER_REST: usize = 100;

/// F/T samples of the tare (0.5 s at 1 kHz): the tare's own error is then well below a rest
/// period's.
pub const TARE_SAMPLES: usize = 500;

/// A simulated rig holding `wire` with the base clamp at the world origin (x horizontal, z up)
/// and the second gripper at `Γ(a0)` of the true wire: the operator placed the wire in the
/// configuration `a0`. The simulator starts from the Kirchhoff shape of `a0`, so it lands on
/// that equilibrium branch (with gravity on, the wire then sags from it).
///
/// # Errors
/// No answer (exit 1) when the model or the simulator cannot place the wire there.
pub fn place_wire(
    wire: &WireSpec,
    gravity: Gravity,
    a0: &Vector6<f64>,
    config: RigParams,
) -> Result<SimRig, LabError> {
    place_among(wire, gravity, ModelKind::Weightless, a0, config, &[])
}

/// As [`place_wire`], on a simulated wire whose bending softens at the curvature `softening`
/// \[1/m\] (`ftwire_sim::RodParams::bending_softening`): a wire that the models, all linear
/// in bending, do not describe. The second gripper is at the weightless model's `Γ(a0)`.
///
/// # Errors
/// As [`place_wire`]; bad input for a softening that is not positive.
pub fn place_softened_wire(
    wire: &WireSpec,
    gravity: Gravity,
    a0: &Vector6<f64>,
    config: RigParams,
    softening: f64,
) -> Result<SimRig, LabError> {
    let params = ftwire_sim::RodParams {
        bending_softening: Some(softening),
        ..crate::wire::rod_params(wire, gravity.vector(), SIM_EDGES)
    };
    let world = World::new(params).map_err(|e| from_sim(e, "building the simulated wire"))?;
    let rod = Rod::new(
        wire.wire_params()
            .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?,
    );
    place_in_world(world, &rod, &Pose::identity(), a0, config)
}

/// As [`place_wire`], in a world with box `obstacles` (world frame = base clamp frame), with
/// the second gripper at `Γ(a0)` of the true wire's `model`:
/// - [`ModelKind::Weightless`]: the weightless rod's `Γ(a0)`, the paper's placement; with
///   gravity on the wire then sags from it, away from `a0`;
/// - [`ModelKind::Loaded`]: the loaded model's ([`true_rod`]: its weight under `gravity` and
///   its rest curvature), so that the true wire's base wrench is `a0` (up to the simulator's
///   discretisation), with gravity on too. What a configuration means to an experiment that
///   steers the wire by the loaded model, from `a0` to a goal.
///
/// # Errors
/// As [`place_wire`].
pub fn place_among(
    wire: &WireSpec,
    gravity: Gravity,
    model: ModelKind,
    a0: &Vector6<f64>,
    config: RigParams,
    obstacles: &[BoxObstacle],
) -> Result<SimRig, LabError> {
    let world = world_among(wire, gravity, obstacles)?;
    let rod = match model {
        ModelKind::Weightless => Rod::new(
            wire.wire_params()
                .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?,
        ),
        ModelKind::Loaded => true_rod(wire, gravity.vector())?,
    };
    place_in_world(world, &rod, &Pose::identity(), a0, config)
}

/// The simulated `wire` under `gravity` among box `obstacles`.
fn world_among(
    wire: &WireSpec,
    gravity: Gravity,
    obstacles: &[BoxObstacle],
) -> Result<World, LabError> {
    let params = crate::wire::rod_params(wire, gravity.vector(), SIM_EDGES);
    Ok(obstacles.iter().fold(
        World::new(params).map_err(|e| from_sim(e, "building the simulated wire"))?,
        |world, obstacle| world.with_box(*obstacle),
    ))
}

/// The loaded model of the true `wire`: its weight under `g_clamp` \[m/s²\] (in the base clamp
/// frame; zero for none) and its natural curvature.
///
/// # Errors
/// Bad input for a wire whose parameters are not valid.
pub fn true_rod(wire: &WireSpec, g_clamp: Vector3<f64>) -> Result<Rod, LabError> {
    let load = Load::from_gravity(wire.density, wire.radius, g_clamp)
        .and_then(|load| load.with_natural_curvature(Vector3::from(wire.natural_curvature)))
        .map_err(|e| from_rod(e, "the loaded model of the wire"))?;
    Ok(Rod::new(
        wire.wire_params()
            .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?,
    )
    .with_load(load))
}

/// A simulated rig in `world` with the base clamp at `base` (world frame) and the second
/// gripper at `base · Γ(a0)` of `model`, the simulator starting from `model`'s shape of `a0`:
/// what [`place_wire`], [`place_among`] and the scenes' placement share.
///
/// # Errors
/// No answer when the model or the simulator cannot place the wire there.
pub fn place_in_world(
    world: World,
    model: &Rod,
    base: &Pose,
    a0: &Vector6<f64>,
    config: RigParams,
) -> Result<SimRig, LabError> {
    let tip = base
        * model
            .tip(a0)
            .map_err(|e| from_rod(e, "placing the wire at its start configuration"))?;
    let guess = kirchhoff_guess(model, a0, world.rod())
        .map_err(|e| from_rod(e, "the start shape of the wire"))?;
    let sim = Simulator::with_guess(world, &guess, base, &tip)
        .map_err(|e| from_sim(e, "placing the wire in the simulator"))?;
    SimRig::from_simulator(sim, config).map_err(|e| from_sim(e, "building the simulated rig"))
}

/// Reads `n` samples; a dropout is `None` (the pipeline skips and counts it).
pub fn read_samples(rig: &mut SimRig, n: usize) -> Vec<Option<FtSample>> {
    (0..n).map(|_| rig.read_ft().ok()).collect()
}

/// Tares the sensor as a robot does before it picks the wire up: [`TARE_SAMPLES`] readings
/// with nothing in the base gripper (`ftwire_estimate::ft::Tare`).
///
/// # Errors
/// No answer when too many samples drop out.
pub fn tare(rig: &mut SimRig) -> Result<Tare, LabError> {
    let samples: Vec<Option<FtSample>> = (0..TARE_SAMPLES)
        .map(|_| rig.read_ft_empty_gripper().ok())
        .collect();
    let rest = RestAverage::new(TARE_SAMPLES / 2)
        .map_err(|e| LabError::bad_input(e.to_string()))?
        .average(samples.iter().map(Option::as_ref))
        .map_err(|e| LabError::no_answer(format!("taring the F/T sensor: {e}")))?;
    Ok(Tare::from_rest(&rest, &Vector6::zeros()))
}

/// The bias observer's settings for a robot with `setup`'s sensor and the execution error
/// `noise`, when it is switched `on`: [`BiasObserverParams::for_sensor`] of the sensor's data
/// sheet, tared over [`TARE_SAMPLES`], with the default execution noise. Without noise and
/// under `increment` each rest is also fused with the reported pose, so that a light wire's
/// few mN are no longer the limit; `None` under `absolute`.
pub fn bias_observer(setup: &SimSetup, noise: NoiseModel, on: bool) -> Option<BiasObserverParams> {
    if !on {
        return None;
    }
    let sheet = crate::setup::sensor::data_sheet(&setup.rig_config(0).sensor);
    BiasObserverParams::for_sensor(&sheet, TARE_SAMPLES, noise, &NoiseParams::default())
}

/// The mounting the robot knows from its drawings: the simulated sensor's `sensor_from_clamp`.
///
/// # Errors
/// Bad input for a non-finite mounting in the rig's sensor settings.
pub fn mounting(config: &RigParams) -> Result<Mounting, LabError> {
    Mounting::new(config.sensor.sensor_from_clamp())
        .map_err(|e| LabError::bad_input(format!("the sensor's mounting: {e}")))
}

/// The noise of `ã` that identification models for `setup`'s sensor, from its data sheet as a
/// user reads it: each rest's white noise (`noise_std` over `rest_samples` readings, its full
/// covariance in `ã`: a force noise is a torque noise at the clamp too), the
/// tare's (over [`TARE_SAMPLES`]) and the bias drift's intensity and time constant, all
/// mapped to `ã` by the mounting (a force error is a torque error at the clamp, a lever arm
/// away). The pose noise keeps the library's default.
///
/// # Errors
/// Bad input for a sensor whose mounting or drift is not valid.
pub fn identification_noise(
    setup: &SimSetup,
    rest_samples: usize,
) -> Result<MeasurementNoise, LabError> {
    let config = setup.rig_config(0);
    identification_noise_of(
        &config.sensor,
        &mounting(&config)?,
        rest_samples,
        TARE_SAMPLES,
    )
}

/// The pose noise the simulated rig leaves in `b̃` when its robot reports the gripper
/// exactly: the simulator's own accuracy against the continuous model (its rod's
/// discretisation and equilibrium tolerance) \[rad, m\], per axis: 0.005° and 0.01 mm, the
/// level at which the fits' `χ²/dof` is about 1 across wires, where the library's default for
/// a real robot (0.05°, 0.1 mm) leaves it far below 1 and every interval too wide
/// (`docs/identify-soft-wires.md`).
pub const SIM_POSE_NOISE: [f64; 2] = [0.005 * std::f64::consts::PI / 180.0, 1e-5];

/// The relative error the wire model itself leaves in `ã` against the simulated rod (its
/// discretisation): the stiff unseen wire's mean error of `c` with a perfect calibration,
/// about 0.01 %.
pub const SIM_MODEL_GAIN_ERROR: f64 = 1e-4;

/// The relative error the wire model itself leaves in each identified parameter against the
/// simulated rod (its discretisation), which no number of samples removes: the error of `c`
/// and `L` identified through a perfect map from a nearly noiseless sensor
/// (`docs/identify-soft-wires.md#error-bars`).
pub const SIM_MODEL_PARAMETER_ERROR: f64 = 1e-4;

/// The model's shape error against the simulated rod at the tip \[mm\], as `σ_model(s) = e·s`
/// with `e` this over the wire's length (`ftwire_estimate::shape::ModelError`): the bound
/// `crates/ftwire/tests/model_vs_sim.rs` holds the model's centreline to.
pub const SIM_MODEL_ERROR_MM: f64 = 0.5;

/// The learnt calibration's relative error per channel against the sensor's exact inverse,
/// `[torque, force]`: the mean over calibrations of several seeds, gravity off and on, each
/// measured on wires across the force scales (`docs/calibration.md#across-seeds`).
pub const LEARNT_GAIN_ERROR: [f64; 2] = [5e-4, 1e-3];

/// The pose noise `[rotation, translation]` \[rad, m\] and the shared relative gain error of
/// `ã`'s `[torque, force]` channels that identification models in the simulator for `setup`'s
/// rig: [`SIM_POSE_NOISE`] with the robot's execution error of both grippers when it has one,
/// and the map's gain error — [`LEARNT_GAIN_ERROR`] through a learnt calibration (`learnt`),
/// otherwise the sensor's own gain and cross-talk (the largest row of `gain − I` of its data
/// sheet, for all six: the mounting mixes force into torque) — with [`SIM_MODEL_GAIN_ERROR`].
pub fn simulated_rig_errors(setup: &SimSetup, learnt: bool) -> ([f64; 2], [f64; 2]) {
    let config = setup.rig_config(0);
    let execution = config.execution;
    let pose = [
        SIM_POSE_NOISE[0].hypot(std::f64::consts::SQRT_2 * execution.orientation_std),
        SIM_POSE_NOISE[1].hypot(std::f64::consts::SQRT_2 * execution.position_std),
    ];
    let map = if learnt {
        LEARNT_GAIN_ERROR
    } else {
        let gain = &config.sensor.gain;
        let largest = (0..6)
            .map(|i| {
                (0..6)
                    .map(|j| (gain[i][j] - f64::from(u8::from(i == j))).powi(2))
                    .sum::<f64>()
                    .sqrt()
            })
            .fold(0.0, f64::max);
        [largest; 2]
    };
    (pose, map.map(|g| g.hypot(SIM_MODEL_GAIN_ERROR)))
}

/// [`identification_noise`] of a sensor's data sheet `sensor` (its white noise, drift
/// intensity and time constant, in its own frame) mounted by `mount`, with `rest_samples`
/// readings averaged per sample and `tare_samples` in the tare.
///
/// # Errors
/// Bad input for a drift that is not valid.
pub fn identification_noise_of(
    sensor: &ftwire_sim::FtSensorParams,
    mount: &Mounting,
    rest_samples: usize,
    tare_samples: usize,
) -> Result<MeasurementNoise, LabError> {
    crate::setup::sensor::data_sheet(sensor)
        .noise(mount, rest_samples, tare_samples)
        .map_err(|e| LabError::bad_input(e.to_string()))
}

/// A pipeline with the default rest average ([`SAMPLES_PER_REST`], at least half of them
/// good), the given tare and calibration.
///
/// # Errors
/// Never for the constants here; kept fallible for the pipeline's own checks.
pub fn pipeline<C: FtCalibration>(tare: Tare, calibration: C) -> Result<FtPipeline<C>, LabError> {
    let average =
        RestAverage::new(SAMPLES_PER_REST / 2).map_err(|e| LabError::bad_input(e.to_string()))?;
    Ok(FtPipeline::new(average, tare, calibration))
}

/// One measured configuration at the rig's current rest: [`SAMPLES_PER_REST`] samples through
/// the pipeline.
///
/// # Errors
/// No answer when too few samples survive screening.
pub fn measure<C: FtCalibration>(
    rig: &mut SimRig,
    pipeline: &FtPipeline<C>,
) -> Result<Measurement, LabError> {
    measure_over(rig, pipeline, SAMPLES_PER_REST)
}

/// One measured configuration at the rig's current rest from `count` samples through the
/// pipeline (a longer rest: the white noise of the mean falls as `1/√count`, while the bias
/// drift grows with the time the rig spends).
///
/// # Errors
/// No answer when too few samples survive screening.
pub fn measure_over<C: FtCalibration>(
    rig: &mut SimRig,
    pipeline: &FtPipeline<C>,
    count: usize,
) -> Result<Measurement, LabError> {
    let samples = read_samples(rig, count);
    pipeline
        .measure(samples.iter().map(Option::as_ref))
        .map_err(|e| LabError::no_answer(format!("measuring the wire's configuration: {e}")))
}

/// The second gripper's pose relative to the base clamp, as the robot believes it.
///
/// # Errors
/// Never on the simulated rig; kept fallible as [`Rig::gripper_poses`] is.
pub fn believed_tip(rig: &SimRig) -> Result<Pose, LabError> {
    let poses: GripperPoses = rig
        .gripper_poses()
        .map_err(|e| from_sim(e, "reading the gripper poses"))?;
    Ok(poses.relative())
}

/// The true wire's centreline \[m\] (base clamp frame): the simulator's ground truth, which
/// the experiments score their estimates against.
pub fn true_centreline(rig: &SimRig) -> Vec<Vector3<f64>> {
    rig.equilibrium()
        .wire_centreline()
        .iter()
        .map(|p| p.coords)
        .collect()
}

/// Contact force \[N\] on a node of the simulated wire above which it touches an obstacle
/// ([`touches`]).
pub const CONTACT_FORCE: f64 = 1e-6;

/// Whether the simulated wire touches an obstacle: a contact force (`contact_forces`, one per
/// node, \[N\]) above [`CONTACT_FORCE`]. The one definition of a touch of every experiment
/// that scores one (tracking, the passage, the demo, the goal experiment's contact runs).
pub fn touches(contact_forces: &[Vector3<f64>]) -> bool {
    contact_forces.iter().any(|f| f.norm() > CONTACT_FORCE)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The softened wire, placed where the linear one is, bends with a smaller moment at the
    /// base: the softening reaches the simulated rig, and a softening of 0 is refused.
    #[test]
    fn a_softened_wire_bends_with_a_smaller_moment() -> Result<(), Box<dyn std::error::Error>> {
        let wire = WireSpec::preset("nitinol-2mm-630").ok_or("no preset")?;
        let a0 = Vector6::new(0.0, 0.0, 0.15, 0.0, 0.1, 0.0);
        let linear = place_wire(&wire, Gravity::Off, &a0, RigParams::ideal())?;
        let soft = place_softened_wire(&wire, Gravity::Off, &a0, RigParams::ideal(), 5.0)?;
        let moment = |rig: &SimRig| {
            rig.equilibrium()
                .base_wrench
                .to_vector()
                .fixed_rows::<3>(0)
                .norm()
        };
        let (hard, softer) = (moment(&linear), moment(&soft));
        assert!(
            softer < 0.97 * hard && softer > 0.5 * hard,
            "{softer} vs {hard} N·m"
        );
        let bad = place_softened_wire(&wire, Gravity::Off, &a0, RigParams::ideal(), 0.0);
        assert!(bad.is_err(), "a softening of 0 must be refused");
        Ok(())
    }

    #[test]
    fn a_touch_is_a_contact_force_above_the_threshold_on_some_node() {
        assert!(!touches(&[]));
        assert!(!touches(&[
            Vector3::zeros(),
            Vector3::new(0.0, CONTACT_FORCE, 0.0)
        ]));
        assert!(touches(&[
            Vector3::zeros(),
            Vector3::new(0.0, 0.0, 2.0 * CONTACT_FORCE)
        ]));
    }

    #[test]
    fn a_rests_force_noise_is_torque_noise_at_the_clamp_too() -> Result<(), LabError> {
        let setup = SimSetup::load(Some("undistorted"), None)
            .map_err(|e| LabError::bad_input(e.to_string()))?;
        let noise = identification_noise(&setup, 400)?;
        let cov = noise.wrench_covariance();
        // The clamp sits 0.08 m from the sensor: each force channel's noise (0.05 N over 400
        // readings) moves a perpendicular torque by 0.08 m times it.
        let force = 0.05 / 20.0;
        let mut correlated = 0;
        for i in 0..3 {
            for j in 3..6 {
                let r = cov[(i, j)] / (cov[(i, i)] * cov[(j, j)]).sqrt();
                if r.abs() > 0.5 {
                    correlated += 1;
                }
            }
            assert!(cov[(i, i)].sqrt() <= 0.08 * force + 0.002 / 20.0 + 1e-12);
        }
        assert_eq!(correlated, 2, "{cov}");
        for j in 3..6 {
            assert!((cov[(j, j)].sqrt() - force).abs() < 1e-12, "{cov}");
        }
        Ok(())
    }

    #[test]
    fn the_simulated_rigs_errors_follow_its_map_and_execution() -> Result<(), LabError> {
        let load = |sensor| {
            SimSetup::load(Some(sensor), None).map_err(|e| LabError::bad_input(e.to_string()))
        };
        let (pose, perfect) = simulated_rig_errors(&load("undistorted")?, false);
        assert_eq!(pose, SIM_POSE_NOISE);
        assert!(
            perfect
                .iter()
                .all(|g| (g - SIM_MODEL_GAIN_ERROR).abs() < 1e-15)
        );
        let (_, learnt) = simulated_rig_errors(&load("distorted")?, true);
        for (g, map) in learnt.iter().zip(LEARNT_GAIN_ERROR) {
            assert!((g - map.hypot(SIM_MODEL_GAIN_ERROR)).abs() < 1e-15);
        }
        assert!(
            learnt[0] < learnt[1],
            "closer in torque than in force: {learnt:?}"
        );
        // The default sensor's gain and cross-talk through the mounting alone: about 1.5 %.
        let (_, raw) = simulated_rig_errors(&load("distorted")?, false);
        assert!(raw.iter().all(|g| (0.01..0.02).contains(g)), "{raw:?}");
        Ok(())
    }
}
