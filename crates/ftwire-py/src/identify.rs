//! `ftwire.identify(a, b, ...)`: a wire's stiffnesses and length from `(ã, b̃)` samples
//! (paper §III-B), the identification `ftwire identify --log` runs, with its seed.

use std::f64::consts::PI;
use std::path::PathBuf;

use ftwire_estimate::identify::Sample;
use ftwire_lab::identify::{Form, ResidualParams};
use ftwire_lab::log::identify::{EstimateReport, IdentifyLogParams, LogDrift, estimate};
use numpy::PyArray2;
use numpy::ndarray::Array2;
use pyo3::prelude::*;

use crate::error::lab_error;
use crate::input::{self, value_error};
use crate::pose;
use crate::wire::{DEFAULT_DENSITY, DEFAULT_RADIUS, Wire};

/// The answer of `identify`: the identified wire, first-order standard deviations and the
/// verdict. Immutable.
#[pyclass(module = "ftwire", frozen, get_all)]
pub struct Identification {
    /// The identified Wire (c, length; radius, density and natural curvature from
    /// wire_guess, the density from the identified linear density when gravity was given).
    wire: Wire,
    /// (c1, c2, c3) [N·m²].
    c: (f64, f64, f64),
    /// Length L [m].
    length: f64,
    /// Standard deviations of c [N·m²] (first order, from the residual's Jacobian).
    c_std: (f64, f64, f64),
    /// Standard deviation of L [m].
    length_std: f64,
    /// The linear density λ [kg/m] (with gravity), else None.
    linear_density: Option<f64>,
    /// Standard deviation of λ [kg/m] (with gravity), else None.
    linear_density_std: Option<f64>,
    /// The first-order covariance of (c1, c2, c3, L), then λ with gravity: a (4, 4) or (5, 5)
    /// float64 array [N·m², m, kg/m products], Σ_η = G s² (JᵀJ)⁻¹ Gᵀ; None where the fit's
    /// information matrix is singular.
    covariance: Py<PyAny>,
    /// The 95 % interval [low, high] of each parameter in the covariance's order,
    /// value ± 1.959964 σ: a (4, 2) or (5, 2) float64 array; None without a covariance.
    interval95: Py<PyAny>,
    /// χ² per degree of freedom under the assumed noise.
    chi2_per_dof: f64,
    /// σ_min / σ_max of the residual's Jacobian.
    condition: f64,
    /// Whether the data identify the wire.
    identified: bool,
    /// Why not, as a short name ("ill_conditioned", "residual_above_noise", "at_bound",
    /// ...), or None.
    flag: Option<&'static str>,
    /// Why not, in words, or None.
    reason: Option<String>,
    /// Samples used.
    samples: usize,
}

#[pymethods]
impl Identification {
    fn __repr__(&self) -> String {
        format!(
            "Identification(c={:?}, length={:?}, identified={}, samples={})",
            self.c,
            self.length,
            if self.identified { "True" } else { "False" },
            self.samples
        )
    }
}

