//! Stretching energy of one edge (Bergou et al. 2008, §4.4, as a stiff penalty):
//! `E = ½·EA·(|e|/h − 1)²·h`.

use nalgebra::{Matrix3, Vector3};

/// Energy \[J\], gradient with respect to the edge vector \[N\], Hessian \[N/m\].
pub(crate) fn energy_derivatives(
    e: &Vector3<f64>,
    rest: f64,
    axial: f64,
) -> (f64, Vector3<f64>, Matrix3<f64>) {
    let len = e.norm();
    let strain = len / rest - 1.0;
    let t = e / len;
    let energy = 0.5 * axial * strain * strain * rest;
    let grad = t * (axial * strain);
    let tt = t * t.transpose();
    let hess = tt * (axial / rest) + (Matrix3::identity() - tt) * (axial * strain / len);
    (energy, grad, hess)
}

/// Energy only \[J\].
pub(crate) fn energy(e: &Vector3<f64>, rest: f64, axial: f64) -> f64 {
    let strain = e.norm() / rest - 1.0;
    0.5 * axial * strain * strain * rest
}
