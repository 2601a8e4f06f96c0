#![doc = include_str!("../README.md")]

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
