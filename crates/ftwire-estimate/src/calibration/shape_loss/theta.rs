//! The map in the fit's own units: `Θ = (A | c | W)` on `ψ(z) = (z, 1, φ(z))`, the affine
//! part and the polynomial features `φ` of the standardised reading ([`Map`]), the
//! standardisations it works in ([`Frame`]), and the [`Calibration`] it becomes.

use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

use crate::EstimateError;
use crate::calibration::polynomial::{MAX_FEATURES, feature_count, features};
use crate::calibration::record::TrainingRecord;
use crate::calibration::{Activation, Affine, Calibration, Mlp, Normaliser, Polynomial};

/// The standardisations and the shapes' resolution.
pub(super) struct Frame {
    pub(super) input: Normaliser,
    pub(super) output: Normaliser,
    pub(super) nodes: usize,
}

/// `Θ = (A | c | W)`, six rows of `7 + K` weights in normalised units.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Map {
    pub(super) degree: usize,
    pub(super) theta: DMatrix<f64>,
}

impl Map {
    pub(super) fn affine(affine: &Affine) -> Self {
        let mut theta = DMatrix::zeros(6, 7);
        for i in 0..6 {
            for j in 0..6 {
                theta[(i, j)] = affine.matrix[(i, j)];
            }
            theta[(i, 6)] = affine.offset[i];
        }
        Self { degree: 1, theta }
    }

    fn width(degree: usize) -> usize {
        7 + feature_count(degree)
    }

    /// The same map with a zero polynomial part of `degree`.
    pub(super) fn extended(&self, degree: usize) -> Self {
        let mut theta = DMatrix::zeros(6, Self::width(degree));
        theta.columns_mut(0, 7).copy_from(&self.theta.columns(0, 7));
        Self { degree, theta }
    }

    pub(super) fn psi(&self, z: &Vector6<f64>) -> DVector<f64> {
        let mut phi = [0.0; MAX_FEATURES];
        let count = features(self.degree, z, &mut phi);
        let mut psi = DVector::zeros(7 + count);
        psi.rows_mut(0, 6).copy_from(z);
        psi[6] = 1.0;
        psi.rows_mut(7, count).copy_from_slice(&phi[..count]);
        psi
    }

    pub(super) fn calibration(
        &self,
        frame: &Frame,
        record: TrainingRecord,
    ) -> Result<Calibration, EstimateError> {
        let affine = Affine {
            matrix: Matrix6::from_fn(|i, j| self.theta[(i, j)]),
            offset: Vector6::from_fn(|i, _| self.theta[(i, 6)]),
        };
        let polynomial = if self.degree >= 2 {
            let rows = (0..6)
                .map(|i| self.theta.row(i).iter().skip(7).copied().collect())
                .collect();
            Some(Polynomial::new(self.degree, rows)?)
        } else {
            None
        };
        let mlp = Mlp::from_parameters(&[], Activation::Tanh, vec![0.0; 42])?;
        Ok(
            Calibration::from_parts(frame.input, frame.output, Some(affine), mlp, record)
                .with_polynomial(polynomial),
        )
    }
}
