//! `ftwire ros2 estimate`: the wire's shape from each F/T sample.
//!
//! For each `geometry_msgs/WrenchStamped` (force first, sensor frame, frame [`SENSOR_FRAME`]),
//! on the thread that receives it:
//!
//! 1. **tare**: the first `tare` samples are the sensor's reading with nothing in the gripper
//!    (the sim streams them first), averaged into the tare (`ftwire_estimate::ft::Tare`);
//! 2. **window**: the mean of the last `window` tared samples (white noise falls as
//!    `1/√window`, at a delay of half the window); steps 1–2 are [`ftwire_rig::Stream`]'s;
//! 3. **ã**: the mean through the learnt calibration or the mounting
//!    ([`ftwire_rig::RawMap::a_tilde`], the map `ftwire shape --log` gives a record's `raw`);
//! 4. **shape**: [`ftwire_rig::Measurement::solve`] and [`ftwire_rig::Stream::flag`], the
//!    calls `ftwire shape --log` makes, of `ã − β̂` (the bias observer's estimate taken out,
//!    step 6): the centreline at `points` nodes (the weight-free model, or the loaded one with
//!    `gravity_in_clamp`), `stable` (`ã ∈ A_stable`) and `confident` (stable and no jump
//!    from the previous estimate);
//! 5. **contact miss** (with `contact_miss`): the reported tip pose (the latest on the tip pose
//!    topic, or with `tf` the pose of the tip frame in the base frame at the batch's newest
//!    wrench stamp, [`super::tf`]) against the estimated shape's tip. A free wire's shape ends
//!    at the gripper; a contact is a force the model does not have, so the estimate's tip
//!    misses the gripper. A miss above `contact_miss` is a contact;
//! 6. **per rest and per move** ([`super::observe`]): the rests of the second gripper found
//!    from the tip pose and the tared samples, the bias observer updated at each, and the
//!    collision detector on each move between two rests (calibrated on the first moves).
//!
//! 7. **error bars** (with [`EstimateNodeParams::error_bars`]): `σ(s)` of the shape at each
//!    node, from the sensor's data sheet, the gain error and the bias observer's covariance
//!    ([`super::sigma`]).
//!
//! It publishes the centreline as `nav_msgs/Path` on [`SHAPE_TOPIC`] (frame [`BASE_FRAME`],
//! orientation left at the identity), the wire as a `LINE_STRIP` (green when confident,
//! orange otherwise) with a `SPHERE` at the shape's tip when there is a contact by either
//! test (`DELETE` when none) and, with error bars, [`SIGMA_SPHERES`] translucent spheres of
//! diameter `4σ` along the wire (namespace `sigma`: the 2σ tube) on [`MARKERS_VIZ_TOPIC`],
//! and on [`STATUS_TOPIC`] `{"stamp", "a", "stable", "confident", "contact", "bias",
//! "rests", "contact_residual", "contact_source", "sigma_mm"}`: `a` the configuration shaped
//! (`ã − β̂`), `bias` `β̂` (torque first, base clamp frame, N·m and N; `null` without the
//! observer), `rests` the rests so far, `contact_residual` the detector's residual of the
//! last move (`null` until calibrated), `contact_source` which test found the contact
//! (`detector`, `contact_miss`, `detector+contact_miss`, or `null`), and `sigma_mm` `σ` at
//! each node of the shape \[mm\] (`null` without error bars), each stamped with the wrench's
//! stamp.
//!
//! **Keeping up.** Steps 1–3 are a few hundred floating-point operations per sample; the
//! shape solve costs more. After each wake-up the node takes every sample waiting and runs
//! steps 1–3 on each; it then solves and publishes them in order, but skips a sample that has
//! a newer one behind it and has waited longer than one sensor period since its arrival: a
//! stale sample is counted as `dropped`, never queued, and the latest is always solved. No
//! estimate is published before the window is full. The latency of a publication is the time from the
//! wrench's arrival at the node's DDS reader to the publication of its shape.
//!
//! With `truth_topic` (a simulator's `/wire/truth`), each true centreline received is compared
//! with the latest shape: the distance of each true node to the estimated polyline, averaged
//! per message (`truth_mm`), and with error bars the share of true points within `2σ`.

