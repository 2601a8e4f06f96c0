//! Error bars of the estimated shape: the standard deviation of each centreline point, to
//! first order in the noise of `ã`.
//!
//! With `D(s) = ∂p(s)/∂a` (3×6) at the estimate and `Σ_ã` the covariance of `ã` (sensor
//! noise, the calibration's error), the covariance of the point `p(s)` is
//!
//! ```text
//! Σ_p(s) = D(s) Σ_ã D(s)ᵀ,        σ(s) = sqrt(trace Σ_p(s))
//! ```
//!
//! `σ(s)` is the RMS radius of the point's error, `sqrt(E‖p̂(s) − p(s)‖²)`: one number per
//! point that adds the three directions, so a band of `σ` is never narrower than the error
//! along any direction (the largest eigenvalue's root would drop the other two directions
//! and under-state the error when they are comparable). For a Gaussian error, `‖δp‖ ≤ 2σ`
//! holds with probability 95.4 % when the error lies along one direction (a slender wire's
//! points move mostly sideways) up to 99.3 % when it is isotropic, and `‖δp‖ ≤ σ` with 68.3 %
//! down to 60.8 %.
//!
//! **The model's own error.** `σ_a(s)`, the above, carries the error of `ã` only: at the true
//! `a` it is zero, but the model's shape is not the real wire there (discretisation of a
//! simulator, unmodelled weight, a clamp that is not ideal, a wrong `c` or `L`). With the model
//! error given as an RMS radius per metre of arc length `e` ([`ModelError`]: zero at the base
//! clamp, which both share, and growing along the wire as an error of the integrated
//! curvature does), the bar is
//!
//! ```text
//! σ_model(s) = e · s,        σ(s)² = σ_a(s)² + σ_model(s)²
//! ```
//!
//! ([`with_model_error`]): the two errors are independent, the model's being the same at the
//! true `a` and at `ã` to first order. `e` is what a user measures with markers at rests where
//! `a` is known (a calibration's held-out split: each inner marker's distance to the model's
//! shape at its label, divided by its arc length, RMS over the markers), or the documented
//! agreement of the model with another model (the coverage test uses the Kirchhoff model's
//! bound against the simulator, 0.5 mm over the wire, of `crates/ftwire/tests/model_vs_sim.rs`).
//!
//! `D(s)` at every node comes from central differences of the shape ([`shape_jacobians`]):
//! 12 shape solves, each the cheapest solve of the model, instead of one truncated Jacobian
//! solve per node ([`super::centreline_point`]). The step in component `i` is
//! [`RELATIVE_STEP`] times `max(|a_i|, u_i)`, with `u_i` the normalised unit (`c2/L` for a
//! torque, `c2/L²` for a force), so that it is relative to the component and still nonzero
//! at a zero component. Guarded by `tests/shape_sigma.rs` (the differences against the
//! analytic `∂p(s)/∂a` of [`super::centreline_point`]) and, against the simulator, by
//! `crates/ftwire-lab/tests/shape_sigma_coverage.rs`.

use ftwire_rod::Shape;
use nalgebra::{Matrix3, Matrix3x6, Matrix6, Vector6};

use crate::{EstimateError, WireModel};

/// Largest model error per metre of arc length [`ModelError`] accepts \[m/m\]: an error as
/// large as the wire is no model.
pub const MAX_MODEL_ERROR: f64 = 1.0;

/// The central-difference step of [`shape_jacobians`], relative to `max(|a_i|, u_i)`: the
/// truncation error is of order its square, and it is large enough that a change of the
/// integrator's step count between the two solves moves the difference by a small fraction
/// only.
pub const RELATIVE_STEP: f64 = 1e-3;

/// The names of the six components of `ã`, torque first, in errors.
const CHANNELS: [&str; 6] = [
    "a_std torque 1",
    "a_std torque 2",
    "a_std torque 3",
    "a_std force 1",
    "a_std force 2",
    "a_std force 3",
];

