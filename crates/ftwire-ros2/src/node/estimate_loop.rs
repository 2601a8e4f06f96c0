//! `ftwire ros2 estimate`'s receive–estimate–publish loop, [`run`] (the steps are in
//! [`super::estimate`]), and `--record`: every message the node receives and publishes, written
//! to a ROS 2 bag (MCAP, CDR) at its arrival or publication time, so that `ftwire import mcap`
//! reads the inputs back and Foxglove or `ros2 bag` replay the whole session.

use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use ftwire_estimate::shape::marker_distances;
use nalgebra::{Vector3, Vector6};
use ros2_client::dds::rustdds::mio1::{Events, Interest, Poll, Token};
use ros2_client::{MessageInfo, Publisher, QosProfile, Subscription};

use super::estimate::{
    EstimateNodeParams, EstimateSummary, Pending, Pipeline, Status, TruthError, arrival,
    finite_wrench, markers, now_ns,
};
use super::observe::{Observer, RestEvent};
use super::sigma::{Coverage, SigmaSummary};
use super::stats::{LossCounter, Spread};
use super::tf::{TF_STATIC_TOPIC, TF_TOPIC, TfListener, tf_qos, tf_static_qos};
use super::{
    BASE_FRAME, Counts, Log, MARKERS_VIZ_TOPIC, NodeError, NodeSettings, RosNode, SENSOR_FRAME,
    SHAPE_TOPIC, STATUS_TOPIC, WRENCH_QUEUE, count, publish, reliable, seconds, should_stop,
};
use crate::bag::BagWriter;
use crate::msg::{
    self, MarkerArray, Path, PoseStamped, RosMessage, StringMsg, TFMessage, WrenchStamped,
};
use crate::node::pose::{pose_of, ros_point};
use crate::node::{path_message, path_points};

/// Longest wait in one poll, so that a stop or the end of the duration is seen \[ms\].
const POLL_MS: u64 = 20;

/// The node's subscriptions, publishers and the poll that wakes it.
struct Io {
    wrench: Subscription<WrenchStamped>,
    /// The tip pose topic, or the TF frames.
    tip: Option<Subscription<PoseStamped>>,
    tf: Option<TfListener>,
    truth: Option<Subscription<Path>>,
    shape: Publisher<Path>,
    markers: Publisher<MarkerArray>,
    status: Publisher<StringMsg>,
    poll: Poll,
    events: Events,
}

fn ros_error(what: &str, e: &std::io::Error) -> NodeError {
    NodeError::Ros {
        what: what.to_owned(),
        message: e.to_string(),
    }
}

/// Each topic the node subscribes to or publishes, with its QoS (what `--record` writes as
/// the topic's `offered_qos_profiles`).
fn topic_qos(params: &EstimateNodeParams) -> Vec<(String, QosProfile)> {
    let small = reliable(10);
    let mut topics = vec![(
        params.wrench_topic.clone(),
        params.qos.profile(WRENCH_QUEUE),
    )];
    if params.tf.is_some() {
        topics.push((TF_TOPIC.to_owned(), tf_qos()));
        topics.push((TF_STATIC_TOPIC.to_owned(), tf_static_qos(false)));
    } else {
        topics.push((params.tip_pose_topic.clone(), small.clone()));
    }
    if let Some(topic) = &params.truth_topic {
        topics.push((topic.clone(), small.clone()));
    }
    for topic in [SHAPE_TOPIC, MARKERS_VIZ_TOPIC, STATUS_TOPIC] {
        topics.push((topic.to_owned(), small.clone()));
    }
    topics
}

