//! Batch identification: the streaming [`Identifier`] run to completion on a set of samples.

use ftwire_core::Pose;
use nalgebra::Vector6;
use rand::Rng;

use super::Identifier;
use crate::identify::{Estimate, IdentifierParams, Sample};
use crate::{EstimateError, WireModel};

/// Identifies `η = (c, L)` from a batch of samples: the streaming [`Identifier`] run to
/// completion.
///
/// `samples` are `(ã_i, b̃_i)` pairs (see [`Sample`]) in the order recorded.
///
/// # Identifiability
/// The data must determine `η`; an estimate is never returned as identified when they do not:
/// - **errors** (nothing to estimate from): fewer samples than the smallest `m ≥ 2` whose
///   equations exceed the unknowns (6 per sample for the absolute form, 6 per pair for the
///   differential forms; two because identification needs motion, paper §III-B, and at least
///   one degree of freedom must remain to estimate the residual variance); a second gripper
///   that moved less than [`IdentifierParams::min_motion`] noise standard deviations (all `b̃`
///   equal, or one sample);
/// - **flags** ([`Estimate::unidentified`]): a residual Jacobian whose relative smallest
///   singular value is below [`IdentifierParams::min_condition`] (the LM normal matrix `JᵀJ` has
///   the squares of these singular values); a parameter on the edge of the search box; a
///   final `χ²/dof` above [`IdentifierParams::max_chi2_per_dof`] under the configured
///   [`MeasurementNoise`](crate::identify::MeasurementNoise) (the fit explains the data far worse than the noise would).
///
/// The standard deviations ([`Estimate::c_std`], [`Estimate::length_std`]) are the first-order
/// `s² (JᵀJ)⁻¹` with `s²` the weighted residual variance per degree of freedom.
///
/// # Errors
/// A bad setting or sample (naming it), too few samples, a degenerate motion. An estimate the
/// data do not identify is returned flagged ([`Estimate::unidentified`]); call
/// [`Estimate::identified`] to turn the flag into an error.
///
/// # Example
/// ```
/// use ftwire_core::WireParams;
/// use ftwire_estimate::{KirchhoffModel, WireModel, identify::{IdentifierParams, identify}};
/// use nalgebra::Vector6;
/// use rand::SeedableRng;
/// let truth = KirchhoffModel::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
/// let samples = [0.0, 0.3, -0.3].map(|d| {
///     let a = Vector6::new(0.01 + 0.01 * d, 0.02, -0.03, -0.1, 0.2 - 0.1 * d, 0.05 + 0.05 * d);
///     (a, truth.tip(&a).expect("solvable"))
/// });
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
/// let estimate = identify(&truth, &samples, &IdentifierParams::default(), &mut rng)?;
/// assert!(estimate.is_identified());
/// assert!((estimate.length - 0.63).abs() < 1e-3);
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
pub fn identify<M: WireModel, R: Rng + ?Sized>(
    model: &M,
    samples: &[(Vector6<f64>, Pose)],
    config: &IdentifierParams,
    rng: &mut R,
) -> Result<Estimate, EstimateError> {
    let mut identifier = Identifier::new(model.clone(), config.clone(), rng)?;
    for (a, b) in samples {
        identifier.push(*a, *b)?;
    }
    identifier.run_to_completion()
}

/// [`identify`] from [`Sample`]s, which may carry their time since the tare: with a bias model
/// ([`crate::identify::MeasurementNoise::bias`]) the final fit then estimates the sensor's drift
/// with the wire.
///
/// # Errors
/// As [`identify`] and [`Identifier::push_sample`].
pub fn identify_samples<M: WireModel, R: Rng + ?Sized>(
    model: &M,
    samples: &[Sample],
    config: &IdentifierParams,
    rng: &mut R,
) -> Result<Estimate, EstimateError> {
    let mut identifier = Identifier::new(model.clone(), config.clone(), rng)?;
    for sample in samples {
        identifier.push_sample(*sample)?;
    }
    identifier.run_to_completion()
}
