//! The loaded model: a distributed weight and a rest curvature/twist (DESIGN.md, "The loaded
//! model: gravity and rest curvature"; beyond the paper, which has neither).
//!
//! A [`Load`] is the wire's weight per length `w = ρ A g` \[N/m\], a constant vector in the base
//! clamp frame, and its natural (rest) strains `u₀ = (κ1, κ2, κ3)` \[1/m\] in the body frame
//! (twist rate, then the rest curvatures about body y and z, the axes of `c2` and `c3`). Attach
//! it with [`Rod::with_load`](crate::Rod::with_load); every solve then honours it. With
//! [`Load::none`] the unloaded solver runs unchanged, bit for bit.
//!
//! # Equations
//!
//! Same conventions as [`crate::equations`]: `μ = (m, n)` the internal wrench that the distal
//! part exerts on the proximal one, body frame, torque first; `a = μ(0)`. The constitutive law
//! becomes `m = C (u − u₀)`, i.e. `u = C⁻¹ m + u₀`.
//!
//! **Force.** Equilibrium of the segment `[0, t]` (weight `w t`, the base reaction and the
//! distal part's force) gives the internal force in the base frame in closed form:
//!
//! ```text
//! N(t) = R n = a_f − w t.
//! ```
//!
//! Differentiating, `R (û n + n') = −w`, so `n' = n × u − Rᵀ w`.
//!
//! **Moment.** The spatial moment about the base origin, `R m + p × N`, changes only by the
//! weight's moment: `(R m + p × N)' = −p × w`. With `m' = m × u + n × e1` (unchanged) this holds
//! identically: `(R m)' = R (û m + m') = R (n × e1)` and `(p × N)' = R e1 × R n − p × w`. Hence
//!
//! ```text
//! m = Rᵀ (a_m − P × w − p × N),   P(t) = ∫₀ᵗ p ds,
//! m' = m × u + n × e1,            n' = n × u − Rᵀ w.
//! ```
//!
//! **Conserved quantity.** `H = ½ m·C⁻¹m + m·u₀ + n1 + w·p` is constant along the wire
//! (`dH/dt = u·(m × u + n × e1) + e1·(n × u) − e1·Rᵀw + w·R e1 = 0`). It bounds the curvature a
//! priori, which sets the step count (below).
//!
//! **Variations.** Perturb `a` by `δa`; `q` moves to `q exp(ĵ)` with `j = (ω, v) = J δa`, and
//! `μ` by `M δa`. Since `δ(Rᵀ w) = −ω̂ Rᵀ w = (Rᵀ w) × ω`, the costate's variation is
//!
//! ```text
//! M' = F M + E J,   F = [[m̂ C⁻¹ − û, −ê1], [n̂ C⁻¹, −û]],   E = [[0, 0], [−(Rᵀw)^, 0]]
//! ```
//!
//! (`E`'s rows: the force part; its columns: the `ω` part of `J`). `F` is DESIGN.md's table of
//! eq. 4 when `u₀ = 0`; with `u₀`, `û` includes it. The twist is `ξ = (u, e1)` with `δξ =
//! (C⁻¹ δm, 0)`, so `J' = G M + H J`, `H = −ad_ξ`, keeps its form, `u` including `u₀`.
//!
//! **What happens to the closed forms.** Closed form (A) of [`crate::equations`], `μ =
//! Ad_qᵀ a`, becomes the two lines above: `n` stays algebraic in `(q, t)`, `m` needs `P`. Closed
//! form (B), `M = Ad_qᵀ + K(μ) J`, keeps its force rows (`δn = n̂ ω + Rᵀ δa_f`) but its torque
//! rows gain `Rᵀ ŵ ∫₀ᵗ R J_v ds` (`J_v` the translational rows of `J`), an integral of the
//! Jacobian that no function of `(q, J)` at `t` gives. So the loaded solver integrates `R`,
//! `p`, `m`, `n`, the torque rows `M_m` of `M` and `J`, with the force rows by their closed form
//! `M_n = [0, Rᵀ] + n̂ J_ω` (then `M_n`'s own rate, with the `E J` term, is not needed), plus
//! `P = ∫ p`: 75 numbers, the crate's DOP853 tableau at fixed step (the private `loaded`
//! module). `m` and `n` are integrated; at the shape nodes between grid points `μ` comes from
//! the closed forms above (`P` interpolated like the frame). The closed forms, the
//! Hamiltonian and the spatial moment balance are checked along the wire in `tests/loaded.rs`,
//! and `M(L)`, `J(L)` against finite differences and an independent integration of the full
//! system (`M' = F M + E J`, 90 numbers).
//!
//! **Step count.** With `K = H(0) + n_max + |w| L`, `n_max = |a_f| + |w| L` (so that `n1 ≥
//! −n_max` and `|w·p| ≤ |w| L`), `k = |C^{-1/2} m|` obeys `½ k² ≤ K + β k`, `β = |C^{1/2} u₀|`,
//! so `k ≤ β + √(β² + 2K)` and `|u| ≤ k / √c_min + |u₀|`. The turning scale `σ` is the larger of
//! that, the load wavenumber `√(n_max / c_min)` and `∛(|w| / c_min)`; it reduces to
//! [`crate::equations::turning_scale`] without a load, and the integrator takes its usual
//! `max(8, ⌈1.5 σL⌉)` steps.
//!
//! **Stability.** The conjugate-point test, `det J` keeping its sign on `(0, L]`, is the Jacobi
//! condition of the loaded problem too; the solver tracks it on the same grid as without load.
//!
//! **The set `A`.** With a weight or a rest curvature, `a = 0` (or any `a` on the plane
//! `a2 = a3 = a5 = a6 = 0`) can be a valid, even unique, equilibrium: a wire hanging straight
//! along gravity, or a rest arc left alone. `A`'s definition (eq. 2) is kept as it is, so such
//! `a` are still rejected ([`crate::validate_configuration`]); configurations arbitrarily close
//! to them are accepted and solved correctly.

