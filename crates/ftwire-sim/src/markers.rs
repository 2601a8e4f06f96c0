//! Motion capture: fiducial markers at fixed arc lengths along the wire.
//!
//! The paper places `V = 11` markers along the wire and reads them with a motion-capture system
//! as ground truth of the shape (Mishani & Sintov, §IV). This model puts markers at fixed
//! fractions of the arc length, interpolates the simulated centreline linearly in arc length,
//! adds isotropic Gaussian noise and drops markers now and then, as occlusions do.
//!
//! A real marker is a ball glued on the wire, so its centre sits off the centreline: by a
//! fixed offset per marker in the wire's cross-section, which turns with the wire as it bends
//! and twists ([`MarkerParams::mount_offset`], off by default). On a real 2 mm wire this
//! offset, not the camera's noise, is what a shape fit leaves at the markers
//! (`shared/DESIGN.md`, "Real recordings": 1.5–1.8 mm RMS). Placing the offsets needs the
//! wire's material frames ([`SectionFrames`], [`MotionCapture::observe_mounted`]).

use ftwire_core::ensure_finite;
use nalgebra::{Point3, Rotation3, UnitQuaternion, Vector2, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

use crate::sensor::{SensingError, all_in_range, in_range};

/// Number of markers of the default configuration, as in the paper.
pub const DEFAULT_MARKER_COUNT: usize = 11;

/// The largest [`MarkerParams::mount_offset`] allowed \[m\]: 5 cm, beyond any marker mounted
/// on a wire (a ball of that size would be a second body, not a marker).
pub const MAX_MOUNT_OFFSET: f64 = 0.05;

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
    /// Distance \[m\] of each marker's centre from the centreline, in `[0, MAX_MOUNT_OFFSET]`
    /// (default `0`: markers on the centreline). A ball of diameter `D` glued on a wire of
    /// radius `r` sits `r + D/2` off. Its direction in the wire's cross-section (the material
    /// frame's `m1`, `m2` at the marker's arc length) is drawn once per marker, uniform about
    /// the wire; the offset turns with the wire's bending and twist, and the per-frame noise
    /// comes on top.
    pub mount_offset: f64,
    /// Seed of the mounting offsets (default `0`): the markers are glued once, so the offsets
    /// come from this seed and not from the rig's, and every rig built with the same
    /// parameters carries the same markers.
    pub mount_seed: u64,
}

impl Default for MarkerParams {
    fn default() -> Self {
        let last = (DEFAULT_MARKER_COUNT - 1) as f64;
        Self {
            fractions: (0..DEFAULT_MARKER_COUNT).map(|i| i as f64 / last).collect(),
            noise_std: 3e-4,
            dropout_probability: 0.02,
            mount_offset: 0.0,
            mount_seed: 0,
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
        in_range("dropout_probability", 0, self.dropout_probability, 0.0, 1.0)?;
        in_range("mount_offset", 0, self.mount_offset, 0.0, MAX_MOUNT_OFFSET)
    }
}

/// The wire's cross-section frames along its arc length: what a marker's mounting offset
/// ([`MarkerParams::mount_offset`]) turns with.
///
/// Each frame is world from body, columns `(t, m1, m2)`: the tangent and the two cross-section
/// axes, as the simulator's material frames (`RodState::material_frames`). A marker between two
/// frames takes their spherical interpolation in arc length.
#[derive(Debug, Clone, Copy)]
pub struct SectionFrames<'a> {
    /// The frames, world from body.
    pub frames: &'a [Rotation3<f64>],
    /// The arc length \[m\] of each frame, strictly increasing.
    pub arc_lengths: &'a [f64],
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
    /// Each marker's mounting offset \[m\] along the cross-section axes `(m1, m2)`.
    offsets: Vec<Vector2<f64>>,
}