/// Per-channel standard deviations of `ã` \[N·m, N·m, N·m, N, N, N\], torque first, base
/// clamp frame: a diagonal `Σ_ã`. Each is finite, `≥ 0` and at most the largest plausible
/// reading (1e3 N·m, 1e4 N).
///
/// # Example
/// ```
/// use ftwire_estimate::shape::ConfigurationStd;
/// let sensor = ConfigurationStd::new([1e-4, 1e-4, 1e-4, 0.01, 0.01, 0.01])?;
/// let calibration = ConfigurationStd::new([0.0, 0.0, 0.0, 0.02, 0.0, 0.0])?;
/// let both = sensor.combined(&calibration);
/// assert!((both.std()[3] - 0.05_f64.sqrt() * 0.1).abs() < 1e-12);
/// assert!(ConfigurationStd::new([0.0, 0.0, 0.0, -0.01, 0.0, 0.0]).is_err());
/// let wide = ConfigurationStd::new([1e308, 0.0, 0.0, 0.0, 0.0, 0.0]).expect_err("beyond any reading");
/// assert!(wide.to_string().contains("= 1e308 is invalid"), "{wide}");
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConfigurationStd {
    std: Vector6<f64>,
}

impl ConfigurationStd {
    /// The standard deviations `std` \[N·m ×3, N ×3\], torque first.
    ///
    /// # Errors
    /// [`EstimateError::BadShapeSetting`] naming the first component that is not finite, is
    /// negative, or exceeds the largest plausible reading ([`crate::log::MAX_TORQUE`],
    /// [`crate::log::MAX_FORCE`]): an error bar wider than any reading squares past `f64`.
    pub fn new(std: [f64; 6]) -> Result<Self, EstimateError> {
        for (k, (name, value)) in CHANNELS.iter().zip(std).enumerate() {
            let max = if k < 3 {
                crate::log::MAX_TORQUE
            } else {
                crate::log::MAX_FORCE
            };
            if !(value.is_finite() && (0.0..=max).contains(&value)) {
                return Err(EstimateError::BadShapeSetting {
                    name,
                    value,
                    allowed: "from 0 to 1e3 N·m for a torque, to 1e4 N for a force",
                });
            }
        }
        Ok(Self {
            std: Vector6::from(std),
        })
    }

    /// The standard deviations, torque first \[N·m ×3, N ×3\].
    pub fn std(&self) -> &Vector6<f64> {
        &self.std
    }

    /// `Σ_ã`: the diagonal covariance \[N²·m², N²\].
    pub fn covariance(&self) -> Matrix6<f64> {
        Matrix6::from_diagonal(&self.std.component_mul(&self.std))
    }

    /// Two independent sources together (e.g. the sensor's noise and the calibration's
    /// error): the root sum of squares per channel.
    #[must_use]
    pub fn combined(&self, other: &Self) -> Self {
        Self {
            std: self.std.zip_map(&other.std, |a, b| (a * a + b * b).sqrt()),
        }
    }
}

/// `D(s_i) = ∂p(s_i)/∂a` \[m per N·m, m per N\] at the `nodes` nodes of `model.shape(a,
/// nodes)`, by central differences of the shape (module docs): 12 shape solves.
///
/// # Errors
/// As [`WireModel::shape`], for `a` or a shifted `a` (a shift that lands outside `A`: the
/// four components `a2, a3, a5, a6` all zero).
pub fn shape_jacobians<M: WireModel>(
    model: &M,
    a: &Vector6<f64>,
    nodes: usize,
) -> Result<Vec<Matrix3x6<f64>>, EstimateError> {
    let wire = model.wire();
    let unit = [wire.torque_scale(), wire.force_scale()];
    let mut jacobians = vec![Matrix3x6::zeros(); nodes];
    for i in 0..6 {
        let step = RELATIVE_STEP * a[i].abs().max(unit[i / 3]);
        let shifted = |sign: f64| -> Result<Shape, EstimateError> {
            let mut b = *a;
            b[i] += sign * step;
            model.shape(&b, nodes)
        };
        let (plus, minus) = (shifted(1.0)?, shifted(-1.0)?);
        for ((d, p), m) in jacobians
            .iter_mut()
            .zip(&plus.positions)
            .zip(&minus.positions)
        {
            d.set_column(i, &((p - m) / (2.0 * step)));
        }
    }
    Ok(jacobians)
}

/// The first-order error of each node of an estimated shape.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeSigma {
    /// `Σ_p(s_i) = D Σ_ã Dᵀ` \[m²\] at each node, base clamp frame.
    pub covariance: Vec<Matrix3<f64>>,
    /// `σ(s_i) = sqrt(trace Σ_p(s_i))` \[m\] at each node: the RMS radius of its error.
    pub sigma: Vec<f64>,
}