/// Identifies a wire's (c1, c2, c3, L) from samples (the paper's §III-B; `ftwire identify`).
///
/// - a: (N, 6) ã, the calibrated configurations, torque first [N·m, N], base clamp frame.
/// - b: (N, 4, 4), (N, 6) or (N, 7): the second gripper's clamp pose in the base clamp frame
///   at each sample (homogeneous matrix; position [m] + rotation vector [rad]; position [m] +
///   unit quaternion (x, y, z, w)).
/// - wire_guess: a Wire whose radius, density and natural curvature the answer keeps (the
///   search over c and L is global); None: radius 0.001 m, density 6450 kg/m³.
/// - form: "absolute" (default), "eq12", "midpoint" or "relative": the residual minimised.
/// - isotropic: c3 = c2 (a round cross-section).
/// - torsion_ratio: a known ν = c1/c2; None: identified.
/// - gravity: (3,) [m/s²] in the base clamp frame: the loaded model, identifying the linear
///   density too; None: the weightless model.
/// - seed: the particle swarm's seed: the same seed gives the same answer.
/// - sensor: the F/T sensor's data sheet, a preset name ("distorted", "undistorted",
///   "real-like") or a sensor TOML file (`noise_std`, `bias_random_walk`, `bias_time_constant`,
///   its clamp's place): the bias every sample shares (the tare's offset and its drift) is
///   modelled and estimated with the wire, as `ftwire identify --log --sensor`; None: the
///   samples' errors are independent.
/// - times: (N,) each sample's time [s] (any clock; needed with sensor).
/// - tare_time: when the sensor was tared, on the same clock [s]; None: the first sample's.
/// - rest_samples, tare_samples: F/T readings averaged per sample and by the tare.
/// - pose_noise_deg, pose_noise_mm: the robot's repeatability at the rests, per axis [°, mm];
///   None: 0.05° and 0.1 mm.
/// - gain_error: the calibration's accuracy [%]: a relative error of each channel of ã that
///   every sample shares, estimated with the wire (`--gain-error`); None: 0.
/// - model_floor: the wire model's own error against the wire [% of each parameter], added to
///   every parameter's variance: no number of samples lowers it (`--model-floor`); None: 0.
///
/// Releases the GIL. Raises ValueError naming the argument for bad input (shapes, values,
/// too few samples or too little motion); RuntimeError when the search has no answer.
#[pyfunction]
#[pyo3(signature = (a, b, wire_guess = None, form = "absolute", isotropic = false, torsion_ratio = None, gravity = None, seed = 0, sensor = None, times = None, tare_time = None, rest_samples = 400, tare_samples = 500, pose_noise_deg = None, pose_noise_mm = None, gain_error = None, model_floor = None))]
#[allow(clippy::too_many_arguments)]
pub fn identify(
    py: Python<'_>,
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    wire_guess: Option<&Wire>,
    form: &str,
    isotropic: bool,
    torsion_ratio: Option<f64>,
    gravity: Option<&Bound<'_, PyAny>>,
    seed: u64,
    sensor: Option<&str>,
    times: Option<Vec<f64>>,
    tare_time: Option<f64>,
    rest_samples: usize,
    tare_samples: usize,
    pose_noise_deg: Option<f64>,
    pose_noise_mm: Option<f64>,
    gain_error: Option<f64>,
    model_floor: Option<f64>,
) -> PyResult<Identification> {
    let rows = input::rows(
        a,
        "a",
        6,
        "configurations ã (τ1, τ2, τ3, f1, f2, f3) [N·m, N]",
    )?;
    if !rows.batched {
        return Err(value_error(
            "a has shape (6,); allowed is (N, 6): N samples",
        ));
    }
    let a = input::vectors6(&rows);
    let b = pose::poses(b, "b")?;
    if a.len() != b.len() {
        return Err(value_error(format!(
            "b has {} poses and a {} configurations: one pose per configuration",
            b.len(),
            a.len()
        )));
    }
    let form = match form {
        "absolute" => Form::Absolute,
        "eq12" => Form::Eq12,
        "midpoint" => Form::Midpoint,
        "relative" => Form::Relative,
        other => {
            return Err(value_error(format!(
                "form = {other:?} is not allowed: \"absolute\", \"eq12\", \"midpoint\" or \
                 \"relative\""
            )));
        }
    };
    if let Some(nu) = torsion_ratio {
        input::positive(nu, "torsion_ratio", "c1/c2")?;
    }
    let gravity = input::vector3(
        gravity,
        "gravity",
        "the gravity vector [m/s²], base clamp frame",
    )?;
    let params = IdentifyLogParams {
        log: PathBuf::from("<arrays>"),
        calibration: None,
        mounting: None,
        samples: None,
        residual: ResidualParams {
            form,
            isotropic,
            torsion_ratio,
            pose_noise: (pose_noise_deg.is_some() || pose_noise_mm.is_some()).then(|| {
                let defaults = ftwire_estimate::identify::MeasurementNoise::default();
                [
                    pose_noise_deg.map_or(defaults.rotation, f64::to_radians),
                    pose_noise_mm.map_or(defaults.translation, |mm| 1e-3 * mm),
                ]
            }),
            gain_error: gain_error.map(|pct| 1e-2 * pct),
            model_floor: model_floor.map(|pct| 1e-2 * pct),
        },
        gravity,
        seed,
        drift: drift(
            sensor,
            times.is_some(),
            tare_time,
            (rest_samples, tare_samples),
        )?,
        front_end: ftwire_lab::error::FrontEnd::Python,
    };
    params.check().map_err(|e| lab_error(&e, "identify"))?;
    let times = sample_times(times, a.len())?;
    let samples: Vec<Sample> = a
        .into_iter()
        .zip(b)
        .zip(times)
        .map(|((a, b), time)| Sample { a, b, time })
        .collect();
    // Ctrl-C ends the search's wait (`KeyboardInterrupt`): the particle swarm of a long log
    // runs for minutes.
    let report: EstimateReport = crate::interrupt::interruptible(py, move || {
        estimate(&params, &samples, &mut |_: &str| {})
    })?
    .map_err(|e| lab_error(&e, "identify"))?;
    let guess = wire_guess.map(|w| w.spec.clone());
    let mut spec = guess.unwrap_or_else(|| ftwire_lab::wire::WireSpec {
        name: "identified".to_owned(),
        c: report.c,
        length: report.length,
        radius: DEFAULT_RADIUS,
        density: DEFAULT_DENSITY,
        natural_curvature: [0.0; 3],
    });
    spec.c = report.c;
    spec.length = report.length;
    if let Some(lambda) = report.linear_density {
        spec.density = lambda / (PI * spec.radius * spec.radius);
    }
    let wire = Wire::from_spec(spec).map_err(|e| {
        value_error(format!(
            "identify: the estimate is not a valid wire ({e}); see its flag and reason"
        ))
    })?;
    let [c1, c2, c3] = report.c;
    let [s1, s2, s3] = report.c_std;
    Ok(Identification {
        wire,
        c: (c1, c2, c3),
        length: report.length,
        c_std: (s1, s2, s3),
        length_std: report.length_std,
        linear_density: report.linear_density,
        linear_density_std: report.linear_density_std,
        covariance: matrix_or_none(py, report.covariance.as_deref())?,
        interval95: intervals_or_none(py, report.interval95.as_deref())?,
        chi2_per_dof: report.chi2_per_dof,
        condition: report.condition,
        identified: report.identified,
        flag: report.flag,
        reason: report.reason,
        samples: report.samples,
    })
}

