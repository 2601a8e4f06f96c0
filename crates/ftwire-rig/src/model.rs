//! The wire model a measurement solves with: the paper's weight-free Kirchhoff rod, or the
//! loaded rod with the wire's weight under gravity given in the base clamp frame (DESIGN.md,
//! "The loaded model").

use ftwire_core::WireParams;
use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::calibration::LabelModel;
use ftwire_rod::Load;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::RigError;

/// Largest gravity accepted \[m/s²\]: ten times the Earth's, far above any rig's.
pub const MAX_GRAVITY: f64 = 100.0;

/// Which model of the wire a measurement solves `ã` with.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum WireModelChoice {
    /// The paper's model: no weight, straight at rest.
    #[default]
    Weightless,
    /// The loaded rod: weight per length `w = ρ π r² g`, with `g` in the base clamp frame, and
    /// the wire's rest curvature.
    Loaded {
        /// Gravity in the base clamp frame \[m/s²\].
        gravity_in_clamp: [f64; 3],
    },
}

/// The kind of wire model a user chooses (`--model kirchhoff|loaded`): the paper's weightless
/// rod or the loaded one; with gravity's direction it is a [`WireModelChoice`]
/// ([`ModelKind::choice`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ModelKind {
    /// The paper's model: a weightless Kirchhoff rod, straight at rest (`kirchhoff` on the
    /// command line and in summaries).
    #[serde(rename = "kirchhoff")]
    Weightless,
    /// The loaded Kirchhoff rod: the wire's weight under gravity and its rest
    /// curvature (`ftwire_rod::Load`).
    Loaded,
}

impl ModelKind {
    /// The model given, or the default for a world with gravity on or off: `loaded` when
    /// gravity is on, `kirchhoff` when it is off.
    pub fn resolve(given: Option<Self>, gravity_on: bool) -> Self {
        match (given, gravity_on) {
            (Some(model), _) => model,
            (None, true) => Self::Loaded,
            (None, false) => Self::Weightless,
        }
    }

    /// The model with gravity `gravity_in_clamp` (base clamp frame \[m/s²\]) for the loaded
    /// rod.
    ///
    /// ```
    /// use ftwire_rig::{ModelKind, WireModelChoice};
    /// let g = [0.0, 0.0, -9.81];
    /// let loaded = WireModelChoice::Loaded { gravity_in_clamp: g };
    /// assert_eq!(ModelKind::resolve(None, true).choice(g), loaded);
    /// assert_eq!(ModelKind::resolve(None, false).choice(g), WireModelChoice::Weightless);
    /// assert_eq!("loaded".parse::<ModelKind>(), Ok(ModelKind::Loaded));
    /// ```
    pub fn choice(self, gravity_in_clamp: [f64; 3]) -> WireModelChoice {
        match self {
            Self::Weightless => WireModelChoice::Weightless,
            Self::Loaded => WireModelChoice::Loaded { gravity_in_clamp },
        }
    }

    /// Every value's name, as `--model` takes it.
    pub const NAMES: [&'static str; 2] = ["kirchhoff", "loaded"];

    /// The model's name in tables and summaries.
    pub fn name(self) -> &'static str {
        match self {
            Self::Weightless => "kirchhoff",
            Self::Loaded => "loaded",
        }
    }

    /// The other model.
    pub fn other(self) -> Self {
        match self {
            Self::Weightless => Self::Loaded,
            Self::Loaded => Self::Weightless,
        }
    }
}

impl std::fmt::Display for ModelKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for ModelKind {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text {
            "kirchhoff" => Ok(Self::Weightless),
            "loaded" => Ok(Self::Loaded),
            _ => Err(format!("model {text:?}: expected kirchhoff or loaded")),
        }
    }
}

/// What a wire is beyond its stiffnesses and length: what its weight and rest shape need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WireBody {
    /// Stiffnesses, length and radius.
    pub params: WireParams,
    /// Density \[kg/m³\].
    pub density: f64,
    /// Rest strains `u₀ = (κ1, κ2, κ3)` \[1/m\], body frame.
    pub natural_curvature: Vector3<f64>,
}

impl WireModelChoice {
    /// The loaded model under `gravity_in_clamp` \[m/s²\], base clamp frame, checked: finite,
    /// of norm in `(0, MAX_GRAVITY]`.
    ///
    /// # Errors
    /// [`RigError::Setting`] naming the value and what is allowed.
    pub fn loaded(gravity_in_clamp: [f64; 3]) -> Result<Self, RigError> {
        let norm = Vector3::from(gravity_in_clamp).norm();
        if !(norm.is_finite() && norm > 0.0 && norm <= MAX_GRAVITY) {
            return Err(RigError::Setting(format!(
                "gravity in the clamp frame {gravity_in_clamp:?} m/s² is not allowed: three \
                 finite numbers, of norm above 0 and at most {MAX_GRAVITY} m/s²"
            )));
        }
        Ok(Self::Loaded { gravity_in_clamp })
    }