use ftwire_core::{ensure_finite, ensure_positive};
use nalgebra::Vector3;

use crate::RodError;

/// A distributed load on the wire: its weight per length and its rest strains.
///
/// Both default to zero ([`Load::none`]), the paper's model.
///
/// # Example
/// ```
/// use nalgebra::{Vector3, Vector6};
/// use ftwire_rod::{Load, Rod, WireParams};
/// // 2 mm nitinol (ρ = 6450 kg/m³), gravity along −z of the base clamp frame.
/// let load = Load::from_gravity(6450.0, 0.001, Vector3::new(0.0, 0.0, -9.81))?;
/// assert!((load.weight_per_length.z + 6450.0 * std::f64::consts::PI * 1e-6 * 9.81).abs() < 1e-12);
/// let rod = Rod::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?).with_load(load);
/// let a = Vector6::new(0.0, 0.0, 0.01, 0.0, 0.0, 0.0);
/// // Its weight pulls the wire down, compared with the weightless one.
/// let loaded = rod.tip(&a)?;
/// let free = rod.with_load(Load::none()).tip(&a)?;
/// assert!(loaded.translation.z < free.translation.z);
/// # Ok::<(), ftwire_rod::RodError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Load {
    /// w = ρ·A·g [N/m], base clamp frame.
    ///
    /// The wire's weight per unit length, constant along it, in the base clamp frame (default
    /// zero).
    pub weight_per_length: Vector3<f64>,
    /// u₀ [1/m], body frame (κ1 twist, κ2, κ3 bending, same axes as c).
    ///
    /// The strains of the unloaded wire: `u = C⁻¹ m + u₀` (default zero: straight, untwisted).
    pub natural_curvature: Vector3<f64>,
}

impl Load {
    /// No load: no weight, a straight untwisted rest shape (the paper's model).
    ///
    /// # Example
    /// ```
    /// assert!(ftwire_rod::Load::none().is_none());
    /// ```
    pub fn none() -> Self {
        Self::default()
    }

    /// Whether this is [`Load::none`]: both the weight and the rest strains are exactly zero.
    pub fn is_none(&self) -> bool {
        self.weight_per_length == Vector3::zeros() && self.natural_curvature == Vector3::zeros()
    }