use std::time::{SystemTime, UNIX_EPOCH};

use ftwire_app::config::wire::WireSpec;
use ftwire_estimate::ft::Tare;
use ftwire_logs::RawMap;
use ftwire_rig::{Measurement, Reading, Stream, StreamParams};
use nalgebra::Vector6;
use ros2_client::MessageInfo;
use serde::Serialize;

use super::observe::{DetectorSummary, ObserveParams, ObserverSummary};
use super::sigma::{ErrorBars, SigmaSummary};
use super::stats::Spread;
use super::tf::{TfFrames, TfSummary};
use super::{Counts, NodeError, check_contact_miss};
use crate::msg::{self, ColorRGBA, Marker, MarkerArray};

/// The line width of the drawn wire \[m\].
const LINE_WIDTH: f64 = 0.004;
/// The diameter of the contact sphere \[m\].
const SPHERE_DIAMETER: f64 = 0.03;
/// The spheres drawn along the wire for its error bars, from the first node after the base
/// clamp to the tip.
pub const SIGMA_SPHERES: usize = 8;

/// What the estimator listens to and how it maps a reading to `ã`.
#[derive(Debug, Clone)]
pub struct EstimateNodeParams {
    /// The wire the shapes are solved for.
    pub wire: WireSpec,
    /// The calibration and mounting: raw readings to `ã`.
    pub map: RawMap,
    /// Gravity in the base clamp frame \[m/s²\]: the loaded model, with the wire's weight;
    /// `None`: the weight-free model.
    pub gravity_in_clamp: Option<[f64; 3]>,
    /// Points of each shape (default [`ftwire_rig::shape::DEFAULT_POINTS`]).
    pub points: usize,
    /// The wrench subscription's QoS (default sensor data: best effort, which matches a
    /// best-effort publisher and a reliable one).
    pub qos: super::SensorQos,
    /// Samples of the tare, with nothing in the gripper (0: no tare) (default 500).
    pub tare: usize,
    /// Samples averaged, 1 to 100 000 (default 100).
    pub window: usize,
    /// The sensor's rate \[Hz\], to count lost samples from the stamps (default 1000).
    pub rate: f64,
    /// The wrench topic.
    pub wrench_topic: String,
    /// The tip pose topic (`geometry_msgs/PoseStamped` in [`super::BASE_FRAME`]); not
    /// subscribed with `tf`.
    pub tip_pose_topic: String,
    /// The tip pose from these two TF frames (`/tf`, `/tf_static`) instead of
    /// `tip_pose_topic` ([`super::tf`]).
    pub tf: Option<TfFrames>,
    /// A true centreline to compare the shapes with (a simulator's `/wire/truth`).
    pub truth_topic: Option<String>,
    /// A tip miss above this is a contact \[m\]; `None`: no contact check.
    pub contact_miss: Option<f64>,
    /// The rests, the bias observer and the collision detector ([`super::observe`]).
    pub observe: ObserveParams,
    /// Each shape's error bars `σ(s)` ([`super::sigma`]); `None`: none.
    pub error_bars: Option<ErrorBars>,
    /// Record what the node receives and publishes into this ROS 2 bag (MCAP), replacing an
    /// existing file only with `overwrite`.
    pub record: Option<Record>,
}

/// Where `--record` writes.
#[derive(Debug, Clone)]
pub struct Record {
    /// The bag file.
    pub path: std::path::PathBuf,
    /// Replace an existing file (`--force`).
    pub overwrite: bool,
}

/// The comparison with the true centreline.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TruthError {
    /// True centrelines compared.
    pub compared: u64,
    /// The mean over them of the mean distance of the true nodes to the shape \[mm\].
    pub mean_mm: f64,
    /// The largest mean distance of one of them \[mm\].
    pub worst_mean_mm: f64,
    /// The largest distance of one true node to its shape \[mm\].
    pub max_mm: f64,
}

