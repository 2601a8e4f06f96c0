//! The nodes' settings as a front end spells them (the binary's options, a launcher's): presets
//! or files by name, millimetres, degrees and percent. Each `params` loads what is named,
//! converts the units, builds the node's params and checks them, naming the option in every
//! error; the front end only parses its input into these and calls.

use std::path::PathBuf;

use ftwire_app::LabError;
use ftwire_app::config::sensor::DataSheetSpec;
use ftwire_app::config::wire::WireSpec;
use ftwire_control::{BiasObserverParams, ControlParams, NoiseModel, NoiseParams};
use ftwire_estimate::ft::{Mounting, MountingSpec};
use ftwire_logs::identification::ResidualParams;
use ftwire_rig::{DataSheet, RawMap};
use nalgebra::Vector6;

use super::control::ControlNodeParams;
use super::estimate::{EstimateNodeParams, Record};
use super::identify::IdentifyNodeParams;
use super::observe::{ObserveParams, RestParams};
use super::robot::RobotParams;
use super::sigma::ErrorBars;
use super::tf::TfFrames;
use super::{NodeError, NodeSettings, SensorQos};

fn bad_input(message: String) -> NodeError {
    NodeError::Lab(LabError::bad_input(message))
}

impl NodeSettings {
    /// The settings of `--domain-id` (else `ROS_DOMAIN_ID`, else 0) and `--duration`, checked.
    ///
    /// # Errors
    /// [`NodeError`] naming `ROS_DOMAIN_ID` when it is not a number, and as
    /// [`NodeSettings::validate`].
    pub fn from_env(domain_id: Option<u16>, duration: Option<f64>) -> Result<Self, NodeError> {
        let domain_id = match domain_id {
            Some(id) => id,
            None => match std::env::var("ROS_DOMAIN_ID") {
                Ok(text) if !text.trim().is_empty() => text.trim().parse().map_err(|_| {
                    bad_input(format!(
                        "ROS_DOMAIN_ID={text:?}: give a DDS domain from 0 to 232, or --domain-id"
                    ))
                })?,
                _ => 0,
            },
        };
        let settings = Self {
            domain_id,
            duration,
        };
        settings.validate()?;
        Ok(settings)
    }
}

/// The wire `--wire` names: a preset or a wire file.
///
/// # Errors
/// Bad input naming `--wire`.
pub fn load_wire(given: &str) -> Result<WireSpec, NodeError> {
    WireSpec::load(given).map_err(|e| bad_input(format!("--wire: {e}")))
}

/// `--sensor`'s data sheet (a preset or a sensor file); the default sensor's without it.
fn data_sheet(given: Option<&str>) -> Result<DataSheet, NodeError> {
    match given {
        Some(given) => Ok(DataSheetSpec::load(given)
            .map_err(|e| bad_input(format!("--sensor: {e}")))?
            .sheet),
        None => Ok(ftwire_app::config::sensor::DEFAULT),
    }
}

/// How a node reads the F/T sensor and the tip pose.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorOptions {
    /// `--calibration`: a learnt calibration's file.
    pub calibration: Option<PathBuf>,
    /// `--mounting`: the sensor's mounting.
    pub mounting: MountingSpec,
    /// `--gravity-in-clamp` \[m/s²\]: the loaded model.
    pub gravity_in_clamp: Option<[f64; 3]>,
    /// `--qos` of the wrench subscription.
    pub qos: SensorQos,
    /// `--tare`: samples of the tare (`None`: the map's default,
    /// [`ftwire_rig::stream::default_tare`]: none before a calibration whose input is raw).
    pub tare: Option<usize>,
    /// `--rate` \[Hz\].
    pub rate: f64,
    /// `--wrench-topic`.
    pub wrench_topic: String,
    /// `--tip-pose-topic`.
    pub tip_pose_topic: String,
}

impl SensorOptions {
    fn raw_map(&self) -> Result<RawMap, NodeError> {
        Ok(ftwire_logs::raw_map(
            self.calibration.as_deref(),
            Some(self.mounting.clone()),
        )?)
    }

    /// `--tare`, or the default tare before `map`.
    fn tare(&self, map: &RawMap) -> usize {
        self.tare
            .unwrap_or_else(|| ftwire_rig::stream::default_tare(map))
    }

    fn mount(&self) -> Result<Mounting, NodeError> {
        self.mounting
            .mounting()
            .map_err(|e| bad_input(format!("--mounting: {e}")))
    }
}

