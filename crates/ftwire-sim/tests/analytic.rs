//! Reference solutions: small models with a known answer.

mod common;

use common::{pose, rel};
use ftwire_sim::{InitialGuess, RodParams, World};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::f64::consts::PI;

fn params(edges: usize) -> RodParams {
    RodParams {
        stiffness: [0.042, 0.055, 0.070],
        ..RodParams::nitinol_2mm_630()
    }
    .without_gravity()
    .with_edges(edges)
}

/// A tip on a circle of radius R in the plane spanned by the base x axis and `normal`.
#[test]
fn pure_bending_to_an_arc_gives_moment_ei_over_r() {
    let p = params(100);
    let (l, c) = (p.length, p.stiffness);
    let world = World::new(p).expect("valid");
    let r = 0.4;
    let phi = l / r;
    // Arc towards +y: rotation about +z; moment +c3/R about z.
    let tip_y = pose([r * phi.sin(), r * (1.0 - phi.cos()), 0.0], [0.0, 0.0, phi]);
    let eq = world
        .solve_cold(&Isometry3::identity(), &tip_y)
        .expect("solves")
        .equilibrium;
    let a = eq.base_wrench.to_vector();
    let expected = c[2] / r;
    println!("arc in x-y: a = {a:?}, expected τ3 = {expected}");
    assert!(
        rel(a[2], expected, expected) < 2e-3,
        "τ3 {} vs {expected}",
        a[2]
    );
    for i in [0, 1] {
        assert!(a[i].abs() < 1e-3 * expected);
    }
    for i in 3..6 {
        assert!(a[i].abs() < 5e-3 * expected / l, "force {i} = {}", a[i]);
    }
    // Arc towards +z: rotation about −y; u2 = −1/R, moment −c2/R about y.
    let tip_z = pose(
        [r * phi.sin(), 0.0, r * (1.0 - phi.cos())],
        [0.0, -phi, 0.0],
    );
    let eq = world
        .solve_cold(&Isometry3::identity(), &tip_z)
        .expect("solves")
        .equilibrium;
    let a = eq.base_wrench.to_vector();
    let expected = -c[1] / r;
    println!("arc in x-z: a = {a:?}, expected τ2 = {expected}");
    assert!(rel(a[1], expected, expected.abs()) < 2e-3);
    assert!(eq.stable_minimum);
    // The tip gripper feels the opposite moment in its own frame.
    let b = eq.tip_wrench.to_vector();
    assert!(
        rel(b[1], -expected, expected.abs()) < 2e-3,
        "tip τ2 {}",
        b[1]
    );
}

/// The same arc on a wire whose bending softens at `κs`: the moment is
/// `c3 κ / √(1 + c3 κ²/(c̄ κs²))`, `c̄ = (c2 + c3)/2` (`c κ / √(1 + (κ/κs)²)` on a round wire).
#[test]
fn softened_bending_to_an_arc_gives_the_softened_moment() {
    let r = 0.4;
    for softening in [1.0 / r, 3.0 / r] {
        let p = RodParams {
            bending_softening: Some(softening),
            ..params(100)
        };
        let (l, c) = (p.length, p.stiffness);
        let world = World::new(p).expect("valid");
        let phi = l / r;
        let tip = pose([r * phi.sin(), r * (1.0 - phi.cos()), 0.0], [0.0, 0.0, phi]);
        let eq = world
            .solve_cold(&Isometry3::identity(), &tip)
            .expect("solves")
            .equilibrium;
        let a = eq.base_wrench.to_vector();
        let kappa = 1.0 / r;
        let mean = 0.5 * (c[1] + c[2]);
        let expected =
            c[2] * kappa / (1.0 + c[2] * kappa.powi(2) / (mean * softening.powi(2))).sqrt();
        println!("softening {softening}: τ3 = {}, expected {expected}", a[2]);
        assert!(
            rel(a[2], expected, expected) < 2e-3,
            "τ3 {} vs {expected}",
            a[2]
        );
        assert!(eq.stable_minimum);
    }
}

#[test]
fn pure_twist_gives_moment_gj_phi_over_l() {
    let p = params(100);
    let (l, c) = (p.length, p.stiffness);
    let world = World::new(p).expect("valid");
    for phi in [0.8, -0.5] {
        let tip = pose([l, 0.0, 0.0], [phi, 0.0, 0.0]);
        let eq = world
            .solve_cold(&Isometry3::identity(), &tip)
            .expect("solves")
            .equilibrium;
        let a = eq.base_wrench.to_vector();
        let expected = c[0] * phi / l;
        println!("twist {phi}: a = {a:?}, expected τ1 = {expected}");
        assert!(rel(a[0], expected, expected.abs()) < 1e-6);
        assert!(eq.stable_minimum);
    }
}

/// A clamped tip displaced as a cantilever under a small tip load P: δ = P·L³/(3EI), slope
/// P·L²/(2EI). The grippers must feel P and P·L at the base and no moment at the tip.
#[test]
fn cantilever_tip_load_matches_pl3_over_3ei() {
    let p = params(100);
    let (l, ei) = (p.length, p.stiffness[2]);
    let world = World::new(p).expect("valid");
    let load = 0.01 * ei / (l * l);
    let k = load / ei;
    let delta = k * l.powi(3) / 3.0;
    let slope = k * l * l / 2.0;
    let shortening = k * k * l.powi(5) / 15.0;
    let tip = pose([l - shortening, delta, 0.0], [0.0, 0.0, slope]);
    let eq = world
        .solve_cold(&Isometry3::identity(), &tip)
        .expect("solves")
        .equilibrium;
    let a = eq.base_wrench.to_vector();
    let b = eq.tip_wrench;
    println!(
        "cantilever: a = {a:?}, expected P = {load}, P·L = {}",
        load * l
    );
    let err_force = rel(a[4], load, load);
    let err_moment = rel(a[2], load * l, load * l);
    println!(
        "relative errors: force {err_force:e}, base moment {err_moment:e}, tip moment {:e}",
        b.torque.norm() / (load * l)
    );
    assert!(err_force < 2e-3);
    assert!(err_moment < 2e-3);
    assert!(b.torque.norm() < 2e-3 * load * l);
    assert!((b.force.y + load).abs() < 2e-3 * load);
}

