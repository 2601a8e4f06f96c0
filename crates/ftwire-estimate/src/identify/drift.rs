//! The sensor bias every sample shares: the offset the tare leaves and the drift since.
//!
//! A wrist F/T sensor is tared once, before the wire is picked up. The tare's own white noise
//! leaves an offset `β₀` in every later sample, and the bias then drifts on: a first-order
//! Gauss–Markov process of intensity `q` and time constant `T` (a random walk for `T = ∞`),
//! at its stationary spread (a sensor that has been on for a while); `β(t)` is its change
//! since the tare.
//! So the errors of the samples' `ã` are not independent: with `t` the time since the tare,
//!
//! ```text
//! ã_i = a_i + β(t_i) + w_i,     Cov(β(t_i), β(t_j)) = Σ₀ + Q k(t_i, t_j),
//! k(s, t) = (T/2) (e^{−|s−t|/T} − e^{−s/T} − e^{−t/T} + 1)      (→ min(s, t) as T → ∞)
//! ```
//!
//! with `Σ₀` the tare offset's covariance, `Q = q qᵀ` the drift's covariance per second and
//! `w_i` the rest's own white noise. A fit that treats the `β(t_i)` as independent noise
//! absorbs the drift into `η`, and more samples, later in the drift, make it worse.
//!
//! **The joint estimate.** The pose equation of each rest is `Γ_η(ã_i − β_i) = b̃_i`, with the
//! `β_i` a path of the process above. Its maximum-likelihood estimate of `η` with the `β`
//! path marginalised is, to first order, generalised least squares with the stacked residual's
//! full covariance
//!
//! ```text
//! Cov(r_i, r_j) = W J_i (δ_ij Σ_a + Cov(β(t_i), β(t_j))) J_jᵀ W + δ_ij W Σ_b W
//! ```
//!
//! (`J_i = J_η(ã_i)`, `W` the residual weighting): the same fit as estimating `η` and every
//! `β_i` together by batch Gauss–Newton with the random walk as the `β` path's prior, with
//! the `β_i` eliminated. Its information, and so its covariance, counts the drift: a sample
//! late in a long run says less about `η`, never something wrong.

use nalgebra::Matrix6;

use crate::EstimateError;

/// The bias model of the samples' `ã` (see the module docs). Matrices are in `ã`'s frame and
/// units: torque first \[N·m\], then force \[N\], base clamp frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BiasDrift {
    /// `Σ₀`: the covariance of the offset the tare leaves \[N²·m², N²\].
    pub tare: Matrix6<f64>,
    /// `Q`: the drift's covariance per second \[N²·m²/s, N²/s\] (a random walk of intensity
    /// `q` per channel has `q²` on the diagonal).
    pub rate: Matrix6<f64>,
    /// `T`: the drift's time constant \[s\], `> 0`, or `f64::INFINITY` for a random walk.
    pub time_constant: f64,
}

