//! How a plan that is to be tracked is made: its margins in `Z_free`, its polish and the
//! choice among candidates, by how the execution lands the second gripper.
//!
//! A tracking loop that converges onto the plan (no execution noise, or a fixed calibration
//! offset) keeps the planner's defaults. Where every move lands the gripper with fresh noise,
//! the plan keeps more room: clear of the boxes by more than one landing's scatter, slack
//! enough that a landing does not tear the wire, away from the folds of `A_stable`; its
//! waypoints are polished for their landings and the plan with the fewest expected touching
//! landings is tracked. The measurements behind each value are in `docs/design/tracking.md`.

use ftwire_rod::Rod;

use crate::{Landing, PolishParams, Scatter, ValidityParams};

/// The clearance \[m\] a plan tracked under fresh noise per move keeps from every box and the
/// floor: a little more than the ~12 mm by which a noisy move scatters the wire (the
/// planner's 5 mm default is less than that scatter).
pub const MARGIN_NOISY: f64 = 0.015;

/// The largest distance between the grippers of a plan tracked under fresh noise per move, as
/// a fraction of the wire's length (or [`MAX_SLACK_NOISY`] of slack where that is less): a
/// gripper landing the noise's few centimetres beyond a taut wire tears it.
pub const MAX_SPAN_NOISY: f64 = 0.93;

/// The most slack \[m\] a plan tracked under fresh noise per move keeps: what
/// [`MAX_SPAN_NOISY`] leaves the 820 mm wire. The tear it guards against is a landing beyond a
/// taut wire, whatever the wire's length, and a longer wire's 7 % left no path through the
/// shipped passage.
pub const MAX_SLACK_NOISY: f64 = (1.0 - MAX_SPAN_NOISY) * 0.82;

/// The distance in normalised `a` from the boundary of `A_stable` that a plan tracked under
/// fresh noise per move keeps (`ValidityParams::stability_margin`): each noisy move scatters
/// `a` by units, and a wire pushed over a fold snaps onto another equilibrium.
pub const STABILITY_MARGIN_NOISY: f64 = 1.0;

/// Standard deviations of one move's scatter by which the landing polish's probes land off
/// ([`PlanPolicy::polish_params`]): 2, a landing that one move in about twenty reaches on its
/// axis.
pub const LANDING_SIGMAS: f64 = 2.0;

/// The landing clearance \[m\] the polish aims at: the plans' own margin under fresh noise
/// ([`MARGIN_NOISY`]), which a waypoint's planned wire already keeps.
pub const LANDING_TARGET: f64 = MARGIN_NOISY;

/// Landings per waypoint of the expected touches ([`crate::expected_touches`]): enough that
/// one touching landing at one waypoint counts 0.001.
pub const TOUCH_SAMPLES: usize = 1024;

/// How a plan to be tracked is made (plain data; [`PlanPolicy::converging`] and
/// [`PlanPolicy::scattered`] give the tuned ones). The caller chooses by its execution noise.
///
/// # Example
/// ```
/// use ftwire_plan::{PlanPolicy, ValidityParams};
/// // The loop converges onto the plan: the planner's defaults, no polish, no choice.
/// let converging = PlanPolicy::converging();
/// assert_eq!(converging.validity(0.82), ValidityParams::default());
/// assert!(!converging.polishes());
/// // Every move lands 10 mm / 3° off (1 σ): 15 mm of margin, 7 % of slack.
/// let noisy = PlanPolicy::scattered(0.010, 3f64.to_radians());
/// assert_eq!(noisy.validity(0.82).margin, 0.015);
/// assert!((noisy.max_span_for(0.82) - 0.93).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanPolicy {
    /// One move's landing scatter of the second gripper (1 σ per axis) and the landings drawn
    /// for the expected touches; `None` where the tracking loop converges onto the plan, which
    /// then is neither polished nor chosen among candidates.
    pub scatter: Option<Scatter>,
    /// Clearance \[m\] from every box and the floor (`ValidityParams::margin`).
    pub margin: f64,
    /// The largest gripper distance as a fraction of the wire's length
    /// ([`PlanPolicy::max_span_for`]).
    pub max_span: f64,
    /// The least slack \[m\] the grippers leave, when that is more than
    /// [`PlanPolicy::max_span`] allows (0: none).
    pub max_slack: f64,
    /// Distance in normalised `a` from the boundary of `A_stable`
    /// (`ValidityParams::stability_margin`; 0: none).
    pub stability_margin: f64,
    /// σ of the scatter by which the landing polish's probes land off ([`LANDING_SIGMAS`]).
    pub landing_sigmas: f64,
    /// The landing clearance \[m\] the polish aims at ([`LANDING_TARGET`]).
    pub landing_target: f64,
}

impl PlanPolicy {
    /// A plan for a tracking loop that converges onto it: the planner's defaults.
    pub fn converging() -> Self {
        Self {
            scatter: None,
            margin: ValidityParams::default().margin,
            max_span: 1.0,
            max_slack: 0.0,
            stability_margin: 0.0,
            landing_sigmas: LANDING_SIGMAS,
            landing_target: LANDING_TARGET,
        }
    }