/// `ftwire ros2 estimate`'s rests, bias observer and collision detector.
#[derive(Debug, Clone, PartialEq)]
pub struct ObserveOptions {
    /// `--rest-tolerance-mm`.
    pub rest_tolerance_mm: f64,
    /// `--rest-tolerance-deg`.
    pub rest_tolerance_deg: f64,
    /// `--rest-dwell` \[s\].
    pub rest_dwell: f64,
    /// `--rest-settle` \[s\].
    pub rest_settle: f64,
    /// `--bias-observer on`.
    pub bias_observer: bool,
    /// `--sensor`: the data sheet's preset or file.
    pub sensor: Option<String>,
    /// `--pose-error`.
    pub pose_error: NoiseModel,
    /// `--collision-calibration`: free moves that calibrate the detector (0: none).
    pub collision_calibration: usize,
}

impl ObserveOptions {
    /// The rests, and the bias observer's settings for `--sensor`'s data sheet, a tare of
    /// `tare` samples and `--pose-error` ([`BiasObserverParams::for_sensor`]).
    ///
    /// # Errors
    /// Bad input naming `--sensor`.
    pub fn params(&self, tare: usize) -> Result<ObserveParams, NodeError> {
        let sheet = data_sheet(self.sensor.as_deref())?;
        let bias_observer = self.bias_observer.then(|| {
            BiasObserverParams::for_sensor(&sheet, tare, self.pose_error, &NoiseParams::default())
        });
        Ok(ObserveParams {
            rest: RestParams {
                position_tolerance: 1e-3 * self.rest_tolerance_mm,
                angle_tolerance: self.rest_tolerance_deg.to_radians(),
                dwell: self.rest_dwell,
                settle: self.rest_settle,
            },
            bias_observer: bias_observer.flatten(),
            calibration_moves: self.collision_calibration,
        })
    }
}

/// `ftwire ros2 estimate`.
#[derive(Debug, Clone, PartialEq)]
pub struct EstimateOptions {
    /// `--wire`.
    pub wire: String,
    /// The sensor and the tip pose.
    pub sensor: SensorOptions,
    /// `--points`.
    pub points: usize,
    /// `--window`.
    pub window: usize,
    /// `--base-frame` (with `--tip-frame`).
    pub base_frame: Option<String>,
    /// `--tip-frame` (with `--base-frame`).
    pub tip_frame: Option<String>,
    /// `--tf-stale` \[s\].
    pub tf_stale: f64,
    /// `--truth-topic`.
    pub truth_topic: Option<String>,
    /// `--contact-miss` \[mm\].
    pub contact_miss_mm: Option<f64>,
    /// The rests, the bias observer and the detector.
    pub observe: ObserveOptions,
    /// `--error-bars on`.
    pub error_bars: bool,
    /// `--gain-error` \[%\].
    pub gain_error_pct: Option<f64>,
    /// `--model-error` \[m/m\].
    pub model_error: Option<f64>,
    /// `--record`.
    pub record: Option<PathBuf>,
    /// `--force`: replace the record.
    pub force: bool,
}

impl EstimateOptions {
    /// The estimator's params.
    ///
    /// # Errors
    /// Bad input naming the option.
    pub fn params(&self) -> Result<EstimateNodeParams, NodeError> {
        let s = &self.sensor;
        let tf = match (&self.base_frame, &self.tip_frame) {
            (Some(base), Some(tip)) => Some(TfFrames {
                base: base.clone(),
                tip: tip.clone(),
                stale: self.tf_stale,
            }),
            (None, None) => None,
            _ => {
                return Err(bad_input(
                    "--base-frame and --tip-frame go together: give both, or neither (the tip \
                     pose then comes from --tip-pose-topic)"
                        .to_owned(),
                ));
            }
        };
        let map = s.raw_map()?;
        let tare = s.tare(&map);
        Ok(EstimateNodeParams {
            wire: load_wire(&self.wire)?,
            map,
            gravity_in_clamp: s.gravity_in_clamp,
            points: self.points,
            qos: s.qos,
            tare,
            window: self.window,
            rate: s.rate,
            wrench_topic: s.wrench_topic.clone(),
            tip_pose_topic: s.tip_pose_topic.clone(),
            tf,
            truth_topic: self.truth_topic.clone(),
            contact_miss: self.contact_miss_mm.map(|mm| 1e-3 * mm),
            observe: self.observe.params(tare)?,
            error_bars: self.error_bars(tare)?,
            record: self.record.clone().map(|path| Record {
                path,
                overwrite: self.force,
            }),
        })
    }

