//! Validity on hand-made cases: a wire through a box is invalid, a clear one valid; unstable
//! and unreachable configurations; an edge through a box.

mod common;

use ftwire_plan::{Invalid, PlanError, Scene, ZPoint, scene_configuration, scene_endpoint};
use ftwire_rod::from_normalised;
use nalgebra::Vector6;

#[test]
fn the_passage_start_and_goal_are_valid() {
    let scene = common::passage();
    let checker = common::checker(&scene);
    for name in ["start", "goal"] {
        let s = scene_endpoint(&scene, &checker, name, name).expect("in Z_free");
        assert!(
            s.clearance >= checker.params().margin,
            "{name}: {}",
            s.clearance
        );
        assert_eq!(s.centreline.len(), checker.params().nodes);
        // The centreline starts at the base clamp and ends at the second gripper.
        assert!((s.centreline[0].coords - scene.base.translation.vector).norm() < 1e-12);
        let last = s.centreline[s.centreline.len() - 1].coords;
        assert!((last - s.tip.translation.vector).norm() < 1e-9);
    }
}

#[test]
fn a_box_around_the_wire_makes_it_invalid() {
    let scene = common::passage();
    let checker = common::checker(&scene);
    let start = scene_endpoint(&scene, &checker, "start", "start").expect("valid");
    // A small box at the wire's middle node.
    let mid = start.centreline[start.centreline.len() / 2];
    let text = format!(
        "[base]\nposition = [0.60, 0.35, 0.35]\nrotation = [0.0, 0.0, -1.5707963267948966]\n\
         [[obstacle]]\nname = \"through\"\ncentre = [{}, {}, {}]\nhalf_extents = [0.01, 0.01, 0.01]\n\
         [configuration.start]\na_normalised = [-0.35, -1.97, -0.3, -4.02, 0.47, 3.49]\n",
        mid.x, mid.y, mid.z
    );
    let blocked = Scene::from_toml(&text, "blocked.toml").expect("valid scene");
    let blocked_checker = common::checker(&blocked);
    match blocked_checker.endpoint(&start.config) {
        Err(Invalid::WireCollision {
            obstacle,
            clearance,
        }) => {
            assert!(obstacle.contains("through"));
            assert!(clearance < 0.0, "{clearance}");
        }
        other => panic!("expected a wire collision, got {other:?}"),
    }
    // The scene's own start is then an invalid endpoint, with the reason named.
    let e = scene_endpoint(&blocked, &blocked_checker, "start", "start").expect_err("blocked");
    assert!(matches!(
        e,
        PlanError::InvalidEndpoint { role: "start", .. }
    ));
    assert!(e.to_string().contains("through"), "{e}");
    // Moved 30 mm off the wire (more than radius + margin + half extent), it is clear.
    let off = text.replace(
        &format!("centre = [{}, {}, {}]", mid.x, mid.y, mid.z),
        &format!("centre = [{}, {}, {}]", mid.x, mid.y, mid.z + 0.03),
    );
    let clear = Scene::from_toml(&off, "clear.toml").expect("valid scene");
    let s = common::checker(&clear)
        .endpoint(&start.config)
        .expect("clear");
    assert!(s.clearance > 0.005 && s.clearance < 0.02, "{}", s.clearance);
}

#[test]
fn an_unstable_configuration_is_invalid() {
    let scene = common::passage();
    let checker = common::checker(&scene);
    let rod = common::rod();
    // Compressed far beyond the clamped–clamped Euler load 4π² (normalised).
    let a = from_normalised(rod.wire(), &Vector6::new(0.0, 0.0, 1e-3, -80.0, 0.0, 0.0));
    let config = ZPoint {
        a,
        base: scene.base,
    };
    assert_eq!(checker.endpoint(&config), Err(Invalid::Unstable));
    // Outside A (a2 = a3 = a5 = a6 = 0): the model refuses it.
    let config = ZPoint {
        a: Vector6::new(0.1, 0.0, 0.0, -0.1, 0.0, 0.0),
        base: scene.base,
    };
    assert!(matches!(checker.endpoint(&config), Err(Invalid::Model(_))));
}

