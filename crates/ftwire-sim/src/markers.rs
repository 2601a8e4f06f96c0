//! Motion capture: fiducial markers at fixed arc lengths along the wire.
//!
//! The paper places `V = 11` markers along the wire and reads them with a motion-capture system
//! as ground truth of the shape (Mishani & Sintov, §IV). This model puts markers at fixed
//! fractions of the arc length, interpolates the simulated centreline linearly in arc length,
//! adds isotropic Gaussian noise and drops markers now and then, as occlusions do.

use ftwire_core::ensure_finite;
use nalgebra::{Point3, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

use crate::sensor::{SensingError, all_in_range, in_range};

/// Number of markers of the default configuration, as in the paper.
pub const DEFAULT_MARKER_COUNT: usize = 11;

/// Parameters of the motion-capture model.
///
/// # Example
/// ```
/// use ftwire_sim::MarkerParams;
///
/// let config = MarkerParams::default();
/// assert_eq!(config.fractions.len(), 11);
/// assert!((config.fractions[5] - 0.5).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MarkerParams {
    /// Marker positions as fractions `s / L` of the wire length, each in `[0, 1]` (default: 11
    /// evenly spaced, `0, 0.1, …, 1`, both ends included, so that the markers span the whole
    /// wire as the paper's do).
    pub fractions: Vec<f64>,
    /// Measurement noise σ per axis, world frame \[m\] (default `0.0003`, 0.3 mm).
    pub noise_std: f64,
    /// Probability that a marker is missing from a frame, independently per marker and frame,
    /// in `[0, 1]` (default `0.02`).
    pub dropout_probability: f64,
}

impl Default for MarkerParams {
    fn default() -> Self {
        let last = (DEFAULT_MARKER_COUNT - 1) as f64;
        Self {
            fractions: (0..DEFAULT_MARKER_COUNT).map(|i| i as f64 / last).collect(),
            noise_std: 3e-4,
            dropout_probability: 0.02,
        }
    }
}

impl MarkerParams {
    /// Markers at the default positions without noise or dropouts.
    ///
    /// # Example
    /// ```
    /// let ideal = ftwire_sim::MarkerParams::ideal();
    /// assert_eq!(ideal.noise_std, 0.0);
    /// assert_eq!(ideal.dropout_probability, 0.0);
    /// ```
    #[must_use]
    pub fn ideal() -> Self {
        Self {
            noise_std: 0.0,
            dropout_probability: 0.0,
            ..Self::default()
        }
    }

    fn validate(&self) -> Result<(), SensingError> {
        all_in_range("fractions", &self.fractions, 0.0, 1.0)?;
        in_range("noise_std", 0, self.noise_std, 0.0, f64::MAX)?;
        in_range("dropout_probability", 0, self.dropout_probability, 0.0, 1.0)
    }
}

/// One motion-capture frame.
#[derive(Debug, Clone, PartialEq)]
pub struct MarkerFrame {
    /// Time of the frame \[s\].
    pub time: f64,
    /// Measured marker positions, world frame \[m\], in the order of
    /// [`MarkerParams::fractions`]; `None` for a marker that dropped out.
    pub positions: Vec<Option<Point3<f64>>>,
}

/// The motion-capture system: a validated [`MarkerParams`] and its own seeded random number
/// generator. Same configuration, seed and calls give the same frames.
#[derive(Debug, Clone)]
pub struct MotionCapture {
    config: MarkerParams,
    rng: ChaCha8Rng,
}

