//! How a wire is identified, by the experiments and by `identify --log` alike, so that both
//! give the same answer on the same data and seed: the residual form and the known relations
//! ([`ResidualParams`]), the error of `ã` from a sensor's data sheet ([`data_sheet_noise`]),
//! the model template, the swarm's random generator and the estimate's flag name.

use ftwire_app::error::{LabError, from_estimate};
use ftwire_core::WireParams;
use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::identify::{
    Estimate, Identifier, IdentifierParams, MeasurementNoise, ParameterConstraints, ResidualForm,
    Sample, Unidentified, identify_samples,
};
use ftwire_rig::DataSheet;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

/// The residual identification minimises (`ftwire_estimate::identify::ResidualForm`), by the
/// names the summaries use.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Form {
    /// The exact absolute form `log(Γ_η(ã_i)⁻¹ b̃_i)`: reaches the noise floor.
    #[default]
    Absolute,
    /// The paper's eq. 12, `J_η(ã_i) δã_i − δb̃_i`: limited to 2–3 % by its linearisation.
    Eq12,
    /// Eq. 12 with `J` at the midpoint of each step.
    Midpoint,
    /// Exact relative poses of consecutive samples.
    Relative,
}

impl Form {
    /// The library's residual form.
    pub fn residual(self) -> ResidualForm {
        match self {
            Self::Absolute => ResidualForm::Absolute,
            Self::Eq12 => ResidualForm::Eq12,
            Self::Midpoint => ResidualForm::Midpoint,
            Self::Relative => ResidualForm::Relative,
        }
    }
}

/// How to identify: the residual form and the known relations between the parameters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct ResidualParams {
    /// The residual minimised (default [`Form::Absolute`]).
    pub form: Form,
    /// Isotropic bending, `c3 = c2` (a wire of round cross-section).
    pub isotropic: bool,
    /// A known torsion ratio `ν = c1/c2` (a round rod: `1/(1 + Poisson's ratio)`); `None`:
    /// identified.
    pub torsion_ratio: Option<f64>,
    /// The standard deviation of the pose `b̃` per axis, rotation \[rad\] and translation
    /// \[m\]: the robot's repeatability at the rests, as the fit weights it and as its
    /// covariance counts it; `None`: the library's default (0.05°, 0.1 mm).
    pub pose_noise: Option<[f64; 2]>,
    /// The relative error of each channel of `ã` that every sample shares (a calibration's
    /// gain error), as a fraction ([`MeasurementNoise::gain`]); `None`: the command's default.
    pub gain_error: Option<f64>,
    /// The wire model's own relative error in each parameter, as a fraction
    /// ([`IdentifierParams::model_error`]); `None`: the command's default.
    pub model_floor: Option<f64>,
}

impl ResidualParams {
    /// [`Self::pose_noise`] of a pose noise given in part, `rotation` \[rad\] or
    /// `translation` \[m\]: the half not given is the library's default
    /// ([`MeasurementNoise::default`]); `None` when neither is given.
    ///
    /// # Example
    /// ```
    /// use ftwire_logs::identification::ResidualParams;
    /// let default = ftwire_estimate::identify::MeasurementNoise::default();
    /// assert_eq!(ResidualParams::pose_noise_of(None, None), None);
    /// assert_eq!(
    ///     ResidualParams::pose_noise_of(None, Some(2e-4)),
    ///     Some([default.rotation, 2e-4])
    /// );
    /// ```
    pub fn pose_noise_of(rotation: Option<f64>, translation: Option<f64>) -> Option<[f64; 2]> {
        let defaults = MeasurementNoise::default();
        (rotation.is_some() || translation.is_some()).then(|| {
            [
                rotation.unwrap_or(defaults.rotation),
                translation.unwrap_or(defaults.translation),
            ]
        })
    }

    /// The library's settings: its defaults with these applied.
    ///
    /// # Errors
    /// Bad input (exit 2) for a torsion ratio that is not positive.
    pub fn config(&self) -> Result<IdentifierParams, LabError> {
        let mut config = IdentifierParams {
            form: self.form.residual(),
            constraints: ParameterConstraints {
                isotropic: self.isotropic,
                torsion_ratio: self.torsion_ratio,
                stiffness_per_length: false,
                weight: None,
            },
            ..IdentifierParams::default()
        };
        config
            .validate()
            .map_err(|e| LabError::bad_input(format!("--torsion-ratio: {e}")))?;
        config.noise = self.with_noise_settings(config.noise)?;
        self.with_model_floor(&mut config, 0.0)?;
        Ok(config)
    }

    /// Sets `config`'s model error to [`Self::model_floor`], or to `default` when not given.
    ///
    /// # Errors
    /// Bad input (exit 2) naming a model floor outside `[0, 100)` %.
    pub fn with_model_floor(
        &self,
        config: &mut IdentifierParams,
        default: f64,
    ) -> Result<(), LabError> {
        let floor = self.model_floor.unwrap_or(default);
        if !(floor.is_finite() && (0.0..1.0).contains(&floor)) {
            return Err(LabError::bad_input(format!(
                "--model-floor {}: give a percentage from 0 to below 100",
                1e2 * floor
            )));
        }
        config.model_error = floor;
        Ok(())
    }