#[test]
fn a_base_out_of_reach_is_invalid() {
    let mut scene = common::passage();
    scene.base = ftwire_core::Pose::translation(2.5, 0.0, 0.3) * scene.base.rotation;
    let checker = common::checker(&scene);
    let config = scene_configuration(&scene, checker.rod(), "start").expect("exists");
    assert!(matches!(
        checker.endpoint(&config),
        Err(Invalid::Unreachable { .. })
    ));
}

#[test]
fn the_edge_through_a_block_is_invalid_and_its_reason_named() {
    let scene = common::passage();
    let checker = common::checker(&scene);
    let start = scene_endpoint(&scene, &checker, "start", "start").expect("valid");
    // Bending the start about its y axis lowers the crossing onto the back block.
    let rod = common::rod();
    let x = ftwire_rod::to_normalised(rod.wire(), &start.config.a);
    let mut blocked = None;
    for k in 1..=40 {
        let mut y = x;
        y[1] += 0.1 * f64::from(k);
        let to = ZPoint {
            a: from_normalised(rod.wire(), &y),
            base: scene.base,
        };
        if let Err(Invalid::WireCollision { obstacle, .. }) = checker.sample(&to, &start.joints) {
            blocked = Some((to, obstacle));
            break;
        }
    }
    let (to, obstacle) = blocked.expect("some bend hits a block");
    assert!(obstacle.contains("block"), "{obstacle}");
    let e = checker
        .edge(&start, &to)
        .expect_err("the edge ends in a block");
    assert!(matches!(e, Invalid::WireCollision { .. }), "{e:?}");
}

#[test]
fn max_span_keeps_the_grippers_closer_than_the_limit() {
    // The planner tests' passage starts taut (the grippers 0.80 m apart, 98 % of 0.82 m).
    let scene = common::passage();
    let start = scene_endpoint(&scene, &common::checker(&scene), "start", "start").expect("valid");
    let span = (start.tip.translation.vector - scene.base.translation.vector).norm();
    let with = |max_span: f64| {
        ftwire_plan::Checker::new(
            common::rod(),
            ftwire_robot::Robot::sda10f().expect("robot"),
            &scene,
            ftwire_plan::ValidityParams {
                max_span,
                ..ftwire_plan::ValidityParams::default()
            },
        )
    };
    let loose = with((span + 0.001) / 0.82).expect("valid setting");
    assert!(loose.endpoint(&start.config).is_ok());
    let tight = with((span - 0.001) / 0.82).expect("valid setting");
    match tight.endpoint(&start.config) {
        Err(Invalid::Taut { span: s, limit }) => {
            assert!((s - span).abs() < 1e-9, "{s} against {span}");
            assert!((limit - (span - 0.001)).abs() < 1e-12);
        }
        other => panic!("expected Taut, got {other:?}"),
    }
    for bad in [0.0, -0.5, 1.01, f64::NAN] {
        match with(bad) {
            Err(PlanError::InvalidParameter { name, .. }) => assert_eq!(name, "max_span"),
            other => panic!("max_span {bad}: expected InvalidParameter, got {other:?}"),
        }
    }
}

/// The configuration `t` normalised units along growing compression (with a little twist).
fn compressed(rod: &ftwire_rod::Rod, t: f64) -> Vector6<f64> {
    from_normalised(rod.wire(), &Vector6::new(0.0, 0.0, 0.5, -t, 0.0, 0.0))
}

