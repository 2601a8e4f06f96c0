//! Motion-capture markers on the wire: the input of the shape fit (paper §IV-A, eq. 15).
//!
//! A motion-capture system sees `V` markers glued at known arc lengths `s_k` along the wire
//! (the paper uses `V = 11`) and reports their positions `p_k` in the base clamp frame, or
//! nothing for a marker it did not see in that frame (a dropout). [`Markers`] holds the markers
//! of one frame that were seen, validated.

use nalgebra::Point3;

use crate::EstimateError;

/// Number of markers of the paper's setup (§IV).
pub const DEFAULT_MARKER_COUNT: usize = 11;

/// Fewest observed markers a fit accepts: 4 markers give 12 (arc-length) or 8 (closest-point)
/// scalar equations for the 6 unknowns of `a`, with some redundancy against noise.
pub const MIN_MARKERS: usize = 4;

/// `count` arc-length fractions `s_k / L` evenly spaced over `[0, 1]`, both ends included (the
/// default layout, `0, 0.1, …, 1` for 11 markers). One marker gives `[0]`, none gives `[]`.
///
/// # Example
/// ```
/// let fractions = ftwire_estimate::shape::evenly_spaced_fractions(11);
/// assert_eq!(fractions.len(), 11);
/// assert!((fractions[3] - 0.3).abs() < 1e-15);
/// assert_eq!(fractions[10], 1.0);
/// ```
pub fn evenly_spaced_fractions(count: usize) -> Vec<f64> {
    let last = count.saturating_sub(1).max(1) as f64;
    (0..count).map(|i| i as f64 / last).collect()
}

/// One observed marker.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Marker {
    /// Index of the marker in its layout (its place in the fractions list).
    pub index: usize,
    /// Arc-length fraction `s_k / L` of the marker, in `[0, 1]`.
    pub fraction: f64,
    /// Measured position `p_k` \[m\] in the base clamp frame.
    pub position: Point3<f64>,
}

/// The markers of one motion-capture frame that were seen: finite positions at fractions in
/// `[0, 1]`, at least [`MIN_MARKERS`] of them.
#[derive(Debug, Clone, PartialEq)]
pub struct Markers {
    markers: Vec<Marker>,
}

impl Markers {
    /// The observed markers of a frame: `positions[k]` is marker `k`'s position \[m\] in the base
    /// clamp frame, or `None` where it dropped out; `fractions[k]` its arc-length fraction.
    ///
    /// # Errors
    /// [`EstimateError::MarkerCountMismatch`] if the two lists differ in length,
    /// [`EstimateError::BadMarkerFraction`] for a fraction outside `[0, 1]` or not finite,
    /// [`EstimateError::NonFiniteMarker`] for a non-finite coordinate (naming marker, axis and
    /// value), [`EstimateError::TooFewMarkers`] if fewer than [`MIN_MARKERS`] were seen.
    ///
    /// # Example
    /// ```
    /// use ftwire_estimate::shape::{Markers, evenly_spaced_fractions};
    /// use nalgebra::Point3;
    /// let fractions = evenly_spaced_fractions(5);
    /// let seen = |x: f64| Some(Point3::new(x, 0.0, 0.0));
    /// let positions = [seen(0.0), None, seen(0.5), seen(0.75), seen(1.0)];
    /// let markers = Markers::new(&fractions, &positions)?;
    /// assert_eq!(markers.len(), 4);
    /// assert_eq!(markers.iter().nth(1).map(|m| m.index), Some(2));
    /// # Ok::<(), ftwire_estimate::EstimateError>(())
    /// ```
    pub fn new(
        fractions: &[f64],
        positions: &[Option<Point3<f64>>],
    ) -> Result<Self, EstimateError> {
        if fractions.len() != positions.len() {
            return Err(EstimateError::MarkerCountMismatch {
                fractions: fractions.len(),
                positions: positions.len(),
            });
        }
        let mut markers = Vec::with_capacity(positions.len());
        for (index, (&fraction, position)) in fractions.iter().zip(positions).enumerate() {
            if !(fraction.is_finite() && (0.0..=1.0).contains(&fraction)) {
                return Err(EstimateError::BadMarkerFraction {
                    marker: index,
                    fraction,
                });
            }
            let Some(position) = position else { continue };
            if let Some((axis, &value)) = position.iter().enumerate().find(|(_, v)| !v.is_finite())
            {
                return Err(EstimateError::NonFiniteMarker {
                    marker: index,
                    axis,
                    value,
                });
            }
            markers.push(Marker {
                index,
                fraction,
                position: *position,
            });
        }
        if markers.len() < MIN_MARKERS {
            return Err(EstimateError::TooFewMarkers {
                observed: markers.len(),
                min: MIN_MARKERS,
            });
        }
        Ok(Self { markers })
    }

