//! The polynomial part of a calibration map: `y += W φ(z)`, with `φ(z)` the monomials of
//! degree 2 to `d` of the normalised reading `z` (`d` ≤ [`MAX_POLYNOMIAL_DEGREE`]).
//!
//! A strain-gauge sensor's bridge and its amplifier are nearly linear; what an affine map
//! leaves (a quadratic bridge term, a cubic one at the ends of the range, the cross-terms of
//! a load on one axis with another) is a low-order polynomial of the reading. Unlike a
//! network, a polynomial is linear in its weights, so a map fitted on the shape
//! (`super::shape_loss`) is a linear least-squares problem in them, solved by Gauss–Newton
//! through the model's Jacobian. The monomials are ordered by degree, then lexicographically
//! in the channel indices (`z0², z0 z1, …, z5², z0³, z0² z1, …`).

use nalgebra::Vector6;

use crate::EstimateError;

/// The highest degree a polynomial part may have.
pub const MAX_POLYNOMIAL_DEGREE: usize = 3;

/// The most monomials of a polynomial part: 21 of degree 2 and 56 of degree 3.
pub const MAX_FEATURES: usize = 77;

/// Monomials of degree 2 to `degree` of six variables (0 for a degree below 2).
pub fn feature_count(degree: usize) -> usize {
    let quadratic = if degree >= 2 { 21 } else { 0 };
    let cubic = if degree >= 3 { 56 } else { 0 };
    quadratic + cubic
}

/// Writes `φ(z)` into `out` (its first [`feature_count`]`(degree)` entries) and returns their
/// count.
pub fn features(degree: usize, z: &Vector6<f64>, out: &mut [f64; MAX_FEATURES]) -> usize {
    let mut k = 0;
    if degree >= 2 {
        for i in 0..6 {
            for j in i..6 {
                out[k] = z[i] * z[j];
                k += 1;
            }
        }
    }
    if degree >= 3 {
        for i in 0..6 {
            for j in i..6 {
                for l in j..6 {
                    out[k] = z[i] * z[j] * z[l];
                    k += 1;
                }
            }
        }
    }
    k
}

/// `W φ(z)` in normalised units: the polynomial part of a calibration map.
#[derive(Debug, Clone, PartialEq)]
pub struct Polynomial {
    degree: usize,
    /// Six rows of [`feature_count`]`(degree)` weights.
    weights: Vec<Vec<f64>>,
}

impl Polynomial {
    /// A polynomial part of `degree` (2 or 3) with six rows of weights, one per output.
    ///
    /// # Errors
    /// [`EstimateError::InvalidSetting`] for a degree outside `2..=3`;
    /// [`EstimateError::CalibrationShape`] for rows of the wrong count or length;
    /// [`EstimateError::CalibrationValue`] for a weight not finite.
    pub fn new(degree: usize, weights: Vec<Vec<f64>>) -> Result<Self, EstimateError> {
        if !(2..=MAX_POLYNOMIAL_DEGREE).contains(&degree) {
            #[allow(clippy::cast_precision_loss)] // a small number
            return Err(EstimateError::InvalidSetting {
                field: "polynomial.degree",
                value: degree as f64,
                allowed: "2 or 3",
            });
        }
        if weights.len() != 6 {
            return Err(EstimateError::CalibrationShape {
                what: "polynomial.weights".into(),
                expected: 6,
                found: weights.len(),
            });
        }
        let count = feature_count(degree);
        for (i, row) in weights.iter().enumerate() {
            if row.len() != count {
                return Err(EstimateError::CalibrationShape {
                    what: format!("polynomial.weights[{i}]"),
                    expected: count,
                    found: row.len(),
                });
            }
            if let Some(j) = row.iter().position(|w| !w.is_finite()) {
                return Err(EstimateError::CalibrationValue {
                    what: format!("polynomial.weights[{i}]"),
                    index: j,
                    value: row[j],
                    allowed: "finite numbers",
                });
            }
        }
        Ok(Self { degree, weights })
    }

    /// The degree.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The weights: six rows (outputs, torque first) of one weight per monomial.
    pub fn weights(&self) -> &[Vec<f64>] {
        &self.weights
    }

    /// `W φ(z)`. Allocation-free.
    pub fn apply(&self, z: &Vector6<f64>) -> Vector6<f64> {
        let mut phi = [0.0; MAX_FEATURES];
        let count = features(self.degree, z, &mut phi);
        Vector6::from_fn(|i, _| {
            self.weights[i]
                .iter()
                .zip(&phi[..count])
                .map(|(w, f)| w * f)
                .sum()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_features_are_every_monomial_once() {
        let z = Vector6::new(2.0, 3.0, 5.0, 7.0, 11.0, 13.0);
        let mut phi = [0.0; MAX_FEATURES];
        assert_eq!(features(3, &z, &mut phi), MAX_FEATURES);
        assert_eq!(feature_count(3), MAX_FEATURES);
        assert_eq!(features(1, &z, &mut phi), 0);
        // Products of distinct primes: every monomial's value is distinct.
        let mut values: Vec<u64> = phi.iter().map(|&v| v as u64).collect();
        values.sort_unstable();
        values.dedup();
        assert_eq!(values.len(), MAX_FEATURES);
        assert_eq!(phi[0], 4.0);
        assert_eq!(phi[1], 6.0);
        assert_eq!(phi[21], 8.0);
    }

    #[test]
    fn a_polynomial_applies_its_weights_and_refuses_bad_ones() -> Result<(), EstimateError> {
        let mut weights = vec![vec![0.0; 21]; 6];
        weights[2][0] = 0.5; // 0.5 z0² into output 2
        let p = Polynomial::new(2, weights)?;
        let y = p.apply(&Vector6::new(2.0, 0.0, 0.0, 0.0, 0.0, 1.0));
        assert_eq!(y, Vector6::new(0.0, 0.0, 2.0, 0.0, 0.0, 0.0));
        assert!(Polynomial::new(4, vec![vec![0.0; 21]; 6]).is_err());
        assert!(Polynomial::new(2, vec![vec![0.0; 20]; 6]).is_err());
        let mut bad = vec![vec![0.0; 21]; 6];
        bad[1][3] = f64::NAN;
        let e = Polynomial::new(2, bad)
            .map(|_| ())
            .expect_err("refused")
            .to_string();
        assert!(e.contains("polynomial.weights[1]"), "{e}");
        Ok(())
    }
}
