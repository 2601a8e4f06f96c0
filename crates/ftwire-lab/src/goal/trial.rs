//! A trial of the goal experiment: what it needs that does not change between trials
//! ([`Context`]), the placed and tared rig it runs on, the simulator's truth at each rest,
//! and the open loop along given poses.

use ftwire_control::open_loop::roll_out;
use ftwire_control::{AnyPose, BiasObserverParams, FtFeedback, NoiseModel, NoiseParams, NoisyRig};
use ftwire_core::{Pose, WireParams};
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::shape::{DEFAULT_METRIC_SAMPLES, centreline_distance};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_rod::to_normalised;
use ftwire_sim::{BoxObstacle, SimRig};
use nalgebra::{Vector3, Vector6};

use crate::error::{LabError, from_estimate};
use crate::experiment::calibration::rig_seed;
use crate::experiment::rig::{
    SAMPLES_PER_REST, bias_observer, pipeline, place_among, tare, touches,
};
use crate::experiment::{Gravity, ModelKind};
use crate::setup::SimSetup;
use crate::wire::WireSpec;

/// One start–goal pair.
pub(super) struct Pair {
    pub(super) a_s: Vector6<f64>,
    pub(super) a_g: Vector6<f64>,
    /// The steering model's `Φ(a_g)` \[m\].
    pub(super) goal_shape: Vec<Vector3<f64>>,
    /// The steering model's `Φ(a_s)` \[m\].
    pub(super) start_shape: Vec<Vector3<f64>>,
}

/// Nodes of the model shapes.
const SHAPE_NODES: usize = 64;

/// Everything a trial needs that does not change between trials.
pub(super) struct Context<'a> {
    pub(super) wire: &'a WireSpec,
    /// The steering model's wire parameters (its normalisation).
    pub(super) params: WireParams,
    pub(super) gravity: Gravity,
    pub(super) model: KirchhoffModel,
    /// Which model `model` is: a loaded model places the true wire at its own `Γ(a_s)`.
    pub(super) kind: ModelKind,
    pub(super) calibration: &'a Calibration,
    /// The simulated sensor and rig.
    pub(super) rig: &'a SimSetup,
    pub(super) seed: u64,
    /// Steer the closed loop by `ã` corrected for the sensor's drift.
    pub(super) bias_observer: bool,
}

/// A placed, tared rig of a trial and its feedback.
pub(super) type TrialRig = (NoisyRig<SimRig>, FtFeedback<Calibration>);

/// The ground truth at one rest.
#[derive(Debug, Clone, Copy)]
pub(super) struct Truth {
    /// Mean distance of the true centreline to `Φ(a_g)` \[mm\].
    pub(super) shape_mm: f64,
    /// `‖N(a_true − a_g)‖` \[normalised\].
    pub(super) a_error: f64,
    pub(super) contact: bool,
    /// Total contact force on the obstacles \[N\].
    pub(super) contact_force: f64,
    /// The last move snapped the wire to another branch (simulator's report).
    pub(super) snapped: bool,
}

impl Truth {
    /// The truth of a trial that could not run: no distances, no contact.
    pub(super) fn unknown() -> Self {
        Self {
            shape_mm: f64::NAN,
            a_error: f64::NAN,
            contact: false,
            contact_force: 0.0,
            snapped: false,
        }
    }
}

/// An open-loop trial.
pub(super) struct OpenTrial {
    /// The truth where the roll-out ended.
    pub(super) truth: Truth,
    pub(super) failure: Option<String>,
    /// The measured `ã` after each move (`None` where the measurement failed).
    pub(super) measured: Vec<Option<Vector6<f64>>>,
    /// Truth at the start and after each move.
    pub(super) truths: Vec<Truth>,
}

