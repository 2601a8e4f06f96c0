#![doc = include_str!("../README.md")]
//!
//! # Modules
//!
//! - [`configuration`]: the set `A` (paper eq. 2), validation, normalised units.
//! - [`equations`]: eq. 1, 3, 4 and the closed forms for `μ(t)` and `M(t)`.
//! - [`integrator`]: fixed-step Runge–Kutta (the tableaux in the private `tableau` module,
//!   septic Hermite dense output in `hermite`; the convergence study is in
//!   `docs/integrator.md`).
//! - [`rod`]: [`Rod`], the entry point: [`Rod::solve`], [`Rod::shape`], [`Rod::jacobian`],
//!   [`Rod::is_stable`], [`Rod::tip`]. The flat states and hot right-hand sides it integrates
//!   are in the private `kirchhoff` module.
//! - [`load`]: [`Load`], a distributed weight and rest strains, and the derivation of the
//!   loaded equations (the loaded solver is the private `loaded` module).
//! - [`stability`]: the `det J` sign test and the first-step pitfall.
//! - [`intersection`]: self-contact of the centreline.
//! - [`perturbation`]: the perturbation map of paper eq. 8–11.
//! - [`sampling`]: seeded uniform sampling of `A`, `A_stable`, `A_free`.
//! - [`batch`]: many solves at once (parallel with the `parallel` feature).
//! - [`se3`]: hat/vee, se(3) exp/log, adjoints.

mod arith;
pub mod batch;
pub mod configuration;
pub mod equations;
mod error;
mod hermite;
pub mod integrator;
pub mod intersection;
mod kirchhoff;
pub mod load;
mod loaded;
pub mod perturbation;
pub mod rod;
pub mod sampling;
pub mod se3;
#[cfg(target_arch = "x86_64")]
mod simd;
pub mod stability;
mod tableau;

pub use configuration::{from_normalised, to_normalised, validate_configuration};
pub use equations::{costate_rate, f_matrix, g_matrix, h_matrix, m_matrix};
pub use error::RodError;
pub use ftwire_core::{CoreError, Pose, WireParams};
pub use integrator::{Integrator, Method};
pub use intersection::{Contact, segment_distance, self_contact};
pub use load::Load;
pub use rod::{DEFAULT_NODES, JacobianSolution, Rod, Shape, Solution};
pub use stability::Stability;
