//! The clearance polish on the shipped passage scene: a first path of RRT*, resampled into the
//! tracking experiments' 13 waypoints, comes out with the same ends, no waypoint closer to a
//! box than before, the tight ones moved (each within its shift cap), the others untouched,
//! and every edge next to a moved waypoint valid.

mod common;

use ftwire_plan::{PlannerParams, PolishParams, Sample, plan, polish_clearance};
use ftwire_rod::to_normalised;

fn resampled(seed: u64) -> (ftwire_plan::Checker, Vec<Sample>) {
    let common::ShippedProblem {
        checker,
        space,
        start,
        goal,
    } = common::shipped_problem();
    let params = PlannerParams {
        seed,
        max_iterations: 3000,
        stop_at_first: true,
        ..PlannerParams::default()
    };
    let found = plan(&space, &checker, &start, &goal.config, &params).expect("a path");
    let waypoints = found
        .path
        .resample(&space, &checker, 12)
        .expect("resampled");
    (checker, waypoints)
}

#[test]
fn the_polish_widens_the_tight_waypoints_and_keeps_the_path_valid() {
    let params = PolishParams::default();
    let mut widened = 0;
    for seed in [1, 2, 3] {
        let (checker, before) = resampled(seed);
        let polished = polish_clearance(&checker, &before, &params).expect("valid settings");
        let after = &polished.waypoints;
        assert_eq!(after.len(), before.len());
        assert_eq!(
            after[0].config, before[0].config,
            "seed {seed}: start moved"
        );
        assert_eq!(
            after[after.len() - 1].config,
            before[before.len() - 1].config,
            "seed {seed}: goal moved"
        );
        let wire = *checker.rod().wire();
        let mut moved = 0;
        for (i, (b, a)) in before.iter().zip(after).enumerate() {
            if b.clearance >= params.target {
                assert_eq!(a.config, b.config, "seed {seed}: waypoint {i} was clear");
            }
            assert!(
                a.clearance >= b.clearance,
                "seed {seed}: waypoint {i} {} → {}",
                b.clearance,
                a.clearance
            );
            let shift =
                (to_normalised(&wire, &a.config.a) - to_normalised(&wire, &b.config.a)).norm();
            assert!(shift <= params.max_shift + 1e-9, "seed {seed}: {shift}");
            if a.config != b.config {
                moved += 1;
                assert_eq!(a.config.base, b.config.base);
            }
        }
        assert_eq!(moved, polished.moved);
        // Every edge next to a moved waypoint was checked by the polish; the others are as
        // resampled (whose seeded IK can fail where the planner's did not).
        for (i, pair) in after.windows(2).enumerate() {
            if pair[0].config != before[i].config || pair[1].config != before[i + 1].config {
                checker
                    .edge(&pair[0], &pair[1].config)
                    .unwrap_or_else(|e| panic!("seed {seed}: edge {i} is invalid: {e}"));
            }
        }
        let (min_before, min_after) = polished.min_clearance;
        assert!(min_after >= min_before);
        if min_after > min_before + 1e-3 {
            widened += 1;
        }
        // Deterministic.
        assert_eq!(
            polish_clearance(&checker, &before, &params)
                .expect("valid settings")
                .waypoints,
            polished.waypoints
        );
    }
    // The passage's first paths pass the gap off its middle: the polish widens them.
    assert!(widened >= 2, "widened {widened} of 3");
}

#[test]
fn bad_polish_settings_are_refused_by_name() {
    let (checker, waypoints) = resampled(1);
    for (name, params) in [
        (
            "target",
            PolishParams {
                target: 0.0,
                ..PolishParams::default()
            },
        ),
        (
            "max_step",
            PolishParams {
                max_step: f64::NAN,
                ..PolishParams::default()
            },
        ),
        (
            "max_shift",
            PolishParams {
                max_shift: -1.0,
                ..PolishParams::default()
            },
        ),
        (
            "difference",
            PolishParams {
                difference: f64::INFINITY,
                ..PolishParams::default()
            },
        ),
    ] {
        let err = polish_clearance(&checker, &waypoints, &params).expect_err("refused");
        assert!(err.to_string().contains(name), "{name}: {err}");
    }
}