impl MotionCapture {
    /// Builds the motion-capture model from a configuration and a seed.
    ///
    /// # Errors
    /// [`SensingError::OutOfRange`] naming a fraction outside `[0, 1]`, a negative or non-finite
    /// noise σ, a dropout probability outside `[0, 1]`, or a mounting offset outside
    /// `[0, MAX_MOUNT_OFFSET]`.
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
        let mut mount = ChaCha8Rng::seed_from_u64(config.mount_seed);
        let offsets = config
            .fractions
            .iter()
            .map(|_| {
                let (sin, cos) = (std::f64::consts::TAU * mount.random::<f64>()).sin_cos();
                config.mount_offset * Vector2::new(cos, sin)
            })
            .collect();
        Ok(Self {
            config,
            rng: ChaCha8Rng::seed_from_u64(seed),
            offsets,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &MarkerParams {
        &self.config
    }

    /// Each marker's mounting offset \[m\] along the wire's cross-section axes `(m1, m2)`, in
    /// the order of [`MarkerParams::fractions`]: each [`MarkerParams::mount_offset`] long, in a
    /// direction drawn once from [`MarkerParams::mount_seed`]; all zero without an offset.
    pub fn mount_offsets(&self) -> &[Vector2<f64>] {
        &self.offsets
    }

    /// Noise-free marker positions on a centreline, world frame \[m\], without their
    /// mounting offsets ([`MotionCapture::mounted_positions`] adds them).
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
        self.config
            .fractions
            .iter()
            .enumerate()
            .map(|(marker, &fraction)| {
                let s = marker_arc_length(marker, fraction, length, arc_lengths)?;
                interpolate(centreline, arc_lengths, s)
            })
            .collect()
    }

    /// Noise-free positions of the markers' centres, world frame \[m\]: the points of
    /// [`MotionCapture::true_positions`], each moved by its mounting offset in the
    /// cross-section frame of `sections` at its arc length. With no mounting offset
    /// ([`MarkerParams::mount_offset`] `= 0`) they are `true_positions`' exactly and
    /// `sections` is not read.
    ///
    /// # Errors
    /// As [`MotionCapture::true_positions`]; for the frames, [`SensingError::SectionFrames`],
    /// [`SensingError::ArcLengthsNotIncreasing`], [`SensingError::Core`] for a non-finite
    /// frame or arc length, and [`SensingError::MarkerOutsideCentreline`] for a marker beyond
    /// the frames' arc lengths.
    ///
    /// # Example
    /// ```
    /// use ftwire_sim::markers::{MarkerParams, MotionCapture, SectionFrames};
    /// use nalgebra::{Point3, Rotation3};
    ///
    /// let config = MarkerParams { mount_offset: 0.002, ..MarkerParams::ideal() };
    /// let mocap = MotionCapture::new(config, 5)?;
    /// let line = [Point3::origin(), Point3::new(0.5, 0.0, 0.0)];
    /// let frames = [Rotation3::identity(); 2];
    /// let sections = SectionFrames { frames: &frames, arc_lengths: &[0.0, 0.5] };
    /// let centres = mocap.mounted_positions(&line, &[0.0, 0.5], 0.5, &sections)?;
    /// // Off the centreline (the x axis) by each marker's offset, in the cross-section.
    /// let offset = mocap.mount_offsets()[3];
    /// assert!((centres[3] - Point3::new(0.15, offset.x, offset.y)).norm() < 1e-12);
    /// # Ok::<(), ftwire_sim::SensingError>(())
    /// ```
    pub fn mounted_positions(
        &self,
        centreline: &[Point3<f64>],
        arc_lengths: &[f64],
        length: f64,
        sections: &SectionFrames<'_>,
    ) -> Result<Vec<Point3<f64>>, SensingError> {
        let points = self.true_positions(centreline, arc_lengths, length)?;
        if self.config.mount_offset <= 0.0 {
            return Ok(points);
        }
        validate_sections(sections)?;
        points
            .into_iter()
            .zip(&self.offsets)
            .zip(&self.config.fractions)
            .enumerate()
            .map(|(marker, ((p, offset), &fraction))| {
                let s = marker_arc_length(marker, fraction, length, sections.arc_lengths)?;
                Ok(p + section_at(sections, s) * Vector3::new(0.0, offset.x, offset.y))
            })
            .collect()
    }

    /// A motion-capture frame at time `time` \[s\]: the marker positions of
    /// [`MotionCapture::true_positions`] with noise and dropouts, for markers on the
    /// centreline.
    ///
    /// # Errors
    /// As [`MotionCapture::true_positions`], [`SensingError::Core`] if `time` is not finite,
    /// and [`SensingError::MountingWithoutFrames`] if the markers have a mounting offset
    /// (use [`MotionCapture::observe_mounted`]).
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
        if self.config.mount_offset > 0.0 {
            return Err(SensingError::MountingWithoutFrames {
                mount_offset: self.config.mount_offset,
            });
        }
        let empty = SectionFrames {
            frames: &[],
            arc_lengths: &[],
        };
        self.observe_mounted(time, centreline, arc_lengths, length, &empty)
    }