    /// The model to solve a calibration's `a` with: the calibration's own label model
    /// (`calibration.json`'s `model`) unless `given` names one, and `given` only when it is
    /// the same (gravity equal to 1e-9 m/s²).
    ///
    /// # Errors
    /// A sentence naming both when `given` and the calibration's model differ, or when the
    /// calibration's gravity is out of range.
    pub fn of_calibration(trained: &LabelModel, given: Option<[f64; 3]>) -> Result<Self, String> {
        let own = match trained.gravity_in_clamp {
            None => Self::Weightless,
            Some(g) => Self::loaded(g).map_err(|e| e.to_string())?,
        };
        let Some(g) = given else {
            return Ok(own);
        };
        let same = own
            .gravity_in_clamp()
            .is_some_and(|t| t.iter().zip(&g).all(|(a, b)| (a - b).abs() <= 1e-9));
        if same {
            Ok(own)
        } else {
            Err(format!(
                "gravity in the clamp frame {},{},{} m/s² conflicts with the calibration, whose \
                 labels were made with the {trained} model: leave the gravity out to use the \
                 calibration's model, or calibrate again with this one",
                g[0], g[1], g[2]
            ))
        }
    }

    /// Gravity in the base clamp frame \[m/s²\], if the model is loaded.
    pub fn gravity_in_clamp(&self) -> Option<[f64; 3]> {
        match self {
            Self::Weightless => None,
            Self::Loaded { gravity_in_clamp } => Some(*gravity_in_clamp),
        }
    }

    /// The model of `wire` this choice names.
    ///
    /// # Errors
    /// [`RigError::Setting`] when the wire's density, radius or rest curvature cannot make a
    /// load (not finite, not positive), or the gravity is outside what
    /// [`WireModelChoice::loaded`] allows.
    pub fn model(&self, wire: &WireBody) -> Result<KirchhoffModel, RigError> {
        let model = KirchhoffModel::new(wire.params);
        match self {
            Self::Weightless => Ok(model),
            Self::Loaded { gravity_in_clamp } => {
                Self::loaded(*gravity_in_clamp)?;
                let load = Load::from_gravity(
                    wire.density,
                    wire.params.radius(),
                    Vector3::from(*gravity_in_clamp),
                )
                .and_then(|load| load.with_natural_curvature(wire.natural_curvature))
                .map_err(|e| RigError::Setting(format!("the loaded model of the wire: {e}")))?;
                Ok(model.with_load(load))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ftwire_estimate::WireModel;

    fn body() -> WireBody {
        WireBody {
            params: WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid"),
            density: 6450.0,
            natural_curvature: Vector3::zeros(),
        }
    }

    #[test]
    fn the_loaded_model_carries_the_wires_weight_in_the_clamp_frame() {
        let choice = WireModelChoice::loaded([0.0, 0.0, -9.81]).expect("valid");
        let model = choice.model(&body()).expect("a model");
        let w = model.weight_per_length();
        let expected = 6450.0 * std::f64::consts::PI * 1e-6 * 9.81;
        assert!(
            (w.z + expected).abs() < 1e-12 && w.x == 0.0 && w.y == 0.0,
            "{w}"
        );
        let weightless = WireModelChoice::Weightless.model(&body()).expect("a model");
        assert_eq!(weightless.weight_per_length(), Vector3::zeros());
    }

    #[test]
    fn gravity_outside_its_range_is_refused_naming_the_value() {
        for bad in [[0.0; 3], [f64::NAN, 0.0, 0.0], [0.0, 0.0, 1e308]] {
            let error = WireModelChoice::loaded(bad).expect_err("refused");
            assert!(error.to_string().contains("m/s²"), "{error}");
        }
    }

    #[test]
    fn the_choice_reads_and_writes_as_kind_and_gravity() {
        let loaded = WireModelChoice::loaded([0.0, -9.81, 0.0]).expect("valid");
        let json = serde_json::to_string(&loaded).expect("serialises");
        assert_eq!(
            json,
            r#"{"kind":"loaded","gravity_in_clamp":[0.0,-9.81,0.0]}"#
        );
        let back: WireModelChoice = serde_json::from_str(&json).expect("reads back");
        assert_eq!(back, loaded);
        let json = serde_json::to_string(&WireModelChoice::Weightless).expect("serialises");
        assert_eq!(json, r#"{"kind":"weightless"}"#);
    }

    #[test]
    fn a_calibrations_model_is_used_and_a_conflicting_gravity_refused() {
        let weightless = LabelModel::WEIGHTLESS;
        let loaded = LabelModel::loaded([0.0, 0.0, -9.81]).expect("valid");
        assert_eq!(
            WireModelChoice::of_calibration(&weightless, None),
            Ok(WireModelChoice::Weightless)
        );
        assert_eq!(
            WireModelChoice::of_calibration(&loaded, None),
            WireModelChoice::loaded([0.0, 0.0, -9.81]).map_err(|e| e.to_string())
        );
        assert!(WireModelChoice::of_calibration(&loaded, Some([0.0, 0.0, -9.81])).is_ok());
        for (trained, given) in [(loaded, [0.0, -9.81, 0.0]), (weightless, [0.0, 0.0, -9.81])] {
            let error =
                WireModelChoice::of_calibration(&trained, Some(given)).expect_err("refused");
            let named = format!("{},{},{}", given[0], given[1], given[2]);
            assert!(
                error.contains(&named) && error.contains(&trained.to_string()),
                "{error}"
            );
        }
    }
}