impl Io {
    fn open(node: &mut RosNode, params: &EstimateNodeParams) -> Result<Self, NodeError> {
        let small = reliable(10);
        let mut wrench = node.subscription::<WrenchStamped>(
            &params.wrench_topic,
            &params.qos.profile(WRENCH_QUEUE),
        )?;
        let (mut tip, mut tf) = match &params.tf {
            Some(frames) => (None, Some(TfListener::open(node, frames)?)),
            None => (
                Some(node.subscription::<PoseStamped>(&params.tip_pose_topic, &small)?),
                None,
            ),
        };
        let mut truth = params
            .truth_topic
            .as_deref()
            .map(|topic| node.subscription::<Path>(topic, &small))
            .transpose()?;
        let poll = Poll::new().map_err(|e| ros_error("a poll", &e))?;
        poll.registry()
            .register(&mut wrench, Token(0), Interest::READABLE)
            .map_err(|e| ros_error("a poll of the wrench", &e))?;
        if let Some(sub) = tip.as_mut() {
            poll.registry()
                .register(sub, Token(1), Interest::READABLE)
                .map_err(|e| ros_error("a poll of the tip pose", &e))?;
        }
        if let Some(listener) = tf.as_mut() {
            listener
                .register(poll.registry(), 3)
                .map_err(|e| ros_error("a poll of TF", &e))?;
        }
        if let Some(sub) = truth.as_mut() {
            poll.registry()
                .register(sub, Token(2), Interest::READABLE)
                .map_err(|e| ros_error("a poll of the truth", &e))?;
        }
        Ok(Self {
            wrench,
            tip,
            tf,
            truth,
            shape: node.publisher::<Path>(SHAPE_TOPIC, &small)?,
            markers: node.publisher::<MarkerArray>(MARKERS_VIZ_TOPIC, &small)?,
            status: node.publisher::<StringMsg>(STATUS_TOPIC, &small)?,
            poll,
            events: Events::with_capacity(16),
        })
    }

    /// Waits for a message or [`POLL_MS`].
    fn wait(&mut self) -> Result<(), NodeError> {
        match self
            .poll
            .poll(&mut self.events, Some(Duration::from_millis(POLL_MS)))
        {
            Err(e) if e.kind() != std::io::ErrorKind::Interrupted => Err(ros_error("polling", &e)),
            _ => Ok(()),
        }
    }
}

/// `--record`: the bag and what went into it.
struct Recorder {
    bag: BagWriter,
    written: u64,
    failed: u64,
    first_error: Option<String>,
}

impl Recorder {
    fn write<M: RosMessage>(&mut self, topic: &str, time_ns: i64, message: &M) {
        let time = u64::try_from(time_ns).unwrap_or(0);
        match self.bag.write(topic, time, message) {
            Ok(()) => self.written += 1,
            Err(e) => {
                self.failed += 1;
                self.first_error.get_or_insert_with(|| e.to_string());
            }
        }
    }
}

/// Records `message` on `topic` when recording.
fn record<M: RosMessage>(recorder: &mut Option<Recorder>, topic: &str, time_ns: i64, m: &M) {
    if let Some(r) = recorder.as_mut() {
        r.write(topic, time_ns, m);
    }
}

/// The running state of the loop.
struct State<'p> {
    params: &'p EstimateNodeParams,
    recorder: Option<Recorder>,
    summary: EstimateSummary,
    pipeline: Pipeline,
    loss: LossCounter,
    tip: Option<Vector3<f64>>,
    shape: Vec<Vector3<f64>>,
    /// `σ` of the latest shape at its nodes \[m\], with error bars.
    sigma: Option<Vec<f64>>,
    /// `σ` at the tip of each shape published \[m\].
    tip_sigmas: Vec<f64>,
    /// The error bars against the truth.
    coverage: Coverage,
    latencies: Vec<f64>,
    solves: Vec<f64>,
    /// Sum, worst and largest node distance \[mm\], and the count of true centrelines.
    truth: (f64, f64, f64, u64),
    index: usize,
    batch: Vec<Pending>,
    stale_ns: i64,
    tared_logged: bool,
    last_error: Option<String>,
    /// Rests, the bias observer and the collision detector.
    observe: Observer,
}