    /// A motion-capture frame at time `time` \[s\]: the markers' centres of
    /// [`MotionCapture::mounted_positions`] with noise and dropouts. The noise and dropouts
    /// draw from the same stream as [`MotionCapture::observe`]'s, so that without a mounting
    /// offset both give the same frames.
    ///
    /// # Errors
    /// As [`MotionCapture::mounted_positions`], and [`SensingError::Core`] if `time` is not
    /// finite.
    pub fn observe_mounted(
        &mut self,
        time: f64,
        centreline: &[Point3<f64>],
        arc_lengths: &[f64],
        length: f64,
        sections: &SectionFrames<'_>,
    ) -> Result<MarkerFrame, SensingError> {
        ensure_finite("time", &[time])?;
        let truth = self.mounted_positions(centreline, arc_lengths, length, sections)?;
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
    all_finite("centreline", centreline.iter().map(|p| p.coords.as_slice()))?;
    ensure_finite("arc_lengths", arc_lengths)?;
    increasing(arc_lengths)
}

fn validate_sections(sections: &SectionFrames<'_>) -> Result<(), SensingError> {
    let (frames, arc_lengths) = (sections.frames, sections.arc_lengths);
    if frames.is_empty() || frames.len() != arc_lengths.len() {
        return Err(SensingError::SectionFrames {
            frames: frames.len(),
            arc_lengths: arc_lengths.len(),
        });
    }
    all_finite(
        "section frames",
        frames.iter().map(|r| r.matrix().as_slice()),
    )?;
    ensure_finite("section arc_lengths", arc_lengths)?;
    increasing(arc_lengths)
}

/// Checks that every number of every item is finite, naming `field` and the item's index.
fn all_finite<'a>(
    field: &'static str,
    items: impl Iterator<Item = &'a [f64]>,
) -> Result<(), SensingError> {
    for (index, values) in items.enumerate() {
        if let Some(value) = values.iter().copied().find(|v| !v.is_finite()) {
            return Err(ftwire_core::CoreError::NonFinite {
                field,
                index,
                value,
            }
            .into());
        }
    }
    Ok(())
}

/// The cross-section frame at arc length `s`, within the validated frames' ends: the spherical
/// interpolation of the two frames around it (the nearer one should they be half a turn apart).
fn section_at(sections: &SectionFrames<'_>, s: f64) -> Rotation3<f64> {
    let (frames, arc_lengths) = (sections.frames, sections.arc_lengths);
    let above = arc_lengths.partition_point(|&a| a <= s);
    let j = above.saturating_sub(1);
    match (
        frames.get(j),
        frames.get(j + 1),
        arc_lengths.get(j),
        arc_lengths.get(j + 1),
    ) {
        (Some(r0), Some(r1), Some(&s0), Some(&s1)) => {
            let t = ((s - s0) / (s1 - s0)).clamp(0.0, 1.0);
            let (q0, q1) = (
                UnitQuaternion::from_rotation_matrix(r0),
                UnitQuaternion::from_rotation_matrix(r1),
            );
            q0.try_slerp(&q1, t, 1e-9)
                .map_or(if t < 0.5 { *r0 } else { *r1 }, |q| q.to_rotation_matrix())
        }
        (Some(r0), ..) => *r0,
        _ => Rotation3::identity(),
    }
}

fn increasing(arc_lengths: &[f64]) -> Result<(), SensingError> {
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

/// The arc length `fraction · length` \[m\] of marker `marker`, within the ends of the
/// validated `arc_lengths` (a marker a rounding error beyond an end is moved onto it).
fn marker_arc_length(
    marker: usize,
    fraction: f64,
    length: f64,
    arc_lengths: &[f64],
) -> Result<f64, SensingError> {
    let (first, last) = ends(arc_lengths);
    let slack = 1e-12 * (last - first).abs().max(length);
    let s = fraction * length;
    if s < first - slack || s > last + slack {
        return Err(SensingError::MarkerOutsideCentreline {
            marker,
            arc_length: s,
            min: first,
            max: last,
        });
    }
    Ok(s.clamp(first, last))
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