/// `rows` (square) as a float64 array, or `None`.
fn matrix_or_none(py: Python<'_>, rows: Option<&[Vec<f64>]>) -> PyResult<Py<PyAny>> {
    let Some(rows) = rows else {
        return Ok(py.None());
    };
    let n = rows.len();
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    let array = Array2::from_shape_vec((n, flat.len() / n.max(1)), flat)
        .map_err(|e| value_error(format!("covariance: {e}")))?;
    Ok(PyArray2::from_owned_array(py, array).into_any().unbind())
}

/// `[low, high]` rows as an (N, 2) float64 array, or `None`.
fn intervals_or_none(py: Python<'_>, rows: Option<&[[f64; 2]]>) -> PyResult<Py<PyAny>> {
    let Some(rows) = rows else {
        return Ok(py.None());
    };
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    let array = Array2::from_shape_vec((rows.len(), 2), flat)
        .map_err(|e| value_error(format!("interval95: {e}")))?;
    Ok(PyArray2::from_owned_array(py, array).into_any().unbind())
}

/// The log command's drift settings from the keyword arguments (`None` without a sensor).
fn drift(
    sensor: Option<&str>,
    timed: bool,
    tare_time: Option<f64>,
    (rest_samples, tare_samples): (usize, usize),
) -> PyResult<Option<LogDrift>> {
    let Some(given) = sensor else {
        return Ok(None);
    };
    if !timed {
        return Err(value_error(
            "sensor is given without times: the drift is counted from each sample's time",
        ));
    }
    for (name, n) in [
        ("rest_samples", rest_samples),
        ("tare_samples", tare_samples),
    ] {
        if n == 0 {
            return Err(value_error(format!(
                "{name} = 0; allowed: at least 1 reading"
            )));
        }
    }
    if let Some(t) = tare_time.filter(|t| !t.is_finite()) {
        return Err(value_error(format!(
            "tare_time = {t}; allowed: finite seconds"
        )));
    }
    let spec = ftwire_lab::config::sensor::DataSheetSpec::load(given)
        .map_err(|e| value_error(format!("sensor: {e}")))?;
    Ok(Some(LogDrift {
        sensor: given.to_owned(),
        params: spec.sheet,
        rest_samples,
        tare_samples,
        tare_time,
    }))
}

/// Each sample's time from `times` (one finite time per configuration of `n`), or `None`s.
fn sample_times(times: Option<Vec<f64>>, n: usize) -> PyResult<Vec<Option<f64>>> {
    match times {
        Some(t) if t.len() != n => Err(value_error(format!(
            "times has {} entries and a {n} configurations: one time per sample",
            t.len()
        ))),
        Some(t) => {
            if let Some(bad) = t.iter().find(|v| !v.is_finite()) {
                return Err(value_error(format!(
                    "times holds {bad}; allowed: finite seconds"
                )));
            }
            Ok(t.into_iter().map(Some).collect())
        }
        None => Ok(vec![None; n]),
    }
}