impl<'p> State<'p> {
    fn new(
        params: &'p EstimateNodeParams,
        pipeline: Pipeline,
        recorder: Option<Recorder>,
        observe: Observer,
    ) -> Self {
        #[allow(clippy::cast_possible_truncation)] // a period of at least 0.1 ms
        let stale_ns = (1e9 / params.rate) as i64;
        Self {
            params,
            recorder,
            summary: EstimateSummary {
                node: "estimate",
                received: Counts::new(),
                published: Counts::new(),
                refused: Counts::new(),
                publish_failed: Counts::new(),
                lost: 0,
                qos_mismatch: 0,
                out_of_order: 0,
                first_sample: None,
                dropped: 0,
                no_shape: 0,
                not_confident: 0,
                contacts: 0,
                rests: 0,
                contact_moves: 0,
                bias_observer: None,
                detector: None,
                latency_ms: None,
                solve_ms: None,
                truth: None,
                sigma: None,
                recorded: None,
                tf: None,
            },
            pipeline,
            loss: LossCounter::new(params.rate),
            tip: None,
            shape: Vec::new(),
            sigma: None,
            tip_sigmas: Vec::new(),
            coverage: Coverage::default(),
            latencies: Vec::with_capacity(1 << 16),
            solves: Vec::with_capacity(1 << 16),
            truth: (0.0, 0.0, 0.0, 0),
            index: 0,
            batch: Vec::with_capacity(WRENCH_QUEUE),
            stale_ns,
            tared_logged: params.tare == 0,
            last_error: None,
            observe,
        }
    }

    /// Logs an error once in a row.
    fn note(&mut self, log: Log<'_>, error: String, line: impl FnOnce(&str) -> String) {
        if self.last_error.as_ref() != Some(&error) {
            log(&line(&error));
            self.last_error = Some(error);
        }
    }

    /// Takes every tip pose waiting: the contact check of the next batch uses the latest, and
    /// each goes to the rest detection.
    fn take_tips(&mut self, sub: &Subscription<PoseStamped>, log: Log<'_>) {
        loop {
            match sub.take() {
                Ok(Some((pose, info))) => {
                    count(&mut self.summary.received, "tip_pose");
                    record(
                        &mut self.recorder,
                        &self.params.tip_pose_topic,
                        arrival(&info),
                        &pose,
                    );
                    if pose.header.frame_id != BASE_FRAME {
                        count(&mut self.summary.refused, "frame_id");
                    } else {
                        match pose_of(&pose.pose) {
                            Ok(p) => {
                                self.tip = Some(p.translation.vector);
                                let t = seconds(&pose.header.stamp);
                                let tare = self.pipeline.tare();
                                let events = self.observe.pose(t, &p, tare, &self.params.map);
                                log_rests(&events, log);
                            }
                            Err(_) => count(&mut self.summary.refused, "non_finite"),
                        }
                    }
                }
                Ok(None) => break,
                Err(_) => count(&mut self.summary.refused, "malformed"),
            }
        }
    }

    /// Takes every TF message waiting into the listener's buffer (and the bag).
    fn take_tf(&mut self, listener: &mut TfListener, log: Log<'_>) {
        let recorder = &mut self.recorder;
        let mut record_tf = |topic: &str, info: &MessageInfo, message: &TFMessage| {
            record(recorder, topic, arrival(info), message);
        };
        listener.take(
            &mut self.summary.received,
            &mut self.summary.refused,
            &mut record_tf,
            log,
        );
    }

    /// The tip from TF at the newest wrench's stamp (none before the first wrench).
    fn tip_from_tf(&mut self, listener: &mut TfListener, log: Log<'_>) {
        #[allow(clippy::cast_precision_loss)] // sample indices far below 2⁵²
        let now = self.loss.last().map(|k| k as f64 / self.params.rate);
        let pose = now.and_then(|now| listener.tip(now, log).map(|pose| (now, pose)));
        self.tip = pose.map(|(_, pose)| pose.translation.vector);
        if let Some((t, p)) = pose {
            let tare = self.pipeline.tare();
            let events = self.observe.pose(t, &p, tare, &self.params.map);
            log_rests(&events, log);
        }
    }

