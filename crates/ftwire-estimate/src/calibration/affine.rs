//! The least-squares affine map `y ≈ A z + c` that the network's residual is taken over.

use nalgebra::{Matrix6, SMatrix, Vector6};

/// An affine map `z ↦ A z + c` between normalised readings and normalised configurations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Affine {
    /// The linear part `A`.
    pub matrix: Matrix6<f64>,
    /// The offset `c`.
    pub offset: Vector6<f64>,
}

impl Affine {
    /// The least-squares fit over `(z, y)` pairs: minimises `Σ |A z + c − y|²` by the normal
    /// equations in `(z, 1)`, solved by SVD so that a constant or collinear channel does not
    /// break it (its direction gets the minimum-norm solution). With normalised `z` the normal
    /// matrix is `n` times a correlation matrix, so it is well conditioned unless the channels
    /// are nearly collinear.
    pub fn fit<'a>(pairs: impl Iterator<Item = (&'a Vector6<f64>, &'a Vector6<f64>)>) -> Self {
        let mut normal = SMatrix::<f64, 7, 7>::zeros();
        let mut right = SMatrix::<f64, 7, 6>::zeros();
        for (z, y) in pairs {
            let extended = z.push(1.0);
            normal += extended * extended.transpose();
            right += extended * y.transpose();
        }
        let svd = normal.svd(true, true);
        let tolerance = 1e-12 * svd.singular_values.max();
        let Ok(solution) = svd.solve(&right, tolerance) else {
            return Self::zero();
        };
        Self {
            matrix: solution.fixed_rows::<6>(0).transpose(),
            offset: solution.fixed_rows::<1>(6).transpose(),
        }
    }

    /// The least-squares linear fit through the origin over `(u, y)` pairs: minimises
    /// `Σ |B u − y|²` by the normal equations in `u`, solved by SVD as [`Affine::fit`]; the
    /// offset is zero.
    pub fn fit_linear<'a>(
        pairs: impl Iterator<Item = (&'a Vector6<f64>, &'a Vector6<f64>)>,
    ) -> Self {
        let mut normal = Matrix6::<f64>::zeros();
        let mut right = Matrix6::<f64>::zeros();
        for (u, y) in pairs {
            normal += u * u.transpose();
            right += u * y.transpose();
        }
        let svd = normal.svd(true, true);
        let tolerance = 1e-12 * svd.singular_values.max();
        let Ok(solution) = svd.solve(&right, tolerance) else {
            return Self::zero();
        };
        Self {
            matrix: solution.transpose(),
            offset: Vector6::zeros(),
        }
    }

    /// The map to zero.
    pub fn zero() -> Self {
        Self {
            matrix: Matrix6::zeros(),
            offset: Vector6::zeros(),
        }
    }

    /// `A z + c`.
    pub fn apply(&self, z: &Vector6<f64>) -> Vector6<f64> {
        self.matrix * z + self.offset
    }
}

#[cfg(test)]
mod tests {
    use super::Affine;
    use approx::assert_relative_eq;
    use nalgebra::{Matrix6, Vector6};

    /// An exact affine relation is recovered.
    #[test]
    fn recovers_an_exact_map() {
        let matrix = Matrix6::from_fn(|i, j| {
            if i == j {
                2.0
            } else {
                0.1 * (i + 2 * j) as f64
            }
        });
        let offset = Vector6::new(1.0, -2.0, 3.0, 0.5, 0.0, -0.25);
        let z: Vec<Vector6<f64>> = (0..40)
            .map(|k| {
                Vector6::from_fn(|i, _| ((k * 7 + i * 13) % 11) as f64 - 5.0 + 0.01 * k as f64)
            })
            .collect();
        let y: Vec<Vector6<f64>> = z.iter().map(|zi| matrix * zi + offset).collect();
        let fit = Affine::fit(z.iter().zip(&y));
        assert_relative_eq!(fit.matrix, matrix, epsilon = 1e-9);
        assert_relative_eq!(fit.offset, offset, epsilon = 1e-9);
    }
}