/// The first-order error of the shape of `model` at `a`, at `nodes` nodes, for a covariance
/// of `a` `covariance` \[N·m, N\]² (torque first): [`shape_jacobians`], then
/// `Σ_p = D Σ_ã Dᵀ` and `σ = sqrt(trace Σ_p)` at each node.
///
/// # Errors
/// As [`shape_jacobians`].
///
/// # Example
/// ```
/// use ftwire_core::WireParams;
/// use ftwire_estimate::KirchhoffModel;
/// use ftwire_estimate::shape::{ConfigurationStd, shape_sigma};
/// use nalgebra::Vector6;
/// let model = KirchhoffModel::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
/// let a = Vector6::new(0.0, 0.02, 0.01, -0.05, 0.03, 0.0);
/// let noise = ConfigurationStd::new([1e-4, 1e-4, 1e-4, 1e-3, 1e-3, 1e-3])?;
/// let sigma = shape_sigma(&model, &a, 64, &noise.covariance())?;
/// // The base clamp is fixed; the error grows towards the free part of the wire.
/// assert!(sigma.sigma[0] < 1e-12);
/// assert!(sigma.sigma[32] > 0.0);
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
pub fn shape_sigma<M: WireModel>(
    model: &M,
    a: &Vector6<f64>,
    nodes: usize,
    covariance: &Matrix6<f64>,
) -> Result<ShapeSigma, EstimateError> {
    let jacobians = shape_jacobians(model, a, nodes)?;
    let covariance: Vec<Matrix3<f64>> = jacobians
        .iter()
        .map(|d| d * covariance * d.transpose())
        .collect();
    let sigma = covariance
        .iter()
        .map(|c| c.trace().max(0.0).sqrt())
        .collect();
    Ok(ShapeSigma { covariance, sigma })
}

/// The model's own error against the real wire (module docs): an RMS radius per metre of arc
/// length from the base clamp `e` \[m/m\], so that `σ_model(s) = e · s` \[m\].
///
/// # Example
/// ```
/// use ftwire_estimate::shape::{ModelError, with_model_error};
/// // 0.5 mm at the tip of a 0.5 m wire: 1 mm per metre.
/// let model = ModelError::new(1e-3)?;
/// let sigma_a = [0.0, 3e-4, 4e-4];
/// let sigma = with_model_error(&sigma_a, &model, 0.5);
/// assert!(sigma[0] < 1e-15);
/// assert!((sigma[2] - 5e-4_f64.hypot(4e-4)).abs() < 1e-15);
/// assert!(ModelError::new(-1e-3).is_err());
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelError {
    per_length: f64,
}

impl ModelError {
    /// The model error `per_length` \[m per m of arc length\].
    ///
    /// # Errors
    /// [`EstimateError::BadShapeSetting`] unless `per_length` is finite, `>= 0` and at most
    /// [`MAX_MODEL_ERROR`].
    pub fn new(per_length: f64) -> Result<Self, EstimateError> {
        if !(per_length.is_finite() && (0.0..=MAX_MODEL_ERROR).contains(&per_length)) {
            return Err(EstimateError::BadShapeSetting {
                name: "model_error",
                value: per_length,
                allowed: "finite, >= 0 and <= 1 (m per m of arc length; 1 mm/m is 0.001)",
            });
        }
        Ok(Self { per_length })
    }

    /// `e` \[m/m\].
    pub fn per_length(&self) -> f64 {
        self.per_length
    }

    /// `σ_model(s) = e · s` \[m\] at arc length `s` \[m\].
    pub fn sigma_at(&self, s: f64) -> f64 {
        self.per_length * s
    }
}

/// `σ(s_i) = sqrt(σ_a(s_i)² + σ_model(s_i)²)` \[m\] (module docs) at nodes evenly spaced in arc
/// length from the base clamp (`s_i = i·L/(n − 1)`, `L` = `length` \[m\]), for `σ_a` \[m\] at
/// those nodes (e.g. [`ShapeSigma::sigma`]; all zeros for the model's error alone).
pub fn with_model_error(sigma_a: &[f64], model: &ModelError, length: f64) -> Vec<f64> {
    let step = length / sigma_a.len().saturating_sub(1).max(1) as f64;
    sigma_a
        .iter()
        .enumerate()
        .map(|(i, a)| a.hypot(model.sigma_at(step * i as f64)))
        .collect()
}