impl Context<'_> {
    /// The steering model's shape `Φ(a)`.
    pub(super) fn shape(&self, a: &Vector6<f64>) -> Result<Vec<Vector3<f64>>, LabError> {
        Ok(self
            .model
            .shape(a, SHAPE_NODES)
            .map_err(|e| from_estimate(e, "the model's shape"))?
            .positions)
    }

    /// The reach check of the runs: none, as in the paper's Table III (see the module docs).
    pub(super) fn reach(&self) -> AnyPose {
        AnyPose
    }

    /// The simulator's truth of `rig` against the goal of `pair`.
    pub(super) fn truth(&self, rig: &SimRig, pair: &Pair) -> Result<Truth, LabError> {
        let equilibrium = rig.equilibrium();
        let centreline: Vec<Vector3<f64>> = equilibrium
            .wire_centreline()
            .iter()
            .map(|p| p.coords)
            .collect();
        let distance = centreline_distance(&pair.goal_shape, &centreline, DEFAULT_METRIC_SAMPLES)
            .map_err(|e| from_estimate(e, "the shape error"))?;
        let a_true = equilibrium.base_wrench.to_vector();
        Ok(Truth {
            shape_mm: 1e3 * distance,
            a_error: to_normalised(&self.params, &(a_true - pair.a_g)).norm(),
            contact: touches(&equilibrium.contact_forces),
            contact_force: equilibrium.contact_forces.iter().map(|f| f.norm()).sum(),
            snapped: rig
                .simulator()
                .last_motion()
                .is_some_and(|m| !m.snaps.is_empty()),
        })
    }

    /// The bias observer of a closed loop under `noise`, when it is on and the noise model
    /// uses one ([`bias_observer`]).
    pub(super) fn observer_settings(&self, noise: NoiseModel) -> Option<BiasObserverParams> {
        bias_observer(self.rig, noise, self.bias_observer)
    }

    /// The placed, tared rig of trial `k` (with `obstacles`) and its feedback; `None` when the
    /// simulator cannot place the wire.
    pub(super) fn rig(
        &self,
        pair: &Pair,
        k: u64,
        noise: NoiseModel,
        obstacles: &[BoxObstacle],
    ) -> Result<Option<TrialRig>, LabError> {
        let config = self
            .rig
            .rig_config(rig_seed(self.seed.wrapping_add(0x60A1), k as usize));
        // The start is `a_s` of the steering model: under the loaded model the true wire's
        // base wrench is then `a_s`, as the pair was drawn (under the weightless one it sags).
        let placed = place_among(
            self.wire,
            self.gravity,
            self.kind,
            &pair.a_s,
            config,
            obstacles,
        );
        let Ok(mut sim) = placed else {
            return Ok(None);
        };
        let tare = tare(&mut sim)?;
        let feedback = FtFeedback::new(pipeline(tare, self.calibration.clone())?, SAMPLES_PER_REST);
        let noisy = NoisyRig::new(
            sim,
            noise,
            NoiseParams::default(),
            rig_seed(self.seed.wrapping_add(0x5EED), k as usize),
        )
        .map_err(|e| LabError::bad_input(e.to_string()))?;
        Ok(Some((noisy, feedback)))
    }

    /// The open loop along `poses` on `pair`.
    pub(super) fn open(
        &self,
        pair: &Pair,
        k: u64,
        noise: NoiseModel,
        poses: &[Pose],
    ) -> Result<OpenTrial, LabError> {
        let Some((mut rig, feedback)) = self.rig(pair, k, noise, &[])? else {
            return Ok(OpenTrial {
                truth: Truth::unknown(),
                failure: Some("the simulator could not place the wire".into()),
                measured: Vec::new(),
                truths: Vec::new(),
            });
        };
        let mut truths = vec![self.truth(rig.inner(), pair)?];
        let mut truth_error = None;
        let out = roll_out(&mut rig, poses, Some(&feedback), |rig, _| {
            match self.truth(rig.inner(), pair) {
                Ok(t) => truths.push(t),
                Err(e) => truth_error = Some(e),
            }
        })
        .map_err(|e| LabError::no_answer(e.to_string()))?;
        if let Some(e) = truth_error {
            return Err(e);
        }
        Ok(OpenTrial {
            truth: self.truth(rig.inner(), pair)?,
            failure: out
                .failed
                .map(|(step, message)| format!("move {step}: {message}")),
            measured: out.measured,
            truths,
        })
    }
}
