//! The closed loop's settings in the goal experiment: the gain, the ε tables, the settling
//! and the iteration limits, with and without noise.

/// The gain K (the paper's).
pub const GAIN: f64 = 0.2;
/// ε values of the no-noise (and `offset`) trade-off table, largest first \[normalised\].
pub const EPSILONS_NO_NOISE: [f64; 3] = [0.1, 0.05, 0.02];
/// The headline ε without noise and with `offset`: the smallest of the table, which the
/// settled rests ([`SETTLE_RADIUS`]) let every run reach; the sensor's bias drift over the
/// run, not ε, is then most of what is left (see [`crate::goal`]).
pub const EPSILON_NO_NOISE: f64 = 0.02;
/// The controller's settling radius \[normalised\] without noise and with `offset`: within it
/// each rest averages [`SETTLE_SAMPLES`] samples (`ControlParams::settle_radius`). It is
/// larger than every ε of [`EPSILONS_NO_NOISE`], so each of their stops reads a settled `ã`.
pub const SETTLE_RADIUS: f64 = 0.25;
/// F/T samples per rest within [`SETTLE_RADIUS`] (0.4 s at 1 kHz, as tracking's last leg).
pub const SETTLE_SAMPLES: usize = 400;
/// ε values of the `increment` / `absolute` trade-off table, largest first \[normalised\].
pub const EPSILONS_NOISE: [f64; 3] = [1.0, 0.5, 0.25];
/// The headline ε with `increment` / `absolute` noise.
pub const EPSILON_NOISE: f64 = 0.5;
/// Iteration limit without noise (and with `offset`).
pub const MAX_ITERATIONS_NO_NOISE: usize = 150;
/// Iteration limit with `increment` / `absolute` noise: the stop rule waits for a step that
/// lands within ε.
pub const MAX_ITERATIONS_NOISE: usize = 400;
