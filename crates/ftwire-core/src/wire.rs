use serde::{Deserialize, Serialize};

use crate::{CoreError, ensure_positive};

/// Mechanical parameters of a Kirchhoff wire: stiffnesses, length and radius.
///
/// Parse, don't validate: once a `WireParams` exists its values are finite and positive.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WireParams {
    c: [f64; 3],
    length: f64,
    radius: f64,
}

impl WireParams {
    /// Builds wire parameters.
    ///
    /// - `c`: stiffnesses `(c1, c2, c3)` \[N·m²\]: torsion, then bending about body y and z.
    /// - `length`: wire length `L` \[m\].
    /// - `radius`: wire radius \[m\], used for self-intersection (segments closer than `2·radius`).
    ///
    /// # Errors
    /// [`CoreError::NonFinite`] or [`CoreError::NotPositive`] naming the field.
    ///
    /// # Example
    /// ```
    /// let wire = ftwire_core::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015)?;
    /// assert_eq!(wire.c(), [0.214, 0.278, 0.278]);
    /// assert!(ftwire_core::WireParams::new([0.0, 1.0, 1.0], 1.0, 0.001).is_err());
    /// # Ok::<(), ftwire_core::CoreError>(())
    /// ```
    pub fn new(c: [f64; 3], length: f64, radius: f64) -> Result<Self, CoreError> {
        const NAMES: [&str; 3] = ["c1", "c2", "c3"];
        for (name, &value) in NAMES.iter().zip(&c) {
            ensure_positive(name, value)?;
        }
        ensure_positive("length", length)?;
        ensure_positive("radius", radius)?;
        Ok(Self { c, length, radius })
    }

    /// Stiffnesses `(c1, c2, c3)` \[N·m²\].
    pub fn c(&self) -> [f64; 3] {
        self.c
    }

    /// Length `L` \[m\].
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Radius \[m\].
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Returns a copy with another length.
    ///
    /// # Errors
    /// [`CoreError::NotPositive`] if `length` is not finite and positive.
    pub fn with_length(self, length: f64) -> Result<Self, CoreError> {
        Self::new(self.c, length, self.radius)
    }

    /// Returns a copy with other stiffnesses.
    ///
    /// # Errors
    /// [`CoreError::NotPositive`] naming the first stiffness that is not finite and positive.
    pub fn with_c(self, c: [f64; 3]) -> Result<Self, CoreError> {
        Self::new(c, self.length, self.radius)
    }

    /// The torque scale `c2 / L` \[N·m\] used to normalise configurations.
    pub fn torque_scale(&self) -> f64 {
        self.c[1] / self.length
    }

    /// The force scale `c2 / L²` \[N\] used to normalise configurations.
    pub fn force_scale(&self) -> f64 {
        self.c[1] / (self.length * self.length)
    }
}

#[derive(Deserialize)]
struct RawWireParams {
    c: [f64; 3],
    length: f64,
    radius: f64,
}

impl<'de> Deserialize<'de> for WireParams {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let raw = RawWireParams::deserialize(deserializer)?;
        WireParams::new(raw.c, raw.length, raw.radius).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_bad_field_is_named() {
        let cases = [
            (WireParams::new([-1.0, 1.0, 1.0], 1.0, 0.1), "c1"),
            (WireParams::new([1.0, f64::NAN, 1.0], 1.0, 0.1), "c2"),
            (WireParams::new([1.0, 1.0, 0.0], 1.0, 0.1), "c3"),
            (
                WireParams::new([1.0, 1.0, 1.0], f64::INFINITY, 0.1),
                "length",
            ),
            (WireParams::new([1.0, 1.0, 1.0], 1.0, -0.1), "radius"),
        ];
        for (result, field) in cases {
            match result {
                Err(CoreError::NotPositive { field: f, .. }) => assert_eq!(f, field),
                other => panic!("expected an error naming {field}, got {other:?}"),
            }
        }
    }

    #[test]
    fn scales_follow_c2_and_length() {
        let wire = WireParams::new([0.042, 0.055, 0.055], 0.5, 0.001).expect("valid");
        assert!((wire.torque_scale() - 0.11).abs() < 1e-12);
        assert!((wire.force_scale() - 0.22).abs() < 1e-12);
    }
}