    /// The weight of a solid round wire: `w = density · π · radius² · gravity`, no rest strain.
    ///
    /// `density` \[kg/m³\] and `radius` \[m\] must be finite and positive, `gravity` \[m/s²\]
    /// (in the base clamp frame) finite.
    ///
    /// # Errors
    /// [`RodError::Core`] naming the value: `density` or `radius` not finite and positive,
    /// `gravity` not finite, or `weight_per_length` overflowing.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector3;
    /// use ftwire_rod::{CoreError, Load, RodError};
    /// let g = Vector3::new(0.0, 0.0, -9.81);
    /// assert!(Load::from_gravity(6450.0, 0.001, g).is_ok());
    /// assert!(matches!(
    ///     Load::from_gravity(-1.0, 0.001, g),
    ///     Err(RodError::Core(CoreError::NotPositive { field: "density", .. }))
    /// ));
    /// ```
    pub fn from_gravity(
        density: f64,
        radius: f64,
        gravity: Vector3<f64>,
    ) -> Result<Self, RodError> {
        ensure_positive("density", density)?;
        ensure_positive("radius", radius)?;
        ensure_finite("gravity", gravity.as_slice())?;
        let weight_per_length = gravity * (density * std::f64::consts::PI * radius * radius);
        ensure_finite("weight_per_length", weight_per_length.as_slice())?;
        Ok(Self {
            weight_per_length,
            natural_curvature: Vector3::zeros(),
        })
    }

    /// The same load with rest strains `k = (κ1, κ2, κ3)` \[1/m\] (body frame: twist rate, rest
    /// curvatures about body y and z).
    ///
    /// # Errors
    /// [`RodError::Core`] naming `natural_curvature` and the component if `k` is not finite.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector3;
    /// let load = ftwire_rod::Load::none().with_natural_curvature(Vector3::new(0.0, 0.0, 1.5))?;
    /// assert!(!load.is_none());
    /// assert!(ftwire_rod::Load::none().with_natural_curvature(Vector3::new(f64::NAN, 0.0, 0.0)).is_err());
    /// # Ok::<(), ftwire_rod::RodError>(())
    /// ```
    pub fn with_natural_curvature(self, k: Vector3<f64>) -> Result<Self, RodError> {
        ensure_finite("natural_curvature", k.as_slice())?;
        Ok(Self {
            natural_curvature: k,
            ..self
        })
    }

    /// Checks that both fields are finite (they are public, so a `Load` can be built without
    /// the validating constructors).
    pub(crate) fn validate(&self) -> Result<(), RodError> {
        ensure_finite("weight_per_length", self.weight_per_length.as_slice())?;
        ensure_finite("natural_curvature", self.natural_curvature.as_slice())?;
        Ok(())
    }

    /// The a-priori turning scale `σ` \[1/m\] of configuration `a` under this load for a wire of
    /// stiffnesses `c` and length `length` (see the module docs, "Step count").
    pub(crate) fn turning_scale(
        &self,
        c: [f64; 3],
        a: &nalgebra::Vector6<f64>,
        length: f64,
    ) -> f64 {
        let c_min = c[0].min(c[1]).min(c[2]);
        let u0 = &self.natural_curvature;
        let w = self.weight_per_length.norm();
        let n_max = (a[3] * a[3] + a[4] * a[4] + a[5] * a[5]).sqrt() + w * length;
        let h0 = 0.5 * (a[0] * a[0] / c[0] + a[1] * a[1] / c[1] + a[2] * a[2] / c[2])
            + a[0] * u0.x
            + a[1] * u0.y
            + a[2] * u0.z
            + a[3];
        let k_max = (h0 + n_max + w * length).max(0.0);
        let beta = (c[0] * u0.x * u0.x + c[1] * u0.y * u0.y + c[2] * u0.z * u0.z).sqrt();
        let k = beta + (beta * beta + 2.0 * k_max).sqrt();
        let curvature = k / c_min.sqrt() + u0.norm();
        curvature
            .max((n_max / c_min).sqrt())
            .max((w / c_min).cbrt())
    }
}
