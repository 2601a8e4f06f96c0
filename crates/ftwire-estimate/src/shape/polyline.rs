//! Geometry of a centreline given as a polyline: closest point, arc length, resampling.
//!
//! Pure functions (as parry's queries), used by the closest-point shape fit and the metrics.

use nalgebra::Vector3;

use crate::EstimateError;

/// The closest point of a polyline to a query point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosestPoint {
    /// The closest point \[m\].
    pub point: Vector3<f64>,
    /// Its distance to the query point \[m\].
    pub distance: f64,
    /// Its arc length along the polyline from the first vertex \[m\].
    pub arc_length: f64,
    /// The segment it lies on (from vertex `segment` to `segment + 1`; 0 for a single point).
    pub segment: usize,
    /// Its place on that segment, in `[0, 1]`.
    pub parameter: f64,
}

/// Checks that a polyline has at least `min` points, all finite.
pub(crate) fn validate_points(
    name: &'static str,
    points: &[Vector3<f64>],
    min: usize,
) -> Result<(), EstimateError> {
    if points.len() < min {
        return Err(EstimateError::TooFewPolylinePoints {
            name,
            points: points.len(),
            min,
        });
    }
    for (index, point) in points.iter().enumerate() {
        if let Some((axis, &value)) = point.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(EstimateError::NonFinitePoint {
                name,
                index,
                axis,
                value,
            });
        }
    }
    Ok(())
}

/// Cumulative chord length at each vertex \[m\] (0 at the first). Empty for an empty polyline.
pub fn cumulative_length(polyline: &[Vector3<f64>]) -> Vec<f64> {
    let mut total = 0.0;
    let mut lengths = Vec::with_capacity(polyline.len());
    let mut previous = polyline.first();
    for point in polyline {
        if let Some(p) = previous {
            total += (point - p).norm();
        }
        lengths.push(total);
        previous = Some(point);
    }
    lengths
}