    /// Takes every wrench waiting through steps 1–3 into the batch.
    fn take_wrenches(&mut self, sub: &Subscription<WrenchStamped>, log: Log<'_>) {
        self.batch.clear();
        loop {
            match sub.take() {
                Ok(Some((wrench, info))) => {
                    count(&mut self.summary.received, "wrench");
                    let arrival_ns = arrival(&info);
                    let topic = &self.params.wrench_topic;
                    record(&mut self.recorder, topic, arrival_ns, &wrench);
                    self.add_wrench(&wrench, arrival_ns, log);
                }
                Ok(None) => break,
                Err(_) => count(&mut self.summary.refused, "malformed"),
            }
        }
        if !self.tared_logged && self.pipeline.tare().is_some() {
            self.tared_logged = true;
            log(&format!(
                "estimate: tared on {} samples from k = {}",
                self.params.tare,
                self.loss.first().unwrap_or_default()
            ));
        }
    }

    fn add_wrench(&mut self, wrench: &WrenchStamped, arrival_ns: i64, log: Log<'_>) {
        if wrench.header.frame_id != SENSOR_FRAME {
            count(&mut self.summary.refused, "frame_id");
            return;
        }
        let Some(raw) = finite_wrench(&wrench.wrench) else {
            count(&mut self.summary.refused, "non_finite");
            return;
        };
        let t = seconds(&wrench.header.stamp);
        self.loss.add(t);
        if let Some(tare) = self.pipeline.tare() {
            let events = self.observe.sample(t, raw, Some(tare), &self.params.map);
            log_rests(&events, log);
        }
        match self.pipeline.add(raw, t) {
            None => {}
            Some(Ok(a)) => self.batch.push(Pending {
                stamp: wrench.header.stamp,
                a,
                arrival_ns,
            }),
            Some(Err(e)) => {
                self.summary.no_shape += 1;
                self.note(log, e, |e| format!("estimate: no ã at t = {t:.3} s: {e}"));
            }
        }
    }

    /// Step 4–5 and the publications of the batch, skipping stale samples.
    fn publish_batch(&mut self, io: &Io, log: Log<'_>) {
        let batch = std::mem::take(&mut self.batch);
        let waiting = batch.len();
        for (i, sample) in batch.iter().enumerate() {
            // A sample with a newer one behind it, waiting longer than its period: stale.
            if i + 1 < waiting && now_ns() - sample.arrival_ns > self.stale_ns {
                self.summary.dropped += 1;
                continue;
            }
            self.estimate(sample, io, log);
        }
        self.batch = batch;
    }

    fn estimate(&mut self, sample: &Pending, io: &Io, log: Log<'_>) {
        let solve_start = Instant::now();
        // The bias estimate taken out, as the experiments' controller steers by it.
        let a = self.observe.correct(&sample.a);
        let time = seconds(&sample.stamp);
        let covariance = self.params.error_bars.as_ref().map(|bars| {
            let since_tare = self.pipeline.tare_time().map_or(0.0, |t| time - t);
            bars.covariance(&a, since_tare, self.observe.bias_covariance(time))
        });
        let solved = self.pipeline.measurement.solve(&a, covariance.as_ref());
        let confidence = self.pipeline.stream.flag(&a, &solved);
        self.index += 1;
        self.solves.push(1e3 * solve_start.elapsed().as_secs_f64());
        match solved {
            Ok(solved) => {
                self.shape.clear();
                self.shape.extend(solved.shape.positions.iter().copied());
                self.sigma = solved.sigma;
                let flags = (confidence.is_stable(), confidence.is_confident());
                self.publish(sample, &a, io, flags);
            }
            Err(e) => {
                self.summary.no_shape += 1;
                self.note(log, e, |e| {
                    format!("estimate: no shape for ã = {:?}: {e}", a.as_slice())
                });
            }
        }
    }

