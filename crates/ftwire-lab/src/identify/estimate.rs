//! One identification as the experiments and `ftwire identify --log` make it, so that both
//! give the same answer on the same data and seed: the model template, the swarm's random
//! generator, the loaded model's settings and the estimate's flag name.

use ftwire_core::WireParams;
use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::identify::{
    Estimate, Identifier, IdentifierParams, Sample, Unidentified, identify_samples,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::error::{LabError, from_estimate};
use crate::experiment::Gravity;

/// The model identification starts from. Only its radius and integrator are used (the search
/// replaces `c` and `L`); the radius is the simulator's default
/// (`ftwire_sim::RodParams::default()`), which the estimate does not depend on. The live
/// experiment and the log command use this one template, so the same data and seed give the
/// same estimate.
///
/// # Errors
/// Never for the constants here; kept fallible for the core type's checks.
pub fn template_model() -> Result<KirchhoffModel, LabError> {
    let radius = ftwire_sim::RodParams::default().radius;
    let wire = WireParams::new([0.1, 0.1, 0.1], 1.0, radius)
        .map_err(|e| LabError::bad_input(format!("the identification template: {e}")))?;
    Ok(KirchhoffModel::new(wire))
}

/// Identifies from `samples` (`(ã, b̃)` and, if known, the time since the tare) with the swarm seeded by `seed` (a fresh
/// generator per call, so an estimate depends only on its data and the seed, not on what ran
/// before).
///
/// # Errors
/// Bad input for data that cannot be identified from (too few samples, too little motion, a
/// sample outside `A`); no answer for anything else the library reports.
pub fn run_identification(
    samples: &[Sample],
    config: &IdentifierParams,
    seed: u64,
) -> Result<Estimate, LabError> {
    let model = template_model()?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    identify_samples(&model, samples, config, &mut rng)
        .map_err(|e| from_estimate(e, "identifying the wire"))
}

/// The streaming identifier of [`run_identification`] with `samples` pushed, for a caller that
/// shows progress: `step` it with a time budget until its estimate is no longer
/// `Unidentified::Unfinished`. It gives the same estimate as [`run_identification`] for the
/// same samples and seed, however the search is cut into steps.
///
/// # Errors
/// As [`run_identification`].
pub fn identifier(
    samples: &[Sample],
    config: &IdentifierParams,
    seed: u64,
) -> Result<Identifier<KirchhoffModel, ChaCha8Rng>, LabError> {
    let failed = |e| from_estimate(e, "identifying the wire");
    let rng = ChaCha8Rng::seed_from_u64(seed);
    let mut identifier = Identifier::new(template_model()?, config.clone(), rng).map_err(failed)?;
    for sample in samples {
        identifier.push_sample(*sample).map_err(failed)?;
    }
    Ok(identifier)
}

/// A short machine-readable name of why an estimate is not trusted (`None`: identified).
pub fn flag_name(reason: Option<&Unidentified>) -> Option<&'static str> {
    reason.map(|reason| match reason {
        Unidentified::IllConditioned { .. } => "ill_conditioned",
        Unidentified::ResidualAboveNoise { .. } => "residual_above_noise",
        Unidentified::AtBound { .. } => "at_bound",
        Unidentified::Unfinished { .. } => "unfinished",
        _ => "unidentified",
    })
}

/// The settings of the loaded model: `config` with the wire's linear density identified under
/// the experiment's gravity. The rig's base clamp sits at the world origin with the world's
/// axes ([`crate::experiment::rig::place_wire`]), so gravity in the base clamp frame is the
/// world's.
pub fn loaded_config(config: &IdentifierParams, gravity: Gravity) -> IdentifierParams {
    let mut loaded = config.clone();
    if gravity == Gravity::On {
        loaded.constraints.weight = Some(gravity.vector());
    }
    loaded
}