impl MotionCapture {
    /// Builds the motion-capture model from a configuration and a seed.
    ///
    /// # Errors
    /// [`SensingError::OutOfRange`] naming a fraction outside `[0, 1]`, a negative or non-finite
    /// noise σ, or a dropout probability outside `[0, 1]`.
    ///
    /// # Example
    /// ```
    /// use ftwire_sim::{MarkerParams, MotionCapture};
    ///
    /// assert!(MotionCapture::new(MarkerParams::default(), 1).is_ok());
    /// let bad = MarkerParams { fractions: vec![0.5, 1.2], ..MarkerParams::default() };
    /// assert!(MotionCapture::new(bad, 1).is_err());
    /// ```
    pub fn new(config: MarkerParams, seed: u64) -> Result<Self, SensingError> {
        config.validate()?;
        Ok(Self {
            config,
            rng: ChaCha8Rng::seed_from_u64(seed),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &MarkerParams {
        &self.config
    }

    /// Noise-free marker positions on a centreline, world frame \[m\].
    ///
    /// `centreline` holds the node points in the world frame, `arc_lengths` the arc length
    /// \[m\] of each node, strictly increasing, and `length` the wire length `L` \[m\]; marker
    /// `i` sits at arc length `fractions[i] · L`. The arc lengths need not start at 0: a
    /// discretisation whose first and last nodes lie beyond the clamps is fine as long as
    /// `[0, L]` is covered.
    ///
    /// # Errors
    /// See [`point_at_arc_length`]; also [`SensingError::OutOfRange`] if `length` is not
    /// positive and finite.
    pub fn true_positions(
        &self,
        centreline: &[Point3<f64>],
        arc_lengths: &[f64],
        length: f64,
    ) -> Result<Vec<Point3<f64>>, SensingError> {
        in_range("length", 0, length, f64::MIN_POSITIVE, f64::MAX)?;
        validate_centreline(centreline, arc_lengths)?;
        let (first, last) = ends(arc_lengths);
        let slack = 1e-12 * (last - first).abs().max(length);
        self.config
            .fractions
            .iter()
            .enumerate()
            .map(|(marker, &fraction)| {
                let s = fraction * length;
                if s < first - slack || s > last + slack {
                    return Err(SensingError::MarkerOutsideCentreline {
                        marker,
                        arc_length: s,
                        min: first,
                        max: last,
                    });
                }
                interpolate(centreline, arc_lengths, s.clamp(first, last))
            })
            .collect()
    }

    /// A motion-capture frame at time `time` \[s\]: the marker positions of
    /// [`MotionCapture::true_positions`] with noise and dropouts.
    ///
    /// # Errors
    /// As [`MotionCapture::true_positions`], and [`SensingError::Core`] if `time` is not finite.
    ///
    /// # Example
    /// ```
    /// use ftwire_sim::{MarkerParams, MotionCapture};
    /// use nalgebra::Point3;
    ///
    /// let mut mocap = MotionCapture::new(MarkerParams::ideal(), 5)?;
    /// let line = [Point3::origin(), Point3::new(0.5, 0.0, 0.0)];
    /// let frame = mocap.observe(0.1, &line, &[0.0, 0.5], 0.5)?;
    /// let p = frame.positions[2].expect("no dropouts in the ideal configuration");
    /// assert!((p - Point3::new(0.1, 0.0, 0.0)).norm() < 1e-12);
    /// # Ok::<(), ftwire_sim::SensingError>(())
    /// ```
    pub fn observe(
        &mut self,
        time: f64,
        centreline: &[Point3<f64>],
        arc_lengths: &[f64],
        length: f64,
    ) -> Result<MarkerFrame, SensingError> {
        ensure_finite("time", &[time])?;
        let truth = self.true_positions(centreline, arc_lengths, length)?;
        let positions = truth
            .into_iter()
            .map(|p| {
                let noise = Vector3::from_fn(|_, _| self.rng.sample::<f64, _>(StandardNormal));
                let dropped = self.rng.random::<f64>() < self.config.dropout_probability;
                (!dropped).then(|| p + self.config.noise_std * noise)
            })
            .collect();
        Ok(MarkerFrame { time, positions })
    }

    /// As [`MotionCapture::observe`], for a centreline whose nodes are evenly spaced in arc
    /// length from 0 to `length`.
    ///
    /// # Errors
    /// As [`MotionCapture::observe`].
    pub fn observe_uniform(
        &mut self,
        time: f64,
        centreline: &[Point3<f64>],
        length: f64,
    ) -> Result<MarkerFrame, SensingError> {
        in_range("length", 0, length, f64::MIN_POSITIVE, f64::MAX)?;
        let arc_lengths = uniform_arc_lengths(centreline.len(), length);
        self.observe(time, centreline, &arc_lengths, length)
    }
}

/// Arc lengths `0, L/(n−1), …, L` of `n` evenly spaced nodes \[m\] (empty for `n = 0`, `[0]`
/// for `n = 1`).
///
/// # Example
/// ```
/// let s = ftwire_sim::markers::uniform_arc_lengths(3, 0.6);
/// assert_eq!(s, vec![0.0, 0.3, 0.6]);
/// ```
pub fn uniform_arc_lengths(nodes: usize, length: f64) -> Vec<f64> {
    let last = nodes.saturating_sub(1).max(1) as f64;
    (0..nodes).map(|i| i as f64 / last * length).collect()
}

/// The point at arc length `s` \[m\] on a polyline, interpolated linearly between the nodes
/// around it.
///
/// `centreline` holds at least two finite node points, `arc_lengths` one strictly increasing
/// arc length \[m\] per node, and `s` must lie within `arc_lengths`' first and last values.
///
/// # Errors
/// [`SensingError::TooFewNodes`], [`SensingError::ArcLengthCount`],
/// [`SensingError::ArcLengthsNotIncreasing`], [`SensingError::Core`] for a non-finite point or
/// arc length, [`SensingError::MarkerOutsideCentreline`] (marker index 0) if `s` lies beyond
/// the ends.
///
/// # Example
/// ```
/// use ftwire_sim::point_at_arc_length;
/// use nalgebra::Point3;
///
/// let nodes = [Point3::origin(), Point3::new(1.0, 0.0, 0.0), Point3::new(1.0, 1.0, 0.0)];
/// let p = point_at_arc_length(&nodes, &[0.0, 1.0, 2.0], 1.25)?;
/// assert!((p - Point3::new(1.0, 0.25, 0.0)).norm() < 1e-15);
/// # Ok::<(), ftwire_sim::SensingError>(())
/// ```
pub fn point_at_arc_length(
    centreline: &[Point3<f64>],
    arc_lengths: &[f64],
    s: f64,
) -> Result<Point3<f64>, SensingError> {
    validate_centreline(centreline, arc_lengths)?;
    ensure_finite("s", &[s])?;
    let (min, max) = ends(arc_lengths);
    if s < min || s > max {
        return Err(SensingError::MarkerOutsideCentreline {
            marker: 0,
            arc_length: s,
            min,
            max,
        });
    }
    interpolate(centreline, arc_lengths, s)
}

fn validate_centreline(
    centreline: &[Point3<f64>],
    arc_lengths: &[f64],
) -> Result<(), SensingError> {
    if centreline.len() < 2 {
        return Err(SensingError::TooFewNodes {
            nodes: centreline.len(),
            min: 2,
        });
    }
    if arc_lengths.len() != centreline.len() {
        return Err(SensingError::ArcLengthCount {
            nodes: centreline.len(),
            arc_lengths: arc_lengths.len(),
        });
    }
    for (index, p) in centreline.iter().enumerate() {
        if let Some(value) = p.coords.iter().copied().find(|v| !v.is_finite()) {
            return Err(ftwire_core::CoreError::NonFinite {
                field: "centreline",
                index,
                value,
            }
            .into());
        }
    }
    ensure_finite("arc_lengths", arc_lengths)?;
    for (i, pair) in arc_lengths.windows(2).enumerate() {
        if let [previous, value] = *pair
            && value <= previous
        {
            return Err(SensingError::ArcLengthsNotIncreasing {
                index: i + 1,
                previous,
                value,
            });
        }
    }
    Ok(())
}

fn ends(arc_lengths: &[f64]) -> (f64, f64) {
    (
        arc_lengths.first().copied().unwrap_or(0.0),
        arc_lengths.last().copied().unwrap_or(0.0),
    )
}

/// Linear interpolation on a validated polyline, `s` within its ends.
fn interpolate(
    centreline: &[Point3<f64>],
    arc_lengths: &[f64],
    s: f64,
) -> Result<Point3<f64>, SensingError> {
    let above = arc_lengths.partition_point(|&a| a <= s);
    let j = above
        .saturating_sub(1)
        .min(arc_lengths.len().saturating_sub(2));
    let segment = (
        centreline.get(j),
        centreline.get(j + 1),
        arc_lengths.get(j),
        arc_lengths.get(j + 1),
    );
    match segment {
        (Some(p0), Some(p1), Some(&s0), Some(&s1)) => {
            let t = (s - s0) / (s1 - s0);
            Ok(p0 + t * (p1 - p0))
        }
        _ => Err(SensingError::TooFewNodes {
            nodes: centreline.len(),
            min: 2,
        }),
    }
}