    /// Publishes (and records) the shape of `a` (the sample's `ã`, corrected), the drawn wire
    /// and the status of `sample`.
    fn publish(
        &mut self,
        sample: &Pending,
        a: &Vector6<f64>,
        io: &Io,
        (stable, confident): (bool, bool),
    ) {
        let missed = matches!(
            (self.params.contact_miss, self.tip, self.shape.last()),
            (Some(miss), Some(tip), Some(end)) if (end - tip).norm() > miss
        );
        let residual = self.observe.residual();
        let detected = residual.is_some_and(|(_, contact)| contact);
        let source = match (detected, missed) {
            (true, true) => Some("detector+contact_miss"),
            (true, false) => Some("detector"),
            (false, true) => Some("contact_miss"),
            (false, false) => None,
        };
        // The detector gives no location: the contact is drawn at the shape's tip.
        let contact = source.and(self.shape.last().map(ros_point));
        self.summary.not_confident += u64::from(!confident);
        self.summary.contacts += u64::from(contact.is_some());
        // The shape is in the base clamp's frame: with TF, the frame the user named for it.
        let frame_id = self
            .params
            .tf
            .as_ref()
            .map_or(BASE_FRAME, |frames| frames.base.as_str());
        let header = msg::Header {
            stamp: sample.stamp,
            frame_id: frame_id.to_owned(),
        };
        let ros_points: Vec<msg::Point> = self.shape.iter().map(ros_point).collect();
        let path = path_message(header.clone(), ros_points.iter().copied());
        let sigma = self.sigma.as_deref();
        let drawn = markers(&header, &ros_points, confident, contact.as_ref(), sigma);
        if let Some(tip) = sigma.and_then(<[f64]>::last) {
            self.tip_sigmas.push(*tip);
        }
        let status = Status {
            stamp: seconds(&sample.stamp),
            a: (*a).into(),
            stable,
            confident,
            contact: contact.is_some(),
            bias: self.observe.bias(),
            rests: self.observe.count,
            contact_residual: residual.map(|(r, _)| r),
            contact_source: source,
            sigma_mm: sigma.map(|s| s.iter().map(|v| 1e3 * v).collect()),
        };
        let status = serde_json::to_string(&status)
            .ok()
            .map(|data| StringMsg { data });
        if self.recorder.is_some() {
            let now = now_ns();
            record(&mut self.recorder, SHAPE_TOPIC, now, &path);
            record(&mut self.recorder, MARKERS_VIZ_TOPIC, now, &drawn);
            if let Some(status) = status.as_ref() {
                record(&mut self.recorder, STATUS_TOPIC, now, status);
            }
        }
        let (published, failed) = (
            &mut self.summary.published,
            &mut self.summary.publish_failed,
        );
        publish(&io.shape, path, "shape", published, failed);
        publish(&io.markers, drawn, "markers_viz", published, failed);
        if let Some(status) = status {
            publish(&io.status, status, "status", published, failed);
        }
        #[allow(clippy::cast_precision_loss)] // nanoseconds of a short latency
        self.latencies
            .push(1e-6 * (now_ns() - sample.arrival_ns) as f64);
    }

    /// Compares each true centreline waiting with the latest shape.
    fn take_truth(&mut self, sub: &Subscription<Path>) {
        loop {
            match sub.take() {
                Ok(Some((truth, info))) => {
                    count(&mut self.summary.received, "truth");
                    if let Some(topic) = self.params.truth_topic.as_deref() {
                        record(&mut self.recorder, topic, arrival(&info), &truth);
                    }
                    if truth.header.frame_id != BASE_FRAME {
                        count(&mut self.summary.refused, "frame_id");
                        continue;
                    }
                    let nodes = path_points(&truth);
                    if self.shape.len() < 2 {
                        continue;
                    }
                    match marker_distances(&nodes, &self.shape) {
                        Ok(d) if !d.is_empty() => {
                            if let Some(sigma) = &self.sigma {
                                let truth: Vec<Vector3<f64>> =
                                    nodes.iter().map(|p| p.coords).collect();
                                self.coverage.add(&truth, &self.shape, sigma);
                            }
                            #[allow(clippy::cast_precision_loss)] // a few hundred nodes
                            let mean = 1e3 * d.iter().sum::<f64>() / d.len() as f64;
                            let (sum, worst, max, n) = &mut self.truth;
                            *sum += mean;
                            *worst = worst.max(mean);
                            *max = d.iter().fold(*max, |m, v| m.max(1e3 * v));
                            *n += 1;
                        }
                        _ => count(&mut self.summary.refused, "non_finite"),
                    }
                }
                Ok(None) => break,
                Err(_) => count(&mut self.summary.refused, "malformed"),
            }
        }
    }

