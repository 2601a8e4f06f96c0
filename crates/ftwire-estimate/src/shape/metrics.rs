//! Shape-error metrics of the experiments (paper §IV-C, Table II, Fig. 5).
//!
//! - [`centreline_distance`]: mean distance between two centrelines at matched arc lengths (the
//!   "mean error along the wire" of Table II, when the ground-truth centreline is known).
//! - [`marker_distances`]: each marker's distance to the closest point of an estimated
//!   centreline (what the paper can measure with motion capture, Fig. 5).

use nalgebra::{Point3, Vector3};

use crate::EstimateError;
use crate::shape::polyline::{closest_distance, resample, validate_points};
use crate::shape::setting;

/// Fewest common arc lengths [`centreline_distance`] accepts.
pub const MIN_METRIC_SAMPLES: usize = 50;

/// Common arc lengths used by the experiments (default).
pub const DEFAULT_METRIC_SAMPLES: usize = 100;

/// Mean distance \[m\] between two centrelines at `samples` matched arc lengths.
///
/// Each polyline (points in one frame, from one end to the other) is resampled at `samples`
/// points evenly spaced in its own chord length, both ends included, and the `i`-th points of
/// the two are compared. Matching by fraction of each polyline's length keeps the metric fair
/// when the two lengths differ slightly (a discretised ground truth, an identified `L`).
///
/// # Errors
/// [`EstimateError::TooFewPolylinePoints`] for a polyline of fewer than 2 points,
/// [`EstimateError::NonFinitePoint`] naming a non-finite point, and
/// [`EstimateError::BadShapeSetting`] if `samples < MIN_METRIC_SAMPLES`.
///
/// # Example
/// ```
/// use ftwire_estimate::shape::centreline_distance;
/// use nalgebra::Vector3;
/// let straight: Vec<_> = (0..=10).map(|i| Vector3::new(0.1 * i as f64, 0.0, 0.0)).collect();
/// let lifted: Vec<_> = straight.iter().map(|p| p + Vector3::new(0.0, 0.0, 0.002)).collect();
/// let d = centreline_distance(&straight, &lifted, 50)?;
/// assert!((d - 0.002).abs() < 1e-12);
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
pub fn centreline_distance(
    estimate: &[Vector3<f64>],
    truth: &[Vector3<f64>],
    samples: usize,
) -> Result<f64, EstimateError> {
    validate_points("estimate", estimate, 2)?;
    validate_points("truth", truth, 2)?;
    setting::count(
        "samples",
        samples,
        MIN_METRIC_SAMPLES,
        usize::MAX,
        "at least 50 common arc lengths",
    )?;
    let a = resample(estimate, samples);
    let b = resample(truth, samples);
    let total: f64 = a.iter().zip(&b).map(|(p, q)| (p - q).norm()).sum();
    Ok(total / samples as f64)
}

/// Each marker's distance \[m\] to the closest point of `centreline` (the paper's marker
/// metric, Fig. 5), in the order of `markers`.
///
/// # Errors
/// [`EstimateError::TooFewPolylinePoints`] for a centreline of fewer than 2 points,
/// [`EstimateError::NonFinitePoint`] naming a non-finite marker or centreline point.
///
/// # Example
/// ```
/// use ftwire_estimate::shape::marker_distances;
/// use nalgebra::{Point3, Vector3};
/// let centreline = [Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0)];
/// let markers = [Point3::new(0.5, 0.003, 0.0), Point3::new(1.0, 0.0, 0.004)];
/// let d = marker_distances(&markers, &centreline)?;
/// assert!((d[0] - 0.003).abs() < 1e-15 && (d[1] - 0.004).abs() < 1e-15);
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
pub fn marker_distances(
    markers: &[Point3<f64>],
    centreline: &[Vector3<f64>],
) -> Result<Vec<f64>, EstimateError> {
    validate_points("centreline", centreline, 2)?;
    let coords: Vec<Vector3<f64>> = markers.iter().map(|p| p.coords).collect();
    validate_points("markers", &coords, 0)?;
    Ok(coords
        .iter()
        .filter_map(|p| closest_distance(centreline, p))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn matched_arc_lengths_ignore_the_sampling_of_each_polyline() -> Result<(), EstimateError> {
        // The same quarter circle sampled at 7 and at 400 points: close to zero apart, and the
        // coarse one's chord error is what remains.
        let arc = |n: usize| -> Vec<Vector3<f64>> {
            (0..n)
                .map(|i| {
                    let t = std::f64::consts::FRAC_PI_2 * i as f64 / (n - 1) as f64;
                    Vector3::new(t.sin(), 1.0 - t.cos(), 0.0)
                })
                .collect()
        };
        let d = centreline_distance(&arc(7), &arc(400), 100)?;
        assert!(d > 0.0 && d < 0.01, "{d}");
        assert_relative_eq!(centreline_distance(&arc(50), &arc(50), 50)?, 0.0);
        Ok(())
    }

    #[test]
    fn bad_inputs_are_named() {
        let line = [Vector3::zeros(), Vector3::x()];
        assert!(matches!(
            centreline_distance(&line, &line, 10),
            Err(EstimateError::BadShapeSetting {
                name: "samples",
                ..
            })
        ));
        assert!(matches!(
            centreline_distance(&line[..1], &line, 50),
            Err(EstimateError::TooFewPolylinePoints {
                name: "estimate",
                points: 1,
                min: 2
            })
        ));
        let markers = [Point3::origin(), Point3::new(0.0, f64::INFINITY, 0.0)];
        assert!(matches!(
            marker_distances(&markers, &line),
            Err(EstimateError::NonFinitePoint {
                name: "markers",
                index: 1,
                axis: 1,
                ..
            })
        ));
    }
}