/// The closest point of `polyline` to `query` (exact on the segments), or `None` for an empty
/// polyline. Ties go to the earlier segment.
///
/// # Example
/// ```
/// use ftwire_estimate::shape::closest_point;
/// use nalgebra::Vector3;
/// let l = [Vector3::zeros(), Vector3::x(), Vector3::new(1.0, 1.0, 0.0)];
/// let c = closest_point(&l, &Vector3::new(2.0, 0.5, 0.0)).ok_or("empty")?;
/// assert!((c.distance - 1.0).abs() < 1e-15);
/// assert!((c.arc_length - 1.5).abs() < 1e-15);
/// # Ok::<(), &str>(())
/// ```
pub fn closest_point(polyline: &[Vector3<f64>], query: &Vector3<f64>) -> Option<ClosestPoint> {
    let first = polyline.first()?;
    let mut best = ClosestPoint {
        point: *first,
        distance: (query - first).norm(),
        arc_length: 0.0,
        segment: 0,
        parameter: 0.0,
    };
    let mut start_length = 0.0;
    for (segment, pair) in polyline.windows(2).enumerate() {
        let [p, q] = pair else { continue };
        let d = q - p;
        let length_sq = d.norm_squared();
        let u = if length_sq > 0.0 {
            ((query - p).dot(&d) / length_sq).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let point = p + u * d;
        let distance = (query - point).norm();
        let length = length_sq.sqrt();
        if distance < best.distance {
            best = ClosestPoint {
                point,
                distance,
                arc_length: start_length + u * length,
                segment,
                parameter: u,
            };
        }
        start_length += length;
    }
    Some(best)
}

/// The distance of `query` to `polyline`: bit for bit [`closest_point`]'s `distance`, without
/// the point, arc length and segment, and without a square root per segment (the squared
/// distances are compared, and `‖v‖ = √(‖v‖²)` is monotone). `None` for an empty polyline.
/// The marker metric's inner loop; guarded by `the_distance_is_the_closest_points`.
pub(crate) fn closest_distance(polyline: &[Vector3<f64>], query: &Vector3<f64>) -> Option<f64> {
    let first = polyline.first()?;
    let mut best = (query - first).norm_squared();
    for pair in polyline.windows(2) {
        let [p, q] = pair else { continue };
        let d = q - p;
        let length_sq = d.norm_squared();
        let u = if length_sq > 0.0 {
            ((query - p).dot(&d) / length_sq).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let squared = (query - (p + u * d)).norm_squared();
        if squared < best {
            best = squared;
        }
    }
    Some(best.sqrt())
}

/// The polyline resampled at `samples` points evenly spaced in its own chord length, both ends
/// included (linear interpolation). Needs at least 2 points and `samples ≥ 2`.
pub(crate) fn resample(polyline: &[Vector3<f64>], samples: usize) -> Vec<Vector3<f64>> {
    let lengths = cumulative_length(polyline);
    let total = lengths.last().copied().unwrap_or(0.0);
    let mut out = Vec::with_capacity(samples);
    let mut segment = 0;
    let last = samples.saturating_sub(1).max(1) as f64;
    for i in 0..samples {
        let target = total * i as f64 / last;
        while segment + 2 < lengths.len() && lengths.get(segment + 1).is_some_and(|&l| l < target) {
            segment += 1;
        }
        let (Some(p), Some(q), Some(&l0), Some(&l1)) = (
            polyline.get(segment),
            polyline.get(segment + 1),
            lengths.get(segment),
            lengths.get(segment + 1),
        ) else {
            break;
        };
        let u = if l1 > l0 {
            ((target - l0) / (l1 - l0)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(p + u * (q - p));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn closest_point_on_an_l_shape() {
        let l = [
            Vector3::zeros(),
            Vector3::new(2.0, 0.0, 0.0),
            Vector3::new(2.0, 2.0, 0.0),
        ];
        let above = closest_point(&l, &Vector3::new(1.0, 0.5, 3.0));
        assert!(
            above.is_some_and(|c| (c.distance - 9.25_f64.sqrt()).abs() < 1e-15
                && (c.arc_length - 1.0).abs() < 1e-15)
        );
        let c = closest_point(&l, &Vector3::new(1.0, 0.5, 0.0));
        assert!(c.is_some_and(
            |c| (c.distance - 0.5).abs() < 1e-15 && (c.arc_length - 1.0).abs() < 1e-15
        ));
        let beyond = closest_point(&l, &Vector3::new(2.0, 5.0, 0.0));
        assert!(beyond.is_some_and(
            |c| (c.distance - 3.0).abs() < 1e-15 && (c.arc_length - 4.0).abs() < 1e-15
        ));
        assert!(closest_point(&[], &Vector3::zeros()).is_none());
    }

    /// Bit for bit the closest point's distance, on random polylines with repeated vertices.
    #[test]
    fn the_distance_is_the_closest_points() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let mut random = |scale: f64| {
            Vector3::new(
                rng.random_range(-scale..scale),
                rng.random_range(-scale..scale),
                rng.random_range(-scale..scale),
            )
        };
        for n in [1, 2, 3, 17, 100] {
            let mut polyline: Vec<Vector3<f64>> = (0..n).map(|_| random(0.5)).collect();
            if n > 3 {
                polyline[2] = polyline[1];
            }
            for _ in 0..200 {
                let query = random(0.7);
                let fast = closest_distance(&polyline, &query).map(f64::to_bits);
                let full = closest_point(&polyline, &query).map(|c| c.distance.to_bits());
                assert_eq!(fast, full, "{n} points, query {query:?}");
            }
        }
        assert!(closest_distance(&[], &Vector3::zeros()).is_none());
    }

    #[test]
    fn resampling_keeps_the_ends_and_spacing() {
        let l = [
            Vector3::zeros(),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(1.0, 3.0, 0.0),
        ];
        let r = resample(&l, 5);
        assert_eq!(r.len(), 5);
        assert_relative_eq!(r[0], l[0]);
        assert_relative_eq!(r[1], Vector3::new(1.0, 0.0, 0.0));
        assert_relative_eq!(r[2], Vector3::new(1.0, 1.0, 0.0));
        assert_relative_eq!(r[4], l[2]);
    }
}