/// Where [`compressed`] leaves `A_stable` of `model` (bisection on `[0, 80]`).
fn compression_boundary(rod: &ftwire_rod::Rod, model: &ftwire_rod::Rod) -> f64 {
    let stable = |t: f64| model.is_stable(&compressed(rod, t)).unwrap_or(false);
    let (mut lo, mut hi) = (0.0, 80.0);
    assert!(stable(lo) && !stable(hi));
    for _ in 0..50 {
        let mid = 0.5 * (lo + hi);
        if stable(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// A checker of `scene` for the passage's wire with `params`.
fn checker_with(
    scene: &Scene,
    params: ftwire_plan::ValidityParams,
) -> Result<ftwire_plan::Checker, PlanError> {
    ftwire_plan::Checker::new(
        common::rod(),
        ftwire_robot::Robot::sda10f().expect("robot"),
        scene,
        params,
    )
}

#[test]
fn stability_margin_rejects_a_stable_configuration_next_to_the_boundary() {
    let scene = common::passage();
    let rod = common::rod();
    let at = |t: f64| compressed(&rod, t);
    let stable = |t: f64| rod.is_stable(&at(t)).unwrap_or(false);
    let lo = compression_boundary(&rod, &rod);
    // Half a unit inside: stable, and one more unit of compression is not.
    let t = lo - 0.5;
    assert!(stable(t) && !stable(t + 1.0), "boundary at {lo}");
    let config = ZPoint {
        a: at(t),
        base: scene.base,
    };
    let with = |stability_margin: f64| {
        checker_with(
            &scene,
            ftwire_plan::ValidityParams {
                stability_margin,
                ..ftwire_plan::ValidityParams::default()
            },
        )
    };
    let near = |r: &Result<_, Invalid>| matches!(r, Err(Invalid::NearBoundary { .. }));
    // Without a margin, and with one smaller than the distance, the stability checks pass.
    for margin in [0.0, 0.25] {
        let r = with(margin).expect("valid").endpoint(&config);
        assert!(!near(&r) && r != Err(Invalid::Unstable), "{margin}: {r:?}");
    }
    let r = with(1.0).expect("valid").endpoint(&config);
    match &r {
        Err(e @ Invalid::NearBoundary { margin, .. }) => {
            assert_eq!(*margin, 1.0);
            assert!(e.to_string().contains("stability_margin"), "{e}");
        }
        other => panic!("expected NearBoundary, got {other:?}"),
    }
    for bad in [-0.5, f64::NAN, f64::INFINITY] {
        match with(bad) {
            Err(PlanError::InvalidParameter { name, .. }) => assert_eq!(name, "stability_margin"),
            other => panic!("stability_margin {bad}: expected InvalidParameter, got {other:?}"),
        }
    }
}

#[test]
fn a_stability_model_holds_configurations_to_its_own_folds() {
    let scene = common::passage();
    let rod = common::rod();
    let weightless = compression_boundary(&rod, &rod);
    // A heavy wire (ten times nitinol's density) with its weight along one of the clamp's
    // axes: some direction moves the compression boundary below the weightless one.
    let (loaded, t_loaded) = [1.0, -1.0]
        .into_iter()
        .flat_map(|s| {
            [
                nalgebra::Vector3::new(s * 9.81, 0.0, 0.0),
                nalgebra::Vector3::new(0.0, 0.0, s * 9.81),
            ]
        })
        .map(|g| {
            let load = ftwire_rod::Load::from_gravity(64_500.0, 0.0015, g).expect("valid load");
            let loaded = rod.with_load(load);
            (loaded, compression_boundary(&rod, &loaded))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("some direction");
    assert!(
        t_loaded < weightless - 0.5,
        "{t_loaded} against {weightless}"
    );
    // Stable for the planner's model, not for the loaded one.
    let config = ZPoint {
        a: compressed(&rod, 0.5 * (t_loaded + weightless)),
        base: scene.base,
    };
    let with = |stability_model| {
        checker_with(
            &scene,
            ftwire_plan::ValidityParams {
                stability_model,
                ..ftwire_plan::ValidityParams::default()
            },
        )
        .expect("valid settings")
    };
    let r = with(None).endpoint(&config);
    assert!(r != Err(Invalid::Unstable), "{r:?}");
    assert_eq!(with(Some(loaded)).endpoint(&config), Err(Invalid::Unstable));
}
