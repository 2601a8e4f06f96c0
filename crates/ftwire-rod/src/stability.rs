//! The stability test of paper §II-A: `a ∈ A_stable` iff `det J(t) ≠ 0` on `(0, L]`, tested as
//! "`det J(t)` keeps one sign at every integration grid point after `t = 0`" (DESIGN.md).
//!
//! # The first step
//!
//! `det J(t)` vanishes like `t¹⁴` at `t = 0` (the base cannot be displaced along the tangent to
//! first order), so its sign at the first grid point is decided by high-order terms of `J`.
//! One RK4 step from `J(0) = 0` is exact only for polynomials of degree 4 and gets that sign
//! wrong, which makes a naive test call every configuration unstable. The default
//! [`Method::Dop853`](crate::Method::Dop853) (as [`Method::Rk8`](crate::Method::Rk8)) is exact
//! to degree 8 on the first step, and its sign at the first grid point agrees with a fine
//! reference over random configurations (test `first_step_sign_matches_a_fine_reference` in
//! `tests/stability.rs`, which also shows the RK4 failure). In addition the first step is
//! always split into [`FIRST_STEP_SUBSTEPS`] substeps, which cuts the error of `det J` at the
//! first grid point by about two orders of magnitude for one extra step (measurements in
//! `docs/integrator.md`).

/// The first integration step is taken as this many equal substeps (cheap insurance for the
/// sign of `det J` at the first grid point; see the module docs).
pub const FIRST_STEP_SUBSTEPS: usize = 2;

/// The outcome of the stability test along the wire.
#[derive(Debug, Clone, PartialEq)]
pub struct Stability {
    /// `true` iff `det J` kept one sign (and stayed non-zero and finite) at every grid point.
    pub stable: bool,
    /// Smallest `|det J(t)|` over the grid points tested.
    pub det_j_min: f64,
    /// The grid interval `[t_(k−1), t_k]` \[m\] containing the first sign change of `det J`,
    /// if any: the first conjugate point lies in it.
    pub first_sign_change: Option<[f64; 2]>,
    /// `det J(t_k)` at the grid points `t_k = k L / steps`, `k = 1, 2, …` (up to the early
    /// exit, if one was taken). Empty when not recorded.
    pub det_j: Vec<f64>,
    /// Grid spacing `L / steps` \[m\].
    pub spacing: f64,
}

/// Tracks the sign of `det J` along the grid.
#[derive(Debug, Clone)]
pub(crate) struct SignTracker {
    reference: f64,
    stable: bool,
    first_change: Option<[f64; 2]>,
    min_abs: f64,
    det_j: Option<Vec<f64>>,
    spacing: f64,
}

impl SignTracker {
    /// A tracker for a grid of `points` points after `t = 0`, spaced `spacing`; `record` keeps
    /// every `det J` (room for all of them is reserved at once).
    pub fn new(spacing: f64, points: usize, record: bool) -> Self {
        Self {
            reference: 0.0,
            stable: true,
            first_change: None,
            min_abs: f64::INFINITY,
            det_j: record.then(|| Vec::with_capacity(points)),
            spacing,
        }
    }

    /// Records `det J(t)` at grid point `t`; returns whether the wire is still stable.
    pub fn push(&mut self, t: f64, det: f64) -> bool {
        if let Some(v) = &mut self.det_j {
            v.push(det);
        }
        self.min_abs = self.min_abs.min(det.abs());
        let sign = if det.is_finite() { det.signum() } else { 0.0 };
        if det == 0.0 || sign == 0.0 {
            self.fail(t);
        } else if self.reference == 0.0 {
            self.reference = sign;
        } else if sign != self.reference {
            self.fail(t);
        }
        self.stable
    }

    fn fail(&mut self, t: f64) {
        if self.stable {
            self.stable = false;
            self.first_change = Some([(t - self.spacing).max(0.0), t]);
        }
    }

    pub fn finish(self) -> Stability {
        Stability {
            stable: self.stable,
            det_j_min: if self.min_abs.is_nan() {
                f64::NAN
            } else {
                self.min_abs
            },
            first_sign_change: self.first_change,
            det_j: self.det_j.unwrap_or_default(),
            spacing: self.spacing,
        }
    }
}
