//! A reading's `ã`: the tool's weight taken out of the raw reading, then the learnt
//! calibration, or the mounting alone.

use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::ft::{Mounting, MountingSpec};
use nalgebra::Vector6;

use crate::{Reading, RigError};

/// How a raw reading becomes `ã` (torque first, base clamp frame): the learnt calibration and
/// the sensor's mounting, each if given.
///
/// - A reading's `a` (computed elsewhere) is used as it is.
/// - A `raw` reading (force first, sensor frame) first loses the weight of the tool below the
///   sensor ([`MountingSpec::compensate`], with the reading's gravity), then goes through the
///   calibration at the reading's time ([`Calibration::apply_at`]); without a calibration but
///   with a mounting, through the mounting alone ([`Mounting::to_configuration`]: the model as
///   it is, uncalibrated); with neither it has no `ã`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RawMap {
    calibration: Option<Calibration>,
    mounting: Option<(MountingSpec, Mounting)>,
}

impl RawMap {
    /// The map of `calibration` and `mounting` (`None`: not given).
    ///
    /// # Errors
    /// [`RigError::Estimate`] for a mounting [`MountingSpec::mounting`] refuses.
    pub fn new(
        calibration: Option<Calibration>,
        mounting: Option<MountingSpec>,
    ) -> Result<Self, RigError> {
        let mounting = mounting
            .map(|spec| spec.mounting().map(|transform| (spec, transform)))
            .transpose()?;
        Ok(Self {
            calibration,
            mounting,
        })
    }

    /// The learnt calibration, if given.
    pub fn calibration(&self) -> Option<&Calibration> {
        self.calibration.as_ref()
    }

    /// The mounting, if given.
    pub fn mounting(&self) -> Option<&MountingSpec> {
        self.mounting.as_ref().map(|(spec, _)| spec)
    }

    /// Whether a raw reading can be mapped (a calibration or a mounting is given).
    pub fn maps_raw(&self) -> bool {
        self.calibration.is_some() || self.mounting.is_some()
    }

    /// The reading's `ã` (torque first, base clamp frame), by the rules of [`RawMap`].
    ///
    /// # Errors
    /// [`RigError::Empty`] for a reading with neither `raw` nor `a`; [`RigError::NoGravity`]
    /// for a raw reading without gravity when the mounting has a tool; [`RigError::NoMap`]
    /// for a raw reading with neither a calibration nor a mounting; [`RigError::NotFinite`]
    /// when the map's output is not finite (a reading far outside the calibration's data).
    ///
    /// # Example
    /// ```
    /// use ftwire_estimate::ft::MountingSpec;
    /// use ftwire_rig::{RawMap, Reading, RigError};
    /// use nalgebra::Vector6;
    /// let reading = Reading::raw(0.5, Vector6::new(0.1, 0.0, -0.2, 0.0, 0.01, 0.0));
    /// assert_eq!(RawMap::default().a_tilde(&reading), Err(RigError::NoMap));
    /// let map = RawMap::new(None, Some(MountingSpec::default()))?;
    /// let expected = MountingSpec::default().mounting()?.to_configuration(&reading.raw.ok_or("raw")?);
    /// assert_eq!(map.a_tilde(&reading)?, expected);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn a_tilde(&self, reading: &Reading) -> Result<Vector6<f64>, RigError> {
        let Some(raw) = reading.raw else {
            return reading.a.ok_or(RigError::Empty);
        };
        let a = self.a_of_raw(&raw, reading)?;
        if a.iter().all(|v| v.is_finite()) {
            Ok(a)
        } else {
            Err(RigError::NotFinite { a: a.into() })
        }
    }

    fn a_of_raw(&self, raw: &Vector6<f64>, reading: &Reading) -> Result<Vector6<f64>, RigError> {
        let default = MountingSpec::default();
        let spec = self.mounting().unwrap_or(&default);
        let raw = spec
            .compensate(raw, reading.gravity.as_ref())
            .map_err(|_| RigError::NoGravity {
                tool_mass: spec.tool_mass,
            })?;
        match (&self.calibration, &self.mounting) {
            (Some(calibration), _) => Ok(calibration.apply_at(&raw, reading.time)),
            (None, Some((_, mounting))) => Ok(mounting.to_configuration(&raw)),
            (None, None) => Err(RigError::NoMap),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    /// The tool's weight comes out before the mounting, with the reading's gravity; a reading
    /// without gravity is refused when there is a tool.
    #[test]
    fn a_tools_weight_is_taken_out_first() {
        let spec = MountingSpec {
            tool_mass: 0.4,
            tool_centre_of_mass: [0.0, 0.01, 0.05],
            ..MountingSpec::default()
        };
        let map = RawMap::new(None, Some(spec.clone())).expect("a valid mounting");
        let gravity = Vector3::new(0.0, -9.81, 0.0);
        let wire = Vector6::new(0.3, -0.1, 0.2, 0.01, 0.0, -0.02);
        let reading = Reading::raw(1.5, wire + spec.tool_reading(&gravity));
        let a = map
            .a_tilde(&reading.with_gravity(Some(gravity)))
            .expect("raw with gravity");
        let expected = spec.mounting().expect("valid").to_configuration(&wire);
        assert!((a - expected).norm() < 1e-12, "{a} vs {expected}");
        assert_eq!(
            map.a_tilde(&reading),
            Err(RigError::NoGravity { tool_mass: 0.4 })
        );
        let bad = MountingSpec {
            tool_mass: -1.0,
            ..MountingSpec::default()
        };
        assert!(RawMap::new(None, Some(bad)).is_err());
    }

    #[test]
    fn an_a_is_used_as_it_is_and_an_empty_reading_has_none() {
        let a = Vector6::new(0.0, 0.01, 0.0, 0.0, 0.1, 0.0);
        let map = RawMap::default();
        assert_eq!(map.a_tilde(&Reading::configuration(0.0, a)), Ok(a));
        let empty = Reading {
            a: None,
            ..Reading::configuration(0.0, a)
        };
        assert_eq!(map.a_tilde(&empty), Err(RigError::Empty));
        assert!(!map.maps_raw());
    }
}