/// The end of a run: one JSON line.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EstimateSummary {
    /// `"estimate"`.
    pub node: &'static str,
    /// Messages received, by topic.
    pub received: Counts,
    /// Messages published, by topic.
    pub published: Counts,
    /// Messages refused, by reason: `frame_id`, `non_finite`, `malformed`, and TF edges by
    /// [`super::tf::TfRefusal::name`].
    pub refused: Counts,
    /// Messages the middleware would not publish, by topic.
    pub publish_failed: Counts,
    /// Samples missing from the stamp sequence (between the first and the last received).
    pub lost: u64,
    /// Publishers of the wrench topic whose QoS the subscription's (`--qos`) does not match,
    /// so that none of their samples arrive (a best-effort driver and `--qos reliable`), at
    /// the end of the run.
    pub qos_mismatch: u64,
    /// Samples whose stamp was not after the one before.
    pub out_of_order: u64,
    /// Index `k` of the first sample received (`k / rate` its stamp): 0 when the tare saw the
    /// stream from its start.
    pub first_sample: Option<i64>,
    /// Samples skipped as stale: a newer one had arrived, and they had waited longer than one
    /// sensor period.
    pub dropped: u64,
    /// Samples the model had no shape for.
    pub no_shape: u64,
    /// Estimates flagged not confident.
    pub not_confident: u64,
    /// Estimates with a contact (by either test).
    pub contacts: u64,
    /// Rests of the second gripper found and measured.
    pub rests: u64,
    /// Moves between rests the collision detector flagged.
    pub contact_moves: u64,
    /// The bias observer's last estimate and counts, with the observer on.
    pub bias_observer: Option<ObserverSummary>,
    /// The collision detector, once calibrated.
    pub detector: Option<DetectorSummary>,
    /// From a wrench's arrival to its shape's publication \[ms\].
    pub latency_ms: Option<Spread>,
    /// One shape solve (step 4) \[ms\].
    pub solve_ms: Option<Spread>,
    /// The shapes against the truth, with `truth_topic`.
    pub truth: Option<TruthError>,
    /// The error bars of the shapes published, with [`EstimateNodeParams::error_bars`].
    pub sigma: Option<SigmaSummary>,
    /// With `--record`: the messages written into the bag.
    pub recorded: Option<Recorded>,
    /// With TF frames as the tip source: its lookups.
    pub tf: Option<TfSummary>,
}

/// What `--record` wrote.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Recorded {
    /// Messages written.
    pub written: u64,
    /// Messages that could not be written.
    pub failed: u64,
}

/// The running state of steps 1–4: the rig layer's measurement and stream
/// ([`ftwire_rig`], the path `ftwire shape --log` and Python take too).
pub(super) struct Pipeline {
    pub(super) measurement: Measurement,
    pub(super) stream: Stream,
    /// The first sample's time, the tare's time without a tare.
    first_time: Option<f64>,
}

impl Pipeline {
    /// The measurement of `params` (its map, its wire's model: loaded with
    /// `gravity_in_clamp`, weight-free without) and a stream with its tare and window.
    pub(super) fn new(params: &EstimateNodeParams) -> Result<Self, NodeError> {
        let gravity = ftwire_logs::model_gravity(&params.map, params.gravity_in_clamp)?;
        let measurement = ftwire_logs::shape::measurement(
            &params.wire,
            params.map.clone(),
            gravity,
            params.points,
            params
                .error_bars
                .as_ref()
                .and_then(|b| b.model_error)
                .map(|e| e.per_length()),
        )?;
        let stream = Stream::new(
            &measurement,
            StreamParams {
                tare: params.tare,
                window: params.window,
            },
        )
        .map_err(|e| NodeError::BadSetting {
            setting: "--tare",
            value: format!("{} ({e})", params.tare),
            allowed: "0, or at least 2 samples, with a mounting without a tool",
        })?;
        Ok(Self {
            measurement,
            stream,
            first_time: None,
        })
    }

    /// The tare, once taken (no offset without a tare).
    pub(super) fn tare(&self) -> Option<Tare> {
        match self.stream.tare() {
            Some((tare, _)) => Some(*tare),
            None => self.stream.is_tared().then(Tare::none),
        }
    }