    /// The error bars: `--sensor`'s data sheet with the window, the tare and `--gain-error`
    /// ([`ftwire_logs::identification::data_sheet_noise`]), and `--model-error`; `None` with
    /// `--error-bars off`.
    fn error_bars(&self, tare: usize) -> Result<Option<ErrorBars>, NodeError> {
        if !self.error_bars {
            return Ok(None);
        }
        let sheet = data_sheet(Some(self.observe.sensor.as_deref().unwrap_or("distorted")))?;
        let noise = ftwire_logs::identification::data_sheet_noise(
            &sheet,
            &self.sensor.mount()?,
            (self.window, tare),
            self.gain_error_pct.map(|pct| 1e-2 * pct),
        )?;
        let model_error = self
            .model_error
            .map(ftwire_estimate::shape::ModelError::new)
            .transpose()
            .map_err(|e| bad_input(format!("--model-error: {e}")))?;
        Ok(Some(ErrorBars { noise, model_error }))
    }
}

/// How a moving node (`identify`, `control`) reads the sensor and moves the robot.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotOptions {
    /// The sensor and the tip pose.
    pub sensor: SensorOptions,
    /// `--rest-samples`.
    pub rest_samples: usize,
    /// `--settle-samples`.
    pub settle_samples: usize,
    /// `--reach-mm`.
    pub reach_mm: f64,
    /// `--reach-deg`.
    pub reach_deg: f64,
    /// `--move-timeout` \[s\].
    pub move_timeout: f64,
    /// `--target-topic`.
    pub target_topic: String,
}

impl RobotOptions {
    /// The robot's params, with `truth_topic` to compare with.
    ///
    /// # Errors
    /// Bad input naming the option.
    pub fn params(&self, truth_topic: Option<String>) -> Result<RobotParams, NodeError> {
        let s = &self.sensor;
        let map = s.raw_map()?;
        let params = RobotParams {
            tare: s.tare(&map),
            map,
            qos: s.qos,
            rate: s.rate,
            rest_samples: self.rest_samples,
            settle_samples: self.settle_samples,
            reach_translation: 1e-3 * self.reach_mm,
            reach_rotation: self.reach_deg.to_radians(),
            move_timeout: self.move_timeout,
            wrench_topic: s.wrench_topic.clone(),
            tip_pose_topic: s.tip_pose_topic.clone(),
            target_topic: self.target_topic.clone(),
            truth_topic,
        };
        params.validate()?;
        Ok(params)
    }
}

/// `ftwire ros2 identify`.
#[derive(Debug, Clone, PartialEq)]
pub struct IdentifyOptions {
    /// The sensor and the moves.
    pub robot: RobotOptions,
    /// `--samples`.
    pub samples: usize,
    /// `--twist` \[degrees\].
    pub twist_deg: f64,
    /// `--seed`.
    pub seed: u64,
    /// The residual form and the known relations (`--form`, `--isotropic`, …).
    pub residual: ResidualParams,
    /// `--sensor`: the data sheet whose bias every rest shares.
    pub sensor: Option<String>,
}

impl IdentifyOptions {
    /// The identification node's params: with `--sensor`, the rests' shared bias (the tare's
    /// offset and the drift since) from its data sheet; with the loaded model (the
    /// calibration's, or `--gravity-in-clamp`), the wire's weight identified with c and L.
    ///
    /// # Errors
    /// Bad input naming the option.
    pub fn params(&self) -> Result<IdentifyNodeParams, NodeError> {
        let mut config = self.residual.config()?;
        let r = &self.robot;
        let robot = r.params(None)?;
        if let Some(given) = &self.sensor {
            let noise = data_sheet(Some(given))?
                .noise(&r.sensor.mount()?, r.rest_samples, robot.tare)
                .map_err(|e| bad_input(format!("--sensor: {e}")))?;
            config.noise = self.residual.with_noise_settings(noise)?;
        }
        if let Some(g) = ftwire_logs::model_gravity(&robot.map, r.sensor.gravity_in_clamp)? {
            ftwire_rig::WireModelChoice::loaded(g)
                .map_err(|e| bad_input(format!("--gravity-in-clamp: {e}")))?;
            config.constraints.weight = Some(nalgebra::Vector3::from(g));
            config
                .validate()
                .map_err(|e| bad_input(format!("--gravity-in-clamp: {e}")))?;
        }
        Ok(IdentifyNodeParams {
            robot,
            samples: self.samples,
            twist: self.twist_deg.to_radians(),
            seed: self.seed,
            config,
        })
    }
}