impl BiasDrift {
    /// The model of a sensor whose channels are independent, given in the sensor's own frame
    /// and order: `tare_std` the tare offset's standard deviation per channel, `intensity` the
    /// drift intensity `q` per channel \[per √s\], both mapped to `ã` by the linear map
    /// `to_a` (`ã = to_a · raw`, e.g. the mounting's wrench transform: it turns a force drift
    /// into a torque drift at the clamp, a lever arm away).
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] for a non-finite or negative entry, or a bad time
    /// constant.
    pub fn from_sensor(
        to_a: &Matrix6<f64>,
        tare_std: [f64; 6],
        intensity: [f64; 6],
        time_constant: f64,
    ) -> Result<Self, EstimateError> {
        let diagonal = |v: [f64; 6]| Matrix6::from_diagonal(&v.map(|x| x * x).into());
        let drift = Self {
            tare: to_a * diagonal(tare_std) * to_a.transpose(),
            rate: to_a * diagonal(intensity) * to_a.transpose(),
            time_constant,
        };
        for (field, values) in [("bias.tare_std", tare_std), ("bias.intensity", intensity)] {
            if let Some(v) = values.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
                return Err(EstimateError::BadIdentifySetting {
                    field,
                    value: *v,
                    allowed: "finite and >= 0",
                });
            }
        }
        drift.validate()?;
        Ok(drift)
    }

    /// Checks the matrices (finite, symmetric, no negative diagonal) and the time constant.
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] naming the bad field.
    pub fn validate(&self) -> Result<(), EstimateError> {
        let bad = |field, value, allowed| {
            Err(EstimateError::BadIdentifySetting {
                field,
                value,
                allowed,
            })
        };
        for (field, m) in [("bias.tare", &self.tare), ("bias.rate", &self.rate)] {
            if let Some(v) = m.iter().find(|v| !v.is_finite()) {
                return bad(field, *v, "finite");
            }
            if let Some(v) = m.diagonal().iter().find(|v| **v < 0.0) {
                return bad(field, *v, "a covariance: no negative diagonal entry");
            }
            let asymmetry = (m - m.transpose()).amax();
            if asymmetry > 1e-12 * m.amax().max(f64::MIN_POSITIVE) {
                return bad(field, asymmetry, "a symmetric matrix");
            }
        }
        let t = self.time_constant;
        if t.is_nan() || t <= 0.0 {
            return bad("bias.time_constant", t, "> 0 (inf for a random walk)");
        }
        Ok(())
    }

    /// `k(s, t)`: the drift's scalar kernel \[s\] (see the module docs), for times since the
    /// tare `s, t ≥ 0`.
    pub fn kernel(&self, s: f64, t: f64) -> f64 {
        let tau = self.time_constant;
        if tau.is_infinite() {
            return s.min(t);
        }
        // Written as sums of (1 − e^{−x/T}) terms, which stay accurate for x ≪ T.
        let one_minus = |x: f64| -(-x / tau).exp_m1();
        let value = 0.5 * tau * (one_minus(s) + one_minus(t) - one_minus((s - t).abs()));
        value.max(0.0)
    }

    /// `Cov(β(s), β(t)) = Σ₀ + Q k(s, t)` for times since the tare \[s\].
    pub fn covariance(&self, s: f64, t: f64) -> Matrix6<f64> {
        self.tare + self.rate * self.kernel(s, t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn walk(t: f64) -> BiasDrift {
        BiasDrift {
            tare: Matrix6::identity() * 1e-6,
            rate: Matrix6::identity() * 4e-6,
            time_constant: t,
        }
    }

    #[test]
    fn kernel_is_the_random_walk_s_min_for_an_infinite_time_constant() {
        let d = walk(f64::INFINITY);
        assert_eq!(d.kernel(3.0, 5.0), 3.0);
        assert_eq!(d.kernel(5.0, 3.0), 3.0);
        assert_eq!(d.kernel(0.0, 5.0), 0.0);
    }

    #[test]
    fn kernel_tends_to_min_for_times_short_against_the_time_constant() {
        let d = walk(600.0);
        let k = d.kernel(10.0, 20.0);
        assert!((k - 10.0).abs() < 0.2, "{k}");
        // Far beyond T the variance settles at T/2 (the stationary spread, twice: the
        // difference of two nearly independent values).
        let far = d.kernel(1e6, 1e6);
        assert!((far - 600.0).abs() < 1e-6, "{far}");
    }

    #[test]
    fn kernel_matches_a_simulated_gauss_markov_process() {
        // Exact discretisation of dx = −x/T dt + q dW from its stationary spread (a sensor
        // that has been on for a while): the sample covariance of the increments since the
        // tare, x(s) − x(0) and x(t) − x(0), over many paths against k(s, t) q².
        use rand::SeedableRng;
        use rand_distr::{Distribution, StandardNormal};
        let (tau, dt, q) = (5.0, 0.01, 1.0);
        let d = walk(tau);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let (i_s, i_t) = (200_usize, 700_usize);
        let (mut sum_ss, mut sum_st) = (0.0, 0.0);
        let paths = 4000;
        let phi = (-dt / tau).exp();
        let step_std = q * (0.5 * tau * (1.0 - phi * phi)).sqrt();
        let stationary_std = q * (0.5 * tau).sqrt();
        for _ in 0..paths {
            let draw: f64 = StandardNormal.sample(&mut rng);
            let start = stationary_std * draw;
            let mut x = start;
            let mut at_s = 0.0;
            for k in 1..=i_t {
                let n: f64 = StandardNormal.sample(&mut rng);
                x = phi * x + step_std * n;
                if k == i_s {
                    at_s = x - start;
                }
            }
            sum_ss += at_s * at_s;
            sum_st += at_s * (x - start);
        }
        let (s, t) = (i_s as f64 * dt, i_t as f64 * dt);
        let (var_s, cov) = (sum_ss / paths as f64, sum_st / paths as f64);
        assert!(
            (var_s / d.kernel(s, s) - 1.0).abs() < 0.08,
            "{var_s} vs {}",
            d.kernel(s, s)
        );
        assert!(
            (cov / d.kernel(s, t) - 1.0).abs() < 0.12,
            "{cov} vs {}",
            d.kernel(s, t)
        );
    }

    #[test]
    fn from_sensor_maps_a_force_drift_into_a_torque_drift_at_the_clamp() {
        // ã = to_a raw, raw force first; a clamp 0.1 m along z: τ = −p × f.
        let mut to_a = Matrix6::zeros();
        to_a.fixed_view_mut::<3, 3>(3, 0).fill_with_identity();
        to_a.fixed_view_mut::<3, 3>(0, 3).fill_with_identity();
        let p = nalgebra::Vector3::new(0.0, 0.0, 0.1);
        to_a.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(-p.cross_matrix()));
        let d = BiasDrift::from_sensor(&to_a, [0.0; 6], [2e-3, 2e-3, 2e-3, 0.0, 0.0, 0.0], 600.0)
            .expect("valid");
        // Torque about x from force along y: (0.1 · 2e-3)².
        assert!((d.rate[(0, 0)] - 4e-8).abs() < 1e-15);
        assert_eq!(d.rate[(2, 2)], 0.0);
        assert!((d.rate[(3, 3)] - 4e-6).abs() < 1e-15);
    }

    #[test]
    fn bad_settings_are_named() {
        let mut d = walk(600.0);
        d.time_constant = 0.0;
        assert!(
            d.validate()
                .expect_err("refused")
                .to_string()
                .contains("bias.time_constant")
        );
        let mut d = walk(600.0);
        d.rate[(1, 1)] = f64::NAN;
        assert!(
            d.validate()
                .expect_err("refused")
                .to_string()
                .contains("bias.rate")
        );
        let err = BiasDrift::from_sensor(&Matrix6::identity(), [-1.0; 6], [0.0; 6], 1.0);
        assert!(
            err.expect_err("refused")
                .to_string()
                .contains("bias.tare_std")
        );
    }
}