/// The tip clamped where a cantilever under its own weight w ends: δ = w·L⁴/(8EI), slope
/// w·L³/(6EI). The tip gripper then carries nothing, the base carries the whole weight.
#[test]
fn cantilever_own_weight_matches_wl4_over_8ei() {
    let base_params = params(100);
    let (l, ei) = (base_params.length, base_params.stiffness[1]);
    let rho_a = base_params.density * PI * base_params.radius.powi(2);
    let w = 0.01 * ei / l.powi(3);
    let p = RodParams {
        gravity: Vector3::new(0.0, 0.0, -w / rho_a),
        ..base_params
    };
    let world = World::new(p).expect("valid");
    let k = w / ei;
    let delta = k * l.powi(4) / 8.0;
    let slope = k * l.powi(3) / 6.0;
    // Foreshortening ∫ ½ y'² ds with y' = k (L² s/2 − L s²/2 + s³/6).
    let m = 10_000;
    let shortening: f64 = (0..m)
        .map(|i| {
            let s = (i as f64 + 0.5) * l / m as f64;
            let dy = k * (l * l * s / 2.0 - l * s * s / 2.0 + s.powi(3) / 6.0);
            0.5 * dy * dy * l / m as f64
        })
        .sum();
    let tip = pose([l - shortening, 0.0, -delta], [0.0, slope, 0.0]);
    let eq = world
        .solve_cold(&Isometry3::identity(), &tip)
        .expect("solves")
        .equilibrium;
    let a = eq.base_wrench.to_vector();
    let b = eq.tip_wrench;
    let (weight, moment) = (w * l, w * l * l / 2.0);
    println!(
        "own weight: a = {a:?}, expected f3 = {}, τ2 = {moment}",
        -weight
    );
    println!(
        "relative errors: weight {:e}, moment {:e}, tip force {:e}, tip moment {:e}",
        rel(a[5], -weight, weight),
        rel(a[1], moment, moment),
        b.force.yz().norm() / weight,
        b.torque.norm() / moment
    );
    assert!(rel(a[5], -weight, weight) < 2e-3);
    assert!(rel(a[1], moment, moment) < 2e-3);
    // The axial force is left out: with the stiff stretching it measures the clamp distance to
    // 1e-10 m, far below the shape's discretisation error.
    assert!(b.force.yz().norm() < 3e-3 * weight);
    assert!(b.torque.norm() < 3e-3 * moment);
}

/// A clamped–clamped wire compressed just past buckling carries the Euler load 4π²EI/L².
/// It buckles about its softer axis (body y, c2 < c3), bulging along z; the same bulge along y
/// would be a saddle, which the stability check must see.
#[test]
fn clamped_clamped_buckling_load_is_4_pi2_ei_over_l2() {
    let p = params(100);
    let (l, ei) = (p.length, p.stiffness[1]);
    let world = World::new(p).expect("valid");
    let rod = world.rod().clone();
    let shortening = 1e-3 * l;
    let amp = 2.0 * (shortening * l).sqrt() / PI;
    let bulged = |axis: usize| {
        InitialGuess::from_shape(&rod, |s| {
            let y = 0.5 * amp * (1.0 - (2.0 * PI * s / l).cos());
            let dy = amp * PI / l * (2.0 * PI * s / l).sin();
            let mut p = Vector3::new(s * (1.0 - shortening / l), 0.0, 0.0);
            p[axis] = y;
            let turn = if axis == 1 {
                UnitQuaternion::from_axis_angle(&Vector3::z_axis(), dy.atan())
            } else {
                UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -dy.atan())
            };
            Isometry3::from_parts(Translation3::from(p), turn)
        })
    };
    let tip = pose([l - shortening, 0.0, 0.0], [0.0, 0.0, 0.0]);
    let eq = world
        .solve_with_guess(&bulged(2), &Isometry3::identity(), &tip)
        .expect("solves");
    let critical = 4.0 * PI * PI * ei / (l * l);
    let a = eq.base_wrench.to_vector();
    let bulge = eq
        .centreline()
        .iter()
        .map(|p| p.z.abs())
        .fold(0.0, f64::max);
    let error = rel(-a[3], critical, critical);
    println!("buckling: a = {a:?}, P_cr = {critical}, error {error:e}, bulge {bulge}");
    assert!(eq.stable_minimum);
    assert!(bulge > 0.5 * amp);
    assert!(error < 1e-3);
    // Bulging about the stiffer axis is an equilibrium too, but a saddle.
    let stiff = world
        .solve_with_guess(&bulged(1), &Isometry3::identity(), &tip)
        .expect("solves");
    let bulge_y = stiff
        .centreline()
        .iter()
        .map(|p| p.y.abs())
        .fold(0.0, f64::max);
    println!(
        "stiff-axis bulge {bulge_y}, stable {}",
        stiff.stable_minimum
    );
    assert!(bulge_y > 0.5 * amp);
    assert!(!stiff.stable_minimum);
}