/// `ftwire ros2 control`.
#[derive(Debug, Clone, PartialEq)]
pub struct ControlOptions {
    /// The sensor and the moves.
    pub robot: RobotOptions,
    /// `--wire`.
    pub wire: String,
    /// The goals in order, each six numbers `a` \[N·m, N\] (`--goal`, or the waypoints after
    /// the start of a planned path).
    pub goals: Vec<Vec<f64>>,
    /// `--gain`.
    pub gain: f64,
    /// `--epsilon` \[normalised\].
    pub epsilon: f64,
    /// `--waypoint-epsilon` \[normalised\].
    pub waypoint_epsilon: f64,
    /// `--max-step-mm`.
    pub max_step_mm: f64,
    /// `--max-step-deg`.
    pub max_step_deg: f64,
    /// `--max-steps`.
    pub max_steps: usize,
    /// `--contact-miss` \[mm\].
    pub contact_miss_mm: Option<f64>,
    /// `--truth-topic`.
    pub truth_topic: Option<String>,
}

impl ControlOptions {
    /// The control node's params (checked again, with the model, when the node runs).
    ///
    /// # Errors
    /// Bad input naming the option.
    pub fn params(&self) -> Result<ControlNodeParams, NodeError> {
        let goals = self
            .goals
            .iter()
            .map(|g| {
                <[f64; 6]>::try_from(g.as_slice())
                    .map(Vector6::from)
                    .map_err(|_| bad_input(format!("--goal {g:?}: give six numbers")))
            })
            .collect::<Result<_, _>>()?;
        Ok(ControlNodeParams {
            robot: self.robot.params(self.truth_topic.clone())?,
            wire: load_wire(&self.wire)?,
            gravity_in_clamp: self.robot.sensor.gravity_in_clamp,
            goals,
            control: ControlParams {
                gain: self.gain,
                epsilon: self.epsilon,
                max_translation: 1e-3 * self.max_step_mm,
                max_rotation: self.max_step_deg.to_radians(),
                ..ControlParams::default()
            },
            waypoint_epsilon: self.waypoint_epsilon,
            max_steps: self.max_steps,
            contact_miss: self.contact_miss_mm.map(|mm| 1e-3 * mm),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ftwire_estimate::calibration::{
        Calibration, CalibrationInput, Dataset, LabelModel, TrainParams,
    };

    /// A calibration file whose map takes `input`, written into a fresh folder.
    fn calibration_file(input: CalibrationInput, name: &str) -> PathBuf {
        let labels: Vec<Vector6<f64>> = (0..40_u32)
            .map(|k| {
                Vector6::from_fn(|i, _| {
                    f64::from((k * 7 + 3 * u32::try_from(i).unwrap_or(0)) % 11) - 5.0
                })
            })
            .collect();
        let raw = labels.iter().map(|a| 2.0 * a).collect();
        let data = Dataset::new(raw, labels).expect("finite");
        let params = TrainParams {
            hidden: vec![],
            max_epochs: 5,
            ..TrainParams::default()
        };
        let calibration = Calibration::train(&data, &params, 1)
            .expect("trains")
            .with_provenance(LabelModel::WEIGHTLESS, input)
            .expect("valid");
        let dir =
            std::env::temp_dir().join(format!("ftwire-options-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a folder");
        let path = dir.join("calibration.json");
        calibration.save(&path).expect("written");
        path
    }

    fn robot(calibration: PathBuf, tare: Option<usize>) -> RobotOptions {
        RobotOptions {
            sensor: SensorOptions {
                calibration: Some(calibration),
                mounting: MountingSpec::default(),
                gravity_in_clamp: None,
                qos: SensorQos::SensorData,
                tare,
                rate: 1000.0,
                wrench_topic: "/ft".into(),
                tip_pose_topic: "/tip".into(),
            },
            rest_samples: 400,
            settle_samples: 20,
            reach_mm: 1.0,
            reach_deg: 1.0,
            move_timeout: 5.0,
            target_topic: "/target".into(),
        }
    }

    /// The moving nodes (`identify`, `control`) take no tare by default before a calibration
    /// that takes raw readings (`calibrate --log`'s), and refuse one given, naming `--tare`,
    /// as `ros2 estimate` does; a calibration trained on tared readings is tared by default.
    #[test]
    fn a_raw_calibration_is_not_tared_by_the_moving_nodes() {
        let raw = calibration_file(CalibrationInput::Raw, "raw");
        assert_eq!(
            robot(raw.clone(), None).params(None).expect("valid").tare,
            0
        );
        let error = robot(raw.clone(), Some(500))
            .params(None)
            .expect_err("a tare before a raw calibration");
        let message = error.to_string();
        assert!(
            message.contains("--tare") && message.contains("raw"),
            "{message}"
        );
        let tared = calibration_file(CalibrationInput::Tared, "tared");
        let params = robot(tared.clone(), None).params(None).expect("valid");
        assert_eq!(params.tare, ftwire_rig::stream::DEFAULT_TARE);
        for path in [raw, tared] {
            if let Some(dir) = path.parent() {
                std::fs::remove_dir_all(dir).ok();
            }
        }
    }
}