    /// `noise` with [`Self::pose_noise`] and [`Self::gain_error`] in place of its own, where
    /// given.
    ///
    /// # Errors
    /// Bad input (exit 2) naming a pose noise that is not finite and positive, or a gain error
    /// outside `[0, 100)` %.
    pub fn with_noise_settings(
        &self,
        noise: MeasurementNoise,
    ) -> Result<MeasurementNoise, LabError> {
        let mut noise = noise;
        if let Some(gain) = self.gain_error {
            if !(gain.is_finite() && (0.0..1.0).contains(&gain)) {
                return Err(LabError::bad_input(format!(
                    "--gain-error {}: give a percentage from 0 to below 100",
                    1e2 * gain
                )));
            }
            noise.gain = gain;
            noise.torque_gain = None;
        }
        let Some([rotation, translation]) = self.pose_noise else {
            return Ok(noise);
        };
        for (option, value, unit) in [
            ("--pose-noise-deg", rotation.to_degrees(), "degrees"),
            ("--pose-noise-mm", 1e3 * translation, "mm"),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(LabError::bad_input(format!(
                    "{option} {value}: give a finite standard deviation > 0 [{unit}]"
                )));
            }
        }
        Ok(MeasurementNoise {
            rotation,
            translation,
            ..noise
        })
    }
}

/// The error of `ã` of the sensor's data sheet `sensor` ([`DataSheet::noise`]) with the map's
/// relative gain error `gain` of every channel (a fraction; `None`: none): what a rig's log or
/// a node draws its error bars and intervals from.
///
/// # Errors
/// Bad input naming `--sensor` for a drift that is not valid, or `--gain-error` outside
/// `[0, 100)` %.
pub fn data_sheet_noise(
    sensor: &DataSheet,
    mount: &ftwire_estimate::ft::Mounting,
    (rest_samples, tare_samples): (usize, usize),
    gain: Option<f64>,
) -> Result<MeasurementNoise, LabError> {
    let noise = sensor
        .noise(mount, rest_samples, tare_samples)
        .map_err(|e| LabError::bad_input(format!("--sensor: {e}")))?;
    ResidualParams {
        gain_error: gain,
        ..ResidualParams::default()
    }
    .with_noise_settings(noise)
}

/// The radius of [`template_model`] \[m\]: the 2 mm wire's, which the estimate does not
/// depend on (the search replaces `c` and `L`).
pub const TEMPLATE_RADIUS: f64 = 0.001;

/// The model identification starts from. Only its radius and integrator are used (the search
/// replaces `c` and `L`). The experiments and the log command use this one template, so the
/// same data and seed give the same estimate.
///
/// # Errors
/// Never for the constants here; kept fallible for the core type's checks.
pub fn template_model() -> Result<KirchhoffModel, LabError> {
    let wire = WireParams::new([0.1, 0.1, 0.1], 1.0, TEMPLATE_RADIUS)
        .map_err(|e| LabError::bad_input(format!("the identification template: {e}")))?;
    Ok(KirchhoffModel::new(wire))
}

/// Identifies from `samples` (`(ã, b̃)` and, if known, the time since the tare) with the swarm seeded by `seed` (a fresh
/// generator per call, so an estimate depends only on its data and the seed, not on what ran
/// before).
///
/// # Errors
/// Bad input for data that cannot be identified from (too few samples, too little motion, a
/// sample outside `A`); no answer for anything else the library reports.
pub fn run_identification(
    samples: &[Sample],
    config: &IdentifierParams,
    seed: u64,
) -> Result<Estimate, LabError> {
    let model = template_model()?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    identify_samples(&model, samples, config, &mut rng)
        .map_err(|e| from_estimate(e, "identifying the wire"))
}

/// The streaming identifier of [`run_identification`] with `samples` pushed, for a caller that
/// shows progress: `step` it with a time budget until its estimate is no longer
/// `Unidentified::Unfinished`. It gives the same estimate as [`run_identification`] for the
/// same samples and seed, however the search is cut into steps.
///
/// # Errors
/// As [`run_identification`].
pub fn identifier(
    samples: &[Sample],
    config: &IdentifierParams,
    seed: u64,
) -> Result<Identifier<KirchhoffModel, ChaCha8Rng>, LabError> {
    let failed = |e| from_estimate(e, "identifying the wire");
    let rng = ChaCha8Rng::seed_from_u64(seed);
    let mut identifier = Identifier::new(template_model()?, config.clone(), rng).map_err(failed)?;
    for sample in samples {
        identifier.push_sample(*sample).map_err(failed)?;
    }
    Ok(identifier)
}

/// A short machine-readable name of why an estimate is not trusted (`None`: identified).
pub fn flag_name(reason: Option<&Unidentified>) -> Option<&'static str> {
    reason.map(|reason| match reason {
        Unidentified::IllConditioned { .. } => "ill_conditioned",
        Unidentified::ResidualAboveNoise { .. } => "residual_above_noise",
        Unidentified::AtBound { .. } => "at_bound",
        Unidentified::Unfinished { .. } => "unfinished",
        _ => "unidentified",
    })
}