    /// The summary, the bag closed.
    fn finish(mut self, log: Log<'_>) -> Result<EstimateSummary, NodeError> {
        let mut summary = self.summary;
        summary.lost = self.loss.lost();
        summary.out_of_order = self.loss.out_of_order();
        summary.first_sample = self.loss.first();
        summary.latency_ms = Spread::of(&mut self.latencies);
        summary.solve_ms = Spread::of(&mut self.solves);
        summary.rests = self.observe.count;
        summary.contact_moves = self.observe.contact_moves;
        summary.bias_observer = self.observe.observer();
        summary.detector = self.observe.detector();
        let (sum, worst, max, n) = self.truth;
        #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
        if n > 0 {
            summary.truth = Some(TruthError {
                compared: n,
                mean_mm: sum / n as f64,
                worst_mean_mm: worst,
                max_mm: max,
            });
        }
        if !self.tip_sigmas.is_empty() {
            #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
            let n = self.tip_sigmas.len() as f64;
            summary.sigma = Some(SigmaSummary {
                tip_mean_mm: 1e3 * self.tip_sigmas.iter().sum::<f64>() / n,
                tip_max_mm: 1e3 * self.tip_sigmas.iter().copied().fold(0.0, f64::max),
                within_2sigma: self.coverage.share(),
            });
        }
        log(&format!(
            "estimate: stopped; {} wrenches received, {} lost, {} dropped as stale",
            summary.received.get("wrench").copied().unwrap_or(0),
            summary.lost,
            summary.dropped
        ));
        if let Some(recorder) = self.recorder {
            if let Some(e) = &recorder.first_error {
                log(&format!(
                    "estimate: {} messages not recorded: {e}",
                    recorder.failed
                ));
            }
            let (written, failed) = (recorder.written, recorder.failed);
            let path = recorder.bag.finish().map_err(|e| {
                NodeError::Lab(ftwire_app::LabError::no_answer(format!("--record: {e}")))
            })?;
            log(&format!(
                "estimate: recorded {written} messages into {}",
                path.display()
            ));
            summary.recorded = Some(super::estimate::Recorded { written, failed });
        }
        Ok(summary)
    }
}

