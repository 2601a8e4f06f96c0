//! The estimated shape's error bars against the simulator's true centreline: `σ(s)` at the
//! truth's own arc lengths, and the share of its points within `2σ`.
//!
//! The simulator's wire (`ftwire_sim`'s `wire_centreline`, N edges) holds the base clamp point
//! (arc length 0), the interior nodes at `(k − ½)h` and the tip clamp point (`L = (N − 1)h`).
//! The estimate and its `σ(s)` ([`ftwire_estimate::shape::shape_sigma`]) are solved at every
//! multiple of `h/2` (`2N − 1` nodes), and the nodes at the truth's arc lengths are compared
//! ([`matched_nodes`]): evenly spaced nodes at `L/N` would be up to `h/2` of arc length off
//! at the ends, a gap of millimetres that is no error of the estimate. The base clamp point,
//! where `σ = 0` and the error is zero, is not counted. Guarded by
//! `tests/shape_sigma_coverage.rs`, which asserts the coverage over 50 configurations.

use ftwire_estimate::shape::{ModelError, shape_sigma, with_model_error};
use ftwire_estimate::{EstimateError, KirchhoffModel, WireModel};
use nalgebra::{Matrix6, Vector3, Vector6};

/// The nodes count `2N − 1` of the estimate and, for each of the `points = N + 1` points of
/// the simulator's wire, the index of the estimate's node at its arc length (module docs).
/// `None` for fewer than 3 points (no interior node).
pub fn matched_nodes(points: usize) -> Option<(usize, Vec<usize>)> {
    let edges = points.checked_sub(1).filter(|&n| n >= 2)?;
    let nodes = 2 * edges - 1;
    let index = (0..points)
        .map(|k| match k {
            0 => 0,
            k if k == edges => nodes - 1,
            k => 2 * k - 1,
        })
        .collect();
    Some((nodes, index))
}

/// An estimate's error bars against the truth, at the truth's points.
#[derive(Debug, Clone, PartialEq)]
pub struct SigmaCheck {
    /// The estimate at the truth's arc lengths \[m\].
    pub estimate: Vec<Vector3<f64>>,
    /// `σ(s)` at the truth's arc lengths \[m\].
    pub sigma: Vec<f64>,
    /// `‖p̂(s) − p(s)‖` at the truth's arc lengths \[m\].
    pub error: Vec<f64>,
}

impl SigmaCheck {
    /// The mean `σ` over the points but the base clamp \[m\].
    pub fn sigma_mean(&self) -> f64 {
        mean(self.sigma.iter().skip(1).copied())
    }

    /// The share of the points but the base clamp whose error is at most `2σ`.
    pub fn coverage_2sigma(&self) -> f64 {
        mean(
            self.error
                .iter()
                .zip(&self.sigma)
                .skip(1)
                .map(|(e, s)| f64::from(u8::from(*e <= 2.0 * s))),
        )
    }
}

fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0_usize), |(s, n), v| (s + v, n + 1));
    #[allow(clippy::cast_precision_loss)] // a few hundred points
    let n = n.max(1) as f64;
    sum / n
}

/// The shape of `model` at `a_tilde` and its `σ(s)` (from the `covariance` of `ã`, and the
/// model error when given) at the arc lengths of the simulator's wire `truth`
/// (module docs); `None` when `truth` has fewer than 3 points.
///
/// # Errors
/// As [`shape_sigma`] and [`WireModel::shape`].
pub fn check_sigma(
    model: &KirchhoffModel,
    a_tilde: &Vector6<f64>,
    covariance: &Matrix6<f64>,
    model_error: Option<&ModelError>,
    truth: &[Vector3<f64>],
) -> Result<Option<SigmaCheck>, EstimateError> {
    let Some((nodes, index)) = matched_nodes(truth.len()) else {
        return Ok(None);
    };
    let shape = model.shape(a_tilde, nodes)?;
    let mut sigma = shape_sigma(model, a_tilde, nodes, covariance)?.sigma;
    if let Some(e) = model_error {
        sigma = with_model_error(&sigma, e, model.wire().length());
    }
    let estimate: Vec<Vector3<f64>> = index.iter().map(|&i| shape.positions[i]).collect();
    let sigma: Vec<f64> = index.iter().map(|&i| sigma[i]).collect();
    let error = estimate
        .iter()
        .zip(truth)
        .map(|(p, t)| (p - t).norm())
        .collect();
    Ok(Some(SigmaCheck {
        estimate,
        sigma,
        error,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_truths_points_map_to_the_nodes_at_their_arc_lengths() {
        // N = 4 edges: the clamp, nodes at h/2, 3h/2, 5h/2, the tip at 3h; 7 nodes at h/2.
        let (nodes, index) = matched_nodes(5).expect("enough points");
        assert_eq!(nodes, 7);
        assert_eq!(index, vec![0, 1, 3, 5, 6]);
        assert!(matched_nodes(2).is_none());
    }
}