    /// The tare's time: the mean stamp of its samples (the first sample's without a tare).
    pub(super) fn tare_time(&self) -> Option<f64> {
        self.stream.tare().map(|(_, t)| t).or(self.first_time)
    }

    /// Takes a raw sample (force first); returns `ã` once the tare is done and the window
    /// full.
    pub(super) fn add(
        &mut self,
        raw: Vector6<f64>,
        time: f64,
    ) -> Option<Result<Vector6<f64>, String>> {
        self.first_time.get_or_insert(time);
        self.stream
            .push(&self.measurement, &Reading::raw(time, raw))
            .map(|r| r.map(|(_, a)| a).map_err(|e| e.to_string()))
    }
}

/// A sample waiting for its shape.
pub(super) struct Pending {
    pub(super) stamp: msg::Time,
    pub(super) a: Vector6<f64>,
    /// When it reached the node's DDS reader, ns since the Unix epoch.
    pub(super) arrival_ns: i64,
}

pub(super) fn now_ns() -> i64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_nanos()).unwrap_or(i64::MAX))
}

pub(super) fn finite_wrench(w: &msg::Wrench) -> Option<Vector6<f64>> {
    let v = Vector6::new(
        w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z,
    );
    v.iter().all(|x| x.is_finite()).then_some(v)
}

pub(super) fn arrival(info: &MessageInfo) -> i64 {
    info.received_timestamp()
        .map_or_else(now_ns, |t| t.to_nanos())
}

/// The drawn wire, the contact sphere and, with `sigma` (\[m\], one per point), the error
/// bars' spheres.
pub(super) fn markers(
    header: &msg::Header,
    points: &[msg::Point],
    confident: bool,
    contact: Option<&msg::Point>,
    sigma: Option<&[f64]>,
) -> MarkerArray {
    let color = if confident {
        ColorRGBA {
            r: 0.1,
            g: 0.8,
            b: 0.2,
            a: 1.0,
        }
    } else {
        ColorRGBA {
            r: 1.0,
            g: 0.55,
            b: 0.0,
            a: 1.0,
        }
    };
    let line = Marker {
        header: header.clone(),
        ns: "wire".to_owned(),
        id: 0,
        kind: Marker::LINE_STRIP,
        action: Marker::ADD,
        scale: msg::Vector3 {
            x: LINE_WIDTH,
            y: 0.0,
            z: 0.0,
        },
        color,
        points: points.to_vec(),
        ..Marker::default()
    };
    let sphere = Marker {
        header: header.clone(),
        ns: "contact".to_owned(),
        id: 0,
        kind: Marker::SPHERE,
        action: if contact.is_some() {
            Marker::ADD
        } else {
            Marker::DELETE
        },
        pose: msg::Pose {
            position: contact.copied().unwrap_or_default(),
            orientation: msg::Quaternion::default(),
        },
        scale: msg::Vector3 {
            x: SPHERE_DIAMETER,
            y: SPHERE_DIAMETER,
            z: SPHERE_DIAMETER,
        },
        color: ColorRGBA {
            r: 1.0,
            g: 0.0,
            b: 0.0,
            a: 0.8,
        },
        ..Marker::default()
    };
    let mut markers = vec![line, sphere];
    if let Some(sigma) = sigma.filter(|s| s.len() == points.len() && points.len() > 1) {
        markers.extend(sigma_spheres(header, points, sigma));
    }
    MarkerArray { markers }
}

/// [`SIGMA_SPHERES`] translucent spheres of diameter `4σ` (the 2σ tube's), evenly along the
/// wire from the first node after the base clamp to the tip.
fn sigma_spheres<'a>(
    header: &'a msg::Header,
    points: &'a [msg::Point],
    sigma: &'a [f64],
) -> impl Iterator<Item = Marker> + 'a {
    let last = points.len() - 1;
    (1..=SIGMA_SPHERES).map(move |j| {
        let k = (j * last).div_ceil(SIGMA_SPHERES).min(last);
        let diameter = 4.0 * sigma[k];
        Marker {
            header: header.clone(),
            ns: "sigma".to_owned(),
            id: i32::try_from(j).unwrap_or(i32::MAX),
            kind: Marker::SPHERE,
            action: Marker::ADD,
            pose: msg::Pose {
                position: points[k],
                orientation: msg::Quaternion::default(),
            },
            scale: msg::Vector3 {
                x: diameter,
                y: diameter,
                z: diameter,
            },
            color: ColorRGBA {
                r: 0.2,
                g: 0.4,
                b: 1.0,
                a: 0.3,
            },
            ..Marker::default()
        }
    })
}

