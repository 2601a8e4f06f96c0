//! Per-feature standardisation of the network's inputs and outputs.

use nalgebra::Vector6;

/// Per-channel mean and standard deviation, fitted on the training split only and saved with
/// the weights: `z = (x − mean) / std` and back.
///
/// Every `std` is positive and finite: a channel that does not vary in the training data gets
/// `std = 1`, so that it is only centred.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Normaliser {
    mean: Vector6<f64>,
    std: Vector6<f64>,
}

impl Normaliser {
    /// Mean and (population) standard deviation of `samples` per channel. No samples gives the
    /// identity (`mean = 0`, `std = 1`).
    pub fn fit<'a>(samples: impl Iterator<Item = &'a Vector6<f64>> + Clone) -> Self {
        let mut count = 0_usize;
        let sum = samples.clone().fold(Vector6::zeros(), |acc, x| {
            count += 1;
            acc + x
        });
        if count == 0 {
            return Self::identity();
        }
        #[allow(clippy::cast_precision_loss)] // sample counts are far below 2⁵²
        let n = count as f64;
        let mean = sum / n;
        let variance = samples.fold(Vector6::zeros(), |acc, x| {
            let d = x - mean;
            acc + d.component_mul(&d)
        }) / n;
        let std = variance.map(|v| {
            let s = v.sqrt();
            if s.is_normal() { s } else { 1.0 }
        });
        Self { mean, std }
    }

    /// `mean = 0`, `std = 1`.
    pub fn identity() -> Self {
        Self {
            mean: Vector6::zeros(),
            std: Vector6::repeat(1.0),
        }
    }

    /// A normaliser from a saved mean and standard deviation; `None` unless every mean is finite
    /// and every std positive and finite.
    pub fn from_parts(mean: Vector6<f64>, std: Vector6<f64>) -> Option<Self> {
        let valid =
            mean.iter().all(|m| m.is_finite()) && std.iter().all(|s| s.is_finite() && *s > 0.0);
        valid.then_some(Self { mean, std })
    }

    /// The per-channel mean.
    pub fn mean(&self) -> &Vector6<f64> {
        &self.mean
    }

    /// The per-channel standard deviation (positive and finite).
    pub fn std(&self) -> &Vector6<f64> {
        &self.std
    }

    /// `(x − mean) / std`.
    pub fn normalise(&self, x: &Vector6<f64>) -> Vector6<f64> {
        (x - self.mean).component_div(&self.std)
    }

    /// `mean + std · z`, the inverse of [`Normaliser::normalise`].
    pub fn denormalise(&self, z: &Vector6<f64>) -> Vector6<f64> {
        self.mean + self.std.component_mul(z)
    }
}

#[cfg(test)]
mod tests {
    use super::Normaliser;
    use approx::assert_relative_eq;
    use nalgebra::Vector6;

    /// Fitted data have zero mean and unit spread; a constant channel is only centred; the
    /// inverse undoes the map.
    #[test]
    fn standardises_and_inverts() {
        let samples: Vec<Vector6<f64>> = (0..5)
            .map(|i| {
                let t = f64::from(i);
                Vector6::new(t, 10.0 * t - 3.0, 2.0, -t * t, 0.1 * t, 1e-3 * t)
            })
            .collect();
        let normaliser = Normaliser::fit(samples.iter());
        assert_relative_eq!(normaliser.std()[2], 1.0);
        let z: Vec<Vector6<f64>> = samples.iter().map(|x| normaliser.normalise(x)).collect();
        let refit = Normaliser::fit(z.iter());
        for i in [0, 1, 3, 4, 5] {
            assert_relative_eq!(refit.mean()[i], 0.0, epsilon = 1e-12);
            assert_relative_eq!(refit.std()[i], 1.0, epsilon = 1e-12);
        }
        for (x, zi) in samples.iter().zip(&z) {
            assert_relative_eq!(normaliser.denormalise(zi), x, epsilon = 1e-12);
        }
    }
}
