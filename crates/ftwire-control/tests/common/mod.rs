//! A small fake rig on the Kirchhoff model itself (not the simulator): the wire is at the
//! configuration `a` whose `Γ(a)` is the commanded tip pose, found by Newton's method from the
//! previous configuration, so the model is exact on it. Faults can be switched on.
#![allow(dead_code)]

use ftwire_control::{ControlParams, FtFeedback};
use ftwire_core::{Command, FtSample, GripperPoses, Pose, Rig, WireParams};
use ftwire_estimate::ft::{FtPipeline, Mounting, RestAverage, Tare};
use ftwire_rod::{Rod, from_normalised, se3};
use nalgebra::Vector6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// The 3 mm / 820 mm nitinol wire.
pub fn wire() -> WireParams {
    WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid wire")
}

/// A start and a goal in A_free of [`wire`], A-connected (normalised units given).
pub fn pair() -> (Vector6<f64>, Vector6<f64>) {
    let w = wire();
    (
        from_normalised(&w, &Vector6::new(0.5, 2.0, 1.0, -2.0, 3.0, 0.5)),
        from_normalised(&w, &Vector6::new(0.2, 3.0, 0.5, -1.0, 2.0, 1.0)),
    )
}

/// Feedback that averages a few samples through the identity mounting.
pub fn feedback() -> FtFeedback<Mounting> {
    FtFeedback::new(
        FtPipeline::new(
            RestAverage::new(2).expect("valid"),
            Tare::none(),
            Mounting::default(),
        ),
        3,
    )
}

/// Default settings with a tight stop.
pub fn settings() -> ControlParams {
    ControlParams {
        epsilon: 1e-3,
        ..ControlParams::default()
    }
}

#[derive(Debug, thiserror::Error)]
pub enum FakeError {
    #[error("the model rig found no configuration for the commanded pose")]
    NoConfiguration,
    #[error("command refused")]
    Refused,
    #[error("sensor dropout")]
    Dropout,
}

/// The fake rig.
#[derive(Debug, Clone)]
pub struct ModelRig {
    pub rod: Rod,
    pub a: Vector6<f64>,
    pub tip: Pose,
    pub moves: usize,
    /// After this many moves, every command is refused.
    pub refuse_after: Option<usize>,
    /// After this many moves, every read drops out.
    pub dropout_after: Option<usize>,
    /// After this many moves, the sensor reads zeros (a configuration outside A).
    pub zeros_after: Option<usize>,
    /// After this many moves, a contact adds this wrench (torque first) to the reading,
    /// growing with each further move.
    pub contact: Option<(usize, Vector6<f64>)>,
    /// After exactly this many moves, and only then, this wrench (torque first) is added to
    /// the reading: one move's throw that the next move undoes.
    pub spike: Option<(usize, Vector6<f64>)>,
    /// White noise on each reading: the standard deviation of each channel of `a` (torque
    /// first, SI units) and the seeded generator drawing it.
    pub noise: Option<(Vector6<f64>, ChaCha8Rng)>,
    /// A sensor bias on every reading (torque first, SI units): `bias.0 + bias.1 · moves`, a
    /// bias that drifts steadily with each move.
    pub bias: (Vector6<f64>, Vector6<f64>),
}

impl ModelRig {
    pub fn new(a: Vector6<f64>) -> Self {
        let rod = Rod::new(wire());
        let tip = rod.tip(&a).expect("solves");
        Self {
            rod,
            a,
            tip,
            moves: 0,
            refuse_after: None,
            dropout_after: None,
            zeros_after: None,
            contact: None,
            spike: None,
            noise: None,
            bias: (Vector6::zeros(), Vector6::zeros()),
        }
    }

    /// The same rig with a sensor bias `initial + per_move · moves` on every reading.
    pub fn with_bias(mut self, initial: Vector6<f64>, per_move: Vector6<f64>) -> Self {
        self.bias = (initial, per_move);
        self
    }

    /// The same rig with white noise of standard deviation `std` (torque first) on every
    /// reading, drawn from `seed`.
    pub fn with_noise(mut self, std: Vector6<f64>, seed: u64) -> Self {
        self.noise = Some((std, ChaCha8Rng::seed_from_u64(seed)));
        self
    }

    /// Newton on `log(Γ(a)⁻¹ b) = 0` from the current `a`.
    fn configuration_for(&self, tip: &Pose) -> Option<Vector6<f64>> {
        let mut a = self.a;
        for _ in 0..50 {
            let j = self.rod.jacobian(&a).ok()?;
            let r = se3::log(&(j.tip.inverse() * tip));
            if r.norm() < 1e-13 {
                return Some(a);
            }
            let da = j.jacobian.lu().solve(&r)?;
            a += da;
        }
        None
    }

    fn after(&self, n: Option<usize>) -> bool {
        n.is_some_and(|n| self.moves >= n)
    }
}

impl Rig for ModelRig {
    type Error = FakeError;

    fn read_ft(&mut self) -> Result<FtSample, FakeError> {
        if self.after(self.dropout_after) {
            return Err(FakeError::Dropout);
        }
        let mut a = self.a;
        if let Some((n, wrench)) = self.contact
            && self.moves >= n
        {
            a += wrench * (1 + self.moves - n) as f64;
        }
        if let Some((n, wrench)) = self.spike
            && self.moves == n
        {
            a += wrench;
        }
        if self.after(self.zeros_after) {
            a = Vector6::zeros();
        }
        a += self.bias.0 + self.bias.1 * self.moves as f64;
        if let Some((std, rng)) = &mut self.noise {
            for i in 0..6 {
                let z: f64 = StandardNormal.sample(rng);
                a[i] += std[i] * z;
            }
        }
        let raw = Vector6::new(a[3], a[4], a[5], a[0], a[1], a[2]);
        Ok(FtSample {
            time: self.moves as f64,
            raw,
            saturated: [false; 6],
        })
    }

    fn gripper_poses(&self) -> Result<GripperPoses, FakeError> {
        Ok(GripperPoses {
            base: Pose::identity(),
            tip: self.tip,
        })
    }

    fn command(&mut self, command: &Command) -> Result<(), FakeError> {
        if self.after(self.refuse_after) {
            return Err(FakeError::Refused);
        }
        let b = command.base.inverse() * command.tip;
        let a = self
            .configuration_for(&b)
            .ok_or(FakeError::NoConfiguration)?;
        self.a = a;
        self.tip = b;
        self.moves += 1;
        Ok(())
    }

    fn time(&self) -> f64 {
        self.moves as f64
    }
}
