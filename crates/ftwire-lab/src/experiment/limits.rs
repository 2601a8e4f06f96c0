//! The ranges of the experiments' counts, which every front end checks a count against
//! before any work: each bounds the time and memory one run may take.

use ftwire_app::input::CountRange;

use super::rig::SAMPLES_PER_REST;

/// `--trials` and `--configs`: each trial is bounded by its own settings, and what the
/// experiments keep of one (a row of results, a trial's samples) is small, so the count
/// bounds the time and memory linearly; the cap sits far above the paper's counts.
pub const TRIALS: CountRange = CountRange::new(1, 10_000);

/// `--rest-samples`: at least [`SAMPLES_PER_REST`], so that the rest average has the half of
/// them that must survive screening; at most 100 s of readings at the simulated sensor's
/// 1 kHz, whose buffer of one rest stays a few megabytes.
pub const REST_SAMPLES: CountRange = CountRange::new(SAMPLES_PER_REST, 100_000);

/// `goal --pairs`, `track --pairs`, `passage --attempts`: every roll-out keeps its record for
/// the summary and the figures (the true centreline at each rest), so the count bounds the
/// memory linearly; the cap keeps it well under a gigabyte at the default move limits.
pub const ROLLOUTS: CountRange = CountRange::new(1, 1000);

/// `passage --plan-candidates`: each candidate is a whole plan, made in turn.
pub const PLAN_CANDIDATES: CountRange = CountRange::new(1, 100);

/// `--waypoint-moves`: a leg's moves are its rests, each recorded, so the cap bounds a
/// roll-out's record at 1000 rests per waypoint.
pub const WAYPOINT_MOVES: CountRange = CountRange::new(1, 1000);
