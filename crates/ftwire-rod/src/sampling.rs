//! Seeded uniform sampling of `A`, `A_stable` and `A_free` in normalised units (torque in
//! `c2/L`, force in `c2/L²`; see [`crate::configuration`]), as the paper's planners and
//! experiments sample configurations (§III-D, §IV).
//!
//! All randomness comes from the caller's RNG: the same seed gives the same samples.

use nalgebra::Vector6;
use rand::{Rng, RngExt};

use crate::{Rod, RodError, from_normalised};

/// Sampling settings: a box `[−half_width, half_width]⁶` in normalised units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sampler {
    /// Half-width of the box in normalised units (default `30`).
    pub half_width: f64,
    /// Rejection-sampling budget per accepted sample (default `10_000`).
    pub max_attempts: usize,
}

impl Default for Sampler {
    fn default() -> Self {
        Self {
            half_width: 30.0,
            max_attempts: 10_000,
        }
    }
}

impl Sampler {
    /// A sampler over `[−half_width, half_width]⁶` (normalised units).
    ///
    /// # Errors
    /// [`RodError::BadSamplingRange`] unless `half_width` is finite and positive.
    ///
    /// # Example
    /// ```
    /// use rand::SeedableRng;
    /// use ftwire_rod::{Rod, WireParams, sampling::Sampler};
    /// let rod = Rod::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
    /// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    /// let a = Sampler::new(10.0)?.sample_stable(&rod, &mut rng)?;
    /// assert!(rod.is_stable(&a)?);
    /// # Ok::<(), ftwire_rod::RodError>(())
    /// ```
    pub fn new(half_width: f64) -> Result<Self, RodError> {
        if !(half_width.is_finite() && half_width > 0.0) {
            return Err(RodError::BadSamplingRange { half_width });
        }
        Ok(Self {
            half_width,
            ..Self::default()
        })
    }

    /// A uniform sample of the box in normalised units, in `A` (the excluded plane has
    /// measure zero; an exact hit is redrawn).
    pub fn sample_normalised<R: Rng + ?Sized>(&self, rng: &mut R) -> Vector6<f64> {
        loop {
            let w = self.half_width;
            let a = Vector6::from_fn(|_, _| rng.random_range(-w..=w));
            if crate::validate_configuration(&a).is_ok() {
                return a;
            }
        }
    }

    /// A uniform sample of `A` in the box, in physical units for `rod`'s wire.
    pub fn sample_a<R: Rng + ?Sized>(&self, rod: &Rod, rng: &mut R) -> Vector6<f64> {
        from_normalised(rod.wire(), &self.sample_normalised(rng))
    }

    /// A uniform sample of `A_stable` in the box (rejection sampling), physical units.
    ///
    /// # Errors
    /// [`RodError::SamplingExhausted`] if `max_attempts` draws were all unstable.
    pub fn sample_stable<R: Rng + ?Sized>(
        &self,
        rod: &Rod,
        rng: &mut R,
    ) -> Result<Vector6<f64>, RodError> {
        for _ in 0..self.max_attempts {
            let a = self.sample_a(rod, rng);
            if rod.is_stable(&a)? {
                return Ok(a);
            }
        }
        Err(RodError::SamplingExhausted {
            set: "A_stable",
            attempts: self.max_attempts,
        })
    }

    /// A uniform sample of `A_free` (stable, no self-intersection) in the box, physical units.
    ///
    /// # Errors
    /// [`RodError::SamplingExhausted`] if `max_attempts` draws were all rejected.
    pub fn sample_free<R: Rng + ?Sized>(
        &self,
        rod: &Rod,
        rng: &mut R,
    ) -> Result<Vector6<f64>, RodError> {
        for _ in 0..self.max_attempts {
            let a = self.sample_a(rod, rng);
            if rod.is_stable(&a)? && rod.solve(&a, crate::DEFAULT_NODES)?.is_free() {
                return Ok(a);
            }
        }
        Err(RodError::SamplingExhausted {
            set: "A_free",
            attempts: self.max_attempts,
        })
    }
}
