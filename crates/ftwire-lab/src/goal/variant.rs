//! The goal experiment's two variants, `no_noise` and `noise`, and one variant's trials on a
//! pair.

use ftwire_control::NoiseModel;

use super::closed::{ClosedSetup, ClosedTrial};
use super::trial::OpenTrial;
use super::tuning::{
    EPSILON_NO_NOISE, EPSILON_NOISE, EPSILONS_NO_NOISE, EPSILONS_NOISE, MAX_ITERATIONS_NO_NOISE,
    MAX_ITERATIONS_NOISE, SETTLE_RADIUS,
};

/// One of a run's two variants, `no_noise` and `noise`: its noise model, its ε table, the
/// stop its headline is read at, and how its closed loop runs.
pub(super) struct Variant {
    /// `no_noise` or `noise`.
    pub(super) name: &'static str,
    pub(super) noise: NoiseModel,
    /// The ε of its trade-off table, largest first.
    pub(super) epsilons: [f64; 3],
    /// The headline ε.
    pub(super) headline_epsilon: f64,
    /// The stop of each closed-loop trial its headline is read at (an index of
    /// `ClosedTrial::stops`: one of the table's, or the run's own end).
    pub(super) headline: usize,
    pub(super) max_iterations: usize,
    /// The shape stop \[m\] (0: off).
    pub(super) shape_stop: f64,
}

impl Variant {
    /// The two variants of a run with `noise` in its `noise` runs and their shape stop
    /// `shape_stop` \[m\].
    pub(super) fn both(noise: NoiseModel, shape_stop: f64) -> [Self; 2] {
        let position = |table: &[f64], eps: f64| table.iter().position(|&e| e == eps).unwrap_or(0);
        let (epsilons, headline_epsilon, max_iterations) = match noise {
            NoiseModel::Increment | NoiseModel::Absolute => {
                (EPSILONS_NOISE, EPSILON_NOISE, MAX_ITERATIONS_NOISE)
            }
            NoiseModel::Offset | NoiseModel::None => {
                (EPSILONS_NO_NOISE, EPSILON_NO_NOISE, MAX_ITERATIONS_NO_NOISE)
            }
        };
        // With the shape stop the noise runs' headline is where each run stopped (the stop
        // after the ε table's, see `Context::closed`); the ε table is read off the same runs.
        let headline = if shape_stop > 0.0 {
            epsilons.len()
        } else {
            position(&epsilons, headline_epsilon)
        };
        [
            Self {
                name: "no_noise",
                noise: NoiseModel::None,
                epsilons: EPSILONS_NO_NOISE,
                headline_epsilon: EPSILON_NO_NOISE,
                headline: position(&EPSILONS_NO_NOISE, EPSILON_NO_NOISE),
                max_iterations: MAX_ITERATIONS_NO_NOISE,
                shape_stop,
            },
            Self {
                name: "noise",
                noise,
                epsilons,
                headline_epsilon,
                headline,
                max_iterations,
                shape_stop,
            },
        ]
    }

    /// How its closed loop runs on the pairs (no detector).
    pub(super) fn setup(&self) -> ClosedSetup<'_> {
        ClosedSetup {
            noise: self.noise,
            epsilons: &self.epsilons,
            max_iterations: self.max_iterations,
            detector: None,
            // Where the sensor's noise limits the stop (no noise, `offset`), the last rests
            // average longer; under `increment` / `absolute` the gripper's noise does.
            settle_radius: match self.noise {
                NoiseModel::None | NoiseModel::Offset => SETTLE_RADIUS,
                NoiseModel::Increment | NoiseModel::Absolute => 0.0,
            },
            shape_stop: if self.noise == NoiseModel::None {
                0.0
            } else {
                self.shape_stop
            },
        }
    }
}

/// One variant's trials on one pair, kept for the figures of the first pair.
pub(super) struct VariantTrials {
    pub(super) variant: &'static str,
    pub(super) closed: ClosedTrial,
    pub(super) open: OpenTrial,
    /// The open loop's steps (the closed loop's at the headline stop, at least 1).
    pub(super) steps: usize,
}