    /// Number of observed markers.
    pub fn len(&self) -> usize {
        self.markers.len()
    }

    /// Always `false`: a [`Markers`] holds at least [`MIN_MARKERS`] markers.
    pub fn is_empty(&self) -> bool {
        self.markers.is_empty()
    }

    /// The observed markers, in layout order.
    pub fn iter(&self) -> std::slice::Iter<'_, Marker> {
        self.markers.iter()
    }

    /// The observed markers as a slice, in layout order.
    pub fn as_slice(&self) -> &[Marker] {
        &self.markers
    }
}

impl<'a> IntoIterator for &'a Markers {
    type Item = &'a Marker;
    type IntoIter = std::slice::Iter<'a, Marker>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(count: usize) -> Vec<Option<Point3<f64>>> {
        (0..count)
            .map(|i| Some(Point3::new(i as f64, 0.0, 0.0)))
            .collect()
    }

    #[test]
    fn rejects_bad_frames_with_what_was_wrong() {
        let fractions = evenly_spaced_fractions(6);
        assert_eq!(
            Markers::new(&fractions, &line(5)),
            Err(EstimateError::MarkerCountMismatch {
                fractions: 6,
                positions: 5
            })
        );
        let mut positions = line(6);
        positions[2] = Some(Point3::new(0.0, f64::NAN, 0.0));
        assert!(matches!(
            Markers::new(&fractions, &positions),
            Err(EstimateError::NonFiniteMarker {
                marker: 2,
                axis: 1,
                value
            }) if value.is_nan()
        ));
        let mut bad_fractions = fractions.clone();
        bad_fractions[4] = 1.5;
        assert_eq!(
            Markers::new(&bad_fractions, &line(6)),
            Err(EstimateError::BadMarkerFraction {
                marker: 4,
                fraction: 1.5
            })
        );
        let mut sparse = line(6);
        for dropped in [0, 3, 5] {
            sparse[dropped] = None;
        }
        assert_eq!(
            Markers::new(&fractions, &sparse),
            Err(EstimateError::TooFewMarkers {
                observed: 3,
                min: MIN_MARKERS
            })
        );
    }

    #[test]
    fn dropouts_are_skipped_and_indices_kept() -> Result<(), EstimateError> {
        let fractions = evenly_spaced_fractions(11);
        let mut positions = line(11);
        positions[4] = None;
        positions[9] = None;
        let markers = Markers::new(&fractions, &positions)?;
        assert_eq!(markers.len(), 9);
        let indices: Vec<usize> = markers.iter().map(|m| m.index).collect();
        assert_eq!(indices, vec![0, 1, 2, 3, 5, 6, 7, 8, 10]);
        Ok(())
    }

    #[test]
    fn evenly_spaced_edge_cases() {
        assert!(evenly_spaced_fractions(0).is_empty());
        assert_eq!(evenly_spaced_fractions(1), vec![0.0]);
        assert_eq!(evenly_spaced_fractions(2), vec![0.0, 1.0]);
    }
}