/// Runs the estimator (module docs of [`super::estimate`]) until `settings.duration` ends or
/// `stop` is set.
///
/// # Errors
/// [`NodeError`] for bad settings, a bad wire, a `--record` file that exists (without
/// overwrite) or cannot be created, or ROS 2 entities that cannot be created. Bad messages are
/// refused and counted, never errors.
pub fn run(
    params: &EstimateNodeParams,
    settings: NodeSettings,
    stop: &AtomicBool,
    log: Log<'_>,
) -> Result<EstimateSummary, NodeError> {
    settings.validate()?;
    params.validate()?;
    let started = Instant::now();
    // The wire is checked before anything is opened.
    params
        .wire
        .wire_params()
        .map_err(|e| NodeError::BadSetting {
            setting: "--wire",
            value: format!("{} ({e})", params.wire.name),
            allowed: "a wire with valid parameters",
        })?;
    let recorder = match &params.record {
        Some(r) => {
            let bad = |e: crate::bag::BagError| {
                NodeError::Lab(ftwire_app::LabError::bad_input(format!("--record: {e}")))
            };
            let mut bag = BagWriter::create(&r.path, r.overwrite).map_err(bad)?;
            for (topic, qos) in topic_qos(params) {
                bag.set_qos(&topic, &qos).map_err(bad)?;
            }
            Some(Recorder {
                bag,
                written: 0,
                failed: 0,
                first_error: None,
            })
        }
        None => None,
    };
    let mut node = RosNode::new("ftwire_estimate", settings.domain_id)?;
    let mut io = Io::open(&mut node, params)?;
    let tip_source = match &params.tf {
        Some(f) => format!(
            "{TF_TOPIC} and {TF_STATIC_TOPIC} (the tip frame {:?} in {:?})",
            f.tip, f.base
        ),
        None => format!("{} (frame {BASE_FRAME})", params.tip_pose_topic),
    };
    log(&format!(
        "estimate: domain {}; subscribed to {} (frame {SENSOR_FRAME}) and {tip_source}{}; \
         publishing {SHAPE_TOPIC}, {MARKERS_VIZ_TOPIC}, {STATUS_TOPIC}; wire {}, tare {} \
         samples, window {}{}",
        settings.domain_id,
        params.wrench_topic,
        params
            .truth_topic
            .as_ref()
            .map_or_else(String::new, |t| format!(" and {t}")),
        params.wire.name,
        params.tare,
        params.window,
        params.record.as_ref().map_or_else(String::new, |r| format!(
            "; recording into {}",
            r.path.display()
        ))
    ));
    let pipeline = Pipeline::new(params)?;
    let observe = Observer::new(*pipeline.measurement.model(), &params.observe)?;
    let mut state = State::new(params, pipeline, recorder, observe);
    while !should_stop(stop, started, settings.duration) {
        io.wait()?;
        if let Some(sub) = io.tip.as_ref() {
            state.take_tips(sub, log);
        }
        if let Some(listener) = io.tf.as_mut() {
            state.take_tf(listener, log);
        }
        state.take_wrenches(&io.wrench, log);
        if let Some(listener) = io.tf.as_mut() {
            state.tip_from_tf(listener, log);
        }
        state.publish_batch(&io, log);
        if let Some(sub) = io.truth.as_ref() {
            state.take_truth(sub);
        }
    }
    state.summary.tf = io.tf.as_ref().map(TfListener::summary);
    state.summary.qos_mismatch =
        node.qos_mismatches(&params.wrench_topic, &params.qos.profile(WRENCH_QUEUE));
    if state.summary.qos_mismatch > 0 {
        log(&format!(
            "estimate: {} publisher(s) of {} offer a QoS that --qos {} does not match: none of \
             their samples arrive",
            state.summary.qos_mismatch,
            params.wrench_topic,
            params.qos.name()
        ));
    }
    state.finish(log)
}

/// Logs what the rests gave: each rest, the detector's calibration and each contact.
fn log_rests(events: &[RestEvent], log: Log<'_>) {
    for event in events {
        match event {
            RestEvent::Rest {
                index,
                time,
                samples,
                residual,
                contact,
                bias_used,
            } => log(&format!(
                "estimate: rest {index} at t = {time:.3} s ({samples} samples){}{}",
                match bias_used {
                    Some(true) => "; bias observer updated",
                    Some(false) => "; beyond the bias observer's gate",
                    None => "",
                },
                residual.map_or_else(String::new, |r| format!(
                    "; move residual {r:.3}{}",
                    if *contact { ": CONTACT" } else { "" }
                ))
            )),
            RestEvent::Calibrated(d) => log(&format!(
                "estimate: collision detector calibrated on {} free moves: threshold {:.3}, \
                 floor {:.4}, slope {:.3}, window {}",
                d.calibrated_on, d.threshold, d.floor, d.slope, d.window
            )),
            RestEvent::NotCalibrated(e) => log(&format!("estimate: {e}; trying again")),
            RestEvent::Failed(e) => log(&format!("estimate: a rest not measured: {e}")),
        }
    }
}