    /// A plan for execution whose every move lands the second gripper off by a fresh draw of
    /// `position_std` \[m\] per axis and `orientation_std` \[rad\] per rotation component (1 σ).
    pub fn scattered(position_std: f64, orientation_std: f64) -> Self {
        Self {
            scatter: Some(Scatter {
                position_std,
                orientation_std,
                samples: TOUCH_SAMPLES,
                seed: 0,
            }),
            margin: MARGIN_NOISY,
            max_span: MAX_SPAN_NOISY,
            max_slack: MAX_SLACK_NOISY,
            stability_margin: STABILITY_MARGIN_NOISY,
            ..Self::converging()
        }
    }

    /// Whether the plan's waypoints are polished for their landings and the plan chosen among
    /// candidates by its expected touches: where every move scatters the landing.
    pub fn polishes(&self) -> bool {
        self.scatter.is_some()
    }

    /// The largest distance between the grippers for a wire of `length` \[m\], as a fraction
    /// of it: [`PlanPolicy::max_span`], or [`PlanPolicy::max_slack`] of slack where that is
    /// less.
    pub fn max_span_for(&self, length: f64) -> f64 {
        self.max_span.max(1.0 - self.max_slack / length)
    }

    /// The validity settings of the plan for a wire of `length` \[m\]: the defaults with
    /// [`PlanPolicy::max_span_for`], the margin and the stability margin.
    pub fn validity(&self, length: f64) -> ValidityParams {
        ValidityParams {
            max_span: self.max_span_for(length),
            margin: self.margin,
            stability_margin: self.stability_margin,
            ..ValidityParams::default()
        }
    }

    /// [`PlanPolicy::validity`] for a plan tracked with the model `tracker`: a stability
    /// margin is kept on `tracker`'s folds (`ValidityParams::stability_model`), so that every
    /// configuration is stable under it too. The planner's weightless model and the loaded one
    /// the wire is tracked with differ most for a heavy wire.
    pub fn validity_tracked(&self, tracker: &Rod) -> ValidityParams {
        let params = self.validity(tracker.wire().length());
        ValidityParams {
            stability_model: (params.stability_margin > 0.0).then_some(*tracker),
            ..params
        }
    }

    /// The clearance polish's settings: each interior waypoint's *landing clearance* (where a
    /// move toward it lands when the gripper lands [`PlanPolicy::landing_sigmas`] σ off on one
    /// axis) raised toward [`PlanPolicy::landing_target`]. The touches of a run are at the
    /// rests beside the waypoints whose landings scatter most toward a box, which need not be
    /// those whose planned wire is closest to it. Without a scatter, the planned clearance.
    pub fn polish_params(&self) -> PolishParams {
        PolishParams {
            target: self.landing_target,
            landing: self.scatter.map(|s| Landing {
                position: self.landing_sigmas * s.position_std,
                rotation: self.landing_sigmas * s.orientation_std,
            }),
            ..PolishParams::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noisy() -> PlanPolicy {
        PlanPolicy::scattered(0.010, 3f64.to_radians())
    }

    #[test]
    fn a_noisy_plan_keeps_seven_percent_of_its_length_as_slack_up_to_that_of_the_820_mm_wire() {
        let noisy = noisy();
        // Up to 820 mm: 93 % of the length.
        assert_eq!(noisy.max_span_for(0.63), MAX_SPAN_NOISY);
        assert_eq!(noisy.max_span_for(0.82), MAX_SPAN_NOISY);
        // Longer: the same 57.4 mm of slack.
        for length in [0.91, 0.92, 1.5] {
            let slack = (1.0 - noisy.max_span_for(length)) * length;
            assert!((slack - 0.0574).abs() < 1e-12, "{length}: {slack}");
            assert!(noisy.max_span_for(length) > MAX_SPAN_NOISY);
        }
        for length in [0.63, 0.82, 0.92, 2.0] {
            let span = noisy.max_span_for(length);
            assert!(span <= 1.0 && span > 0.5);
            assert_eq!(PlanPolicy::converging().max_span_for(length), 1.0);
        }
    }

    #[test]
    fn a_noisy_plan_is_polished_for_landings_two_standard_deviations_off() {
        let params = noisy().polish_params();
        let landing = params.landing.expect("the landings are polished");
        assert_eq!(landing.position, 2.0 * 0.010);
        assert_eq!(landing.rotation, 2.0 * 3f64.to_radians());
        assert_eq!(params.target, MARGIN_NOISY);
        // The rest as the plain polish.
        assert_eq!(
            PolishParams {
                target: PolishParams::default().target,
                landing: None,
                ..params
            },
            PolishParams::default()
        );
        assert!(noisy().polishes() && !PlanPolicy::converging().polishes());
    }

    #[test]
    fn only_a_noisy_plan_keeps_the_wider_margins_on_the_tracking_models_folds() {
        assert_eq!(noisy().validity(0.82).max_span, MAX_SPAN_NOISY);
        assert_eq!(noisy().validity(0.82).margin, MARGIN_NOISY);
        assert_eq!(
            PlanPolicy::converging().validity(0.82),
            ValidityParams::default()
        );
        let tracker = Rod::new(
            ftwire_rod::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("wire"),
        )
        .with_load(
            ftwire_rod::Load::from_gravity(6450.0, 0.0015, nalgebra::Vector3::new(0.0, 0.0, -9.81))
                .expect("load"),
        );
        let tracked = noisy().validity_tracked(&tracker);
        assert_eq!(tracked.stability_margin, STABILITY_MARGIN_NOISY);
        assert_eq!(tracked.stability_model, Some(tracker));
        assert_eq!(
            PlanPolicy::converging().validity_tracked(&tracker),
            ValidityParams::default()
        );
    }
}