/// The status line of one estimate.
#[derive(Serialize)]
pub(super) struct Status {
    /// The wrench's stamp \[s\].
    pub(super) stamp: f64,
    /// The configuration the shape is of: `ã − β̂` \[N·m, N\].
    pub(super) a: [f64; 6],
    pub(super) stable: bool,
    pub(super) confident: bool,
    pub(super) contact: bool,
    /// The bias estimate `β̂` (torque first, base clamp frame) \[N·m, N\]; `None` without the
    /// observer.
    pub(super) bias: Option<[f64; 6]>,
    /// Rests so far.
    pub(super) rests: u64,
    /// The collision detector's residual of the last move, once calibrated.
    pub(super) contact_residual: Option<f64>,
    /// Which test found the contact: `detector`, `contact_miss` or `detector+contact_miss`.
    pub(super) contact_source: Option<&'static str>,
    /// `σ` at each node of the shape \[mm\], with error bars.
    pub(super) sigma_mm: Option<Vec<f64>>,
}

impl EstimateNodeParams {
    pub(super) fn validate(&self) -> Result<(), NodeError> {
        if !(1..=100_000).contains(&self.window) {
            return Err(NodeError::BadSetting {
                setting: "--window",
                value: self.window.to_string(),
                allowed: "1 to 100000 samples",
            });
        }
        if self.tare > 1_000_000 {
            return Err(NodeError::BadSetting {
                setting: "--tare",
                value: self.tare.to_string(),
                allowed: "0 to 1000000 samples",
            });
        }
        if !(self.rate.is_finite() && (1.0..=10_000.0).contains(&self.rate)) {
            return Err(NodeError::BadSetting {
                setting: "--rate",
                value: self.rate.to_string(),
                allowed: "the sensor's rate, 1 Hz to 10 kHz",
            });
        }
        check_contact_miss(self.contact_miss)?;
        if let Some(frames) = &self.tf {
            frames.validate()?;
        }
        self.observe.validate()?;
        if let Some(spec) = self.map.mounting()
            && spec.tool_mass > 0.0
        {
            return Err(NodeError::BadSetting {
                setting: "--mounting",
                value: format!("tool_mass = {} kg", spec.tool_mass),
                allowed: "a mounting without a tool: the wrench carries no gravity vector to take \
                          the tool's weight out with",
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::node::BASE_FRAME;
    use ftwire_estimate::ft::MountingSpec;

    fn params(tare: usize, window: usize) -> EstimateNodeParams {
        EstimateNodeParams {
            wire: WireSpec::load("nitinol-3mm-820").expect("a preset"),
            map: RawMap::new(None, Some(MountingSpec::default())).expect("a mounting"),
            gravity_in_clamp: None,
            points: ftwire_rig::shape::DEFAULT_POINTS,
            qos: crate::node::SensorQos::default(),
            tare,
            window,
            rate: 1000.0,
            wrench_topic: "/ft_sensor/wrench".into(),
            tip_pose_topic: "/wire/tip_pose".into(),
            tf: None,
            truth_topic: None,
            contact_miss: None,
            observe: ObserveParams::default(),
            error_bars: None,
            record: None,
        }
    }

    #[test]
    fn the_pipeline_tares_then_averages_a_window_then_maps() {
        let p = params(4, 3);
        let mut pipeline = Pipeline::new(&p).expect("valid settings");
        let offset = Vector6::new(0.3, -0.2, 0.6, 0.01, -0.008, 0.005);
        for i in 0..4 {
            assert!(pipeline.add(offset, f64::from(i) * 1e-3).is_none());
        }
        let load = Vector6::new(0.1, 0.2, -0.3, 0.01, 0.02, 0.0);
        let mut last = Vector6::zeros();
        for i in 0..10 {
            let jitter = if i % 2 == 0 { 0.01 } else { -0.01 };
            let raw = offset + load + Vector6::repeat(jitter);
            match pipeline.add(raw, 0.004 + f64::from(i) * 1e-3) {
                // Nothing until the window is full.
                None => assert!(i < 2, "sample {i}"),
                Some(a) => last = a.expect("mapped"),
            }
        }
        let mounting = MountingSpec::default().mounting().expect("valid");
        // The last three jitters average to −0.01/3.
        let expected = mounting.to_configuration(&(load + Vector6::repeat(-0.01 / 3.0)));
        assert!((last - expected).norm() < 1e-12, "{last} vs {expected}");
    }

    /// The node and `ftwire shape --log` (the lab's `LogShapes`) are one path: the same raw
    /// readings give the same `ã`, the same points and the same flags, to the bit, for the
    /// weight-free and the loaded model.
    #[test]
    fn the_node_and_shape_log_give_the_same_shapes_to_the_bit() {
        let dir = std::env::temp_dir().join(format!("ftwire-ros2-one-path-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a temporary folder");
        let mounting = MountingSpec::default().mounting().expect("valid");
        let wire = WireSpec::load("nitinol-3mm-820").expect("a preset");
        let params_of = wire.wire_params().expect("valid");
        let raws: Vec<Vector6<f64>> = (0..12)
            .map(|k| {
                let z = f64::from(k);
                let a = ftwire_rod::from_normalised(
                    &params_of,
                    &Vector6::new(0.5, 2.0 + 0.1 * z, -1.0, -3.0, 1.5, 0.5 + 0.02 * z),
                );
                // A jump at the eighth reading.
                let a = if k == 8 { a * 3.0 } else { a };
                mounting.to_sensor(&a)
            })
            .collect();
        let log = dir.join("rig.jsonl");
        let text: String = raws
            .iter()
            .enumerate()
            .map(|(k, raw)| {
                #[allow(clippy::cast_precision_loss)]
                let time = 0.25 * k as f64;
                let record = ftwire_estimate::log::LogRecord {
                    time,
                    raw: Some((*raw).into()),
                    a: None,
                    b: None,
                    markers: None,
                    gravity: None,
                };
                ftwire_estimate::log::to_line(&record).expect("a line") + "\n"
            })
            .collect();
        std::fs::write(&log, text).expect("writes the log");
        for gravity in [None, Some([0.0, 0.0, -9.81])] {
            let cli = ftwire_logs::shape::LogShapes::new(&ftwire_logs::shape::ShapeLogParams {
                mounting: Some(MountingSpec::default()),
                gravity_in_clamp: gravity,
                ..ftwire_logs::shape::ShapeLogParams::new(log.clone(), "nitinol-3mm-820")
            })
            .expect("a good log")
            .collect::<Result<Vec<_>, _>>()
            .expect("every record");
            let mut p = params(0, 1);
            p.gravity_in_clamp = gravity;
            let mut pipeline = Pipeline::new(&p).expect("valid settings");
            for (k, (raw, record)) in raws.iter().zip(&cli).enumerate() {
                #[allow(clippy::cast_precision_loss)]
                let time = 0.25 * k as f64;
                let a = pipeline
                    .add(*raw, time)
                    .expect("no tare, a window of 1")
                    .expect("ã");
                assert_eq!(a.as_slice(), record.a.as_slice(), "ã of reading {k}");
                let solved = pipeline.measurement.solve(&a, None);
                let flag = pipeline.stream.flag(&a, &solved);
                assert_eq!(flag, record.confidence, "the flag of reading {k}");
                let points: Vec<[f64; 3]> = solved
                    .expect("a shape")
                    .shape
                    .positions
                    .iter()
                    .map(|p| [p.x, p.y, p.z])
                    .collect();
                assert_eq!(points, record.points, "the points of reading {k}");
            }
            assert!(
                cli.iter().any(|r| !r.confident),
                "the jump is flagged: {:?}",
                cli.iter().map(|r| r.confidence).collect::<Vec<_>>()
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_mounting_with_a_tool_is_refused() {
        let mut p = params(0, 1);
        p.map = RawMap::new(
            None,
            Some(MountingSpec {
                tool_mass: 0.3,
                ..MountingSpec::default()
            }),
        )
        .expect("valid");
        assert!(matches!(
            p.validate(),
            Err(NodeError::BadSetting {
                setting: "--mounting",
                ..
            })
        ));
        assert!(params(0, 0).validate().is_err());
    }

    #[test]
    fn the_status_names_the_bias_the_rests_and_which_test_found_the_contact() {
        let status = Status {
            stamp: 1.5,
            a: [0.0, 0.1, 0.0, -0.2, 0.1, 0.0],
            stable: true,
            confident: false,
            contact: true,
            bias: Some([0.0, 0.0, 0.0, 0.01, 0.0, 0.0]),
            rests: 12,
            contact_residual: Some(3.5),
            contact_source: Some("detector"),
            sigma_mm: Some(vec![0.0, 0.4, 0.9]),
        };
        let json: serde_json::Value = serde_json::to_value(&status).expect("the status serialises");
        assert_eq!(json["contact_source"], "detector");
        assert_eq!(json["rests"], 12);
        assert_eq!(json["bias"].as_array().map(Vec::len), Some(6));
        assert_eq!(json["contact_residual"], 3.5);
        assert_eq!(json["sigma_mm"][2], 0.9);
        let quiet = Status {
            sigma_mm: None,
            bias: None,
            contact_residual: None,
            contact_source: None,
            contact: false,
            ..status
        };
        let json = serde_json::to_value(&quiet).expect("the status serialises");
        assert!(json["bias"].is_null() && json["contact_source"].is_null());
        assert!(json["sigma_mm"].is_null());
    }

    #[test]
    fn the_drawn_wire_is_green_when_confident_and_the_sphere_is_deleted_without_contact() {
        let h = super::super::header(0.0, BASE_FRAME);
        let points = [
            msg::Point::default(),
            msg::Point {
                x: 0.5,
                y: 0.0,
                z: 0.0,
            },
        ];
        let free = markers(&h, &points, true, None, None);
        assert_eq!(free.markers.len(), 2, "no error bars without sigma");
        assert_eq!(free.markers[0].kind, Marker::LINE_STRIP);
        assert!(free.markers[0].color.g > free.markers[0].color.r);
        assert_eq!(free.markers[1].action, Marker::DELETE);
        let touched = markers(&h, &points, false, Some(&points[1]), None);
        assert!(touched.markers[0].color.r > touched.markers[0].color.g);
        assert_eq!(
            (touched.markers[1].kind, touched.markers[1].action),
            (Marker::SPHERE, Marker::ADD)
        );
        // With σ: the tube's spheres, 4σ across, the last at the tip.
        let wire: Vec<msg::Point> = (0..17)
            .map(|k| msg::Point {
                x: 0.05 * f64::from(k),
                y: 0.0,
                z: 0.0,
            })
            .collect();
        let sigma: Vec<f64> = (0..17).map(|k| 1e-4 * f64::from(k)).collect();
        let barred = markers(&h, &wire, true, None, Some(&sigma));
        let tube: Vec<&Marker> = barred.markers.iter().filter(|m| m.ns == "sigma").collect();
        assert_eq!(tube.len(), SIGMA_SPHERES);
        let tip = tube[SIGMA_SPHERES - 1];
        assert!((tip.pose.position.x - 0.8).abs() < 1e-12);
        assert!((tip.scale.x - 4.0 * 1.6e-3).abs() < 1e-12);
        assert!(tube[0].pose.position.x > 0.0, "not at the base clamp");
        // A σ of another length is not drawn.
        assert_eq!(
            markers(&h, &wire, true, None, Some(&sigma[..3]))
                .markers
                .len(),
            2
        );
    }
}
