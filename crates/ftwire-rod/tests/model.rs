//! Derivative checks, reference models and invariants of the Kirchhoff wire.

mod common;

use approx::assert_relative_eq;
use ftwire_rod::{
    CoreError, Integrator, Method, Rod, RodError, WireParams, from_normalised, se3, to_normalised,
};
use nalgebra::Vector6;
use proptest::prelude::*;

fn nitinol() -> WireParams {
    WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid")
}

fn fine(wire: WireParams) -> Rod {
    Rod::new(wire).with_integrator(Integrator::new(Method::Rk8, 200).expect("valid"))
}

fn normalised() -> impl Strategy<Value = Vector6<f64>> {
    prop::array::uniform6(-30.0..30.0f64).prop_map(|a| Vector6::from_column_slice(&a))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// J(L) δa is the body twist of the tip: central differences of log(q(L)⁻¹ q_{a±h e_k}(L)).
    #[test]
    fn jacobian_matches_finite_differences(an in normalised()) {
        let wire = nitinol();
        let rod = fine(wire);
        let a = from_normalised(&wire, &an);
        let solution = rod.jacobian(&a).expect("solves");
        let tip = solution.tip;
        let scale = Vector6::new(
            wire.torque_scale(), wire.torque_scale(), wire.torque_scale(),
            wire.force_scale(), wire.force_scale(), wire.force_scale(),
        );
        let mut fd = nalgebra::Matrix6::zeros();
        for k in 0..6 {
            let h = 1e-5 * scale[k];
            let mut ap = a;
            ap[k] += h;
            let mut am = a;
            am[k] -= h;
            let xp = se3::log(&(tip.inverse() * rod.tip(&ap).expect("solves")));
            let xm = se3::log(&(tip.inverse() * rod.tip(&am).expect("solves")));
            fd.set_column(k, &((xp - xm) / (2.0 * h)));
        }
        // Compare column by column in the scaled units the columns live in.
        let j = solution.jacobian;
        for k in 0..6 {
            let col_scale = fd.column(k).amax().max(1e-12);
            let err = (j.column(k) - fd.column(k)).amax() / col_scale;
            prop_assert!(err < 1e-5, "column {k}: relative error {err:e}\nJ = {j}\nFD = {fd}");
        }
    }

    /// The closed forms μ = Ad_qᵀ a and M = Ad_qᵀ + K J against the full system integrated
    /// independently (eq. 3 for μ, M' = F M for M).
    #[test]
    fn closed_forms_match_the_full_system(an in normalised(), frac in 0.2..1.0f64) {
        let wire = nitinol();
        let a = from_normalised(&wire, &an);
        let t = frac * wire.length();
        let reference = common::reference_at(&wire, &a, t, 1e-12);
        let mu = ftwire_rod::se3::adjoint(&reference.pose).transpose() * a;
        prop_assert!((mu - reference.mu).amax() < 1e-8 * (1.0 + reference.mu.amax()));
        let m = ftwire_rod::m_matrix(&reference.pose, &reference.mu, &reference.j);
        let err = (m - reference.m).amax() / reference.m.amax();
        prop_assert!(err < 1e-7, "M relative error {err:e}");
    }
}

/// |n|², m·n and the Hamiltonian ½ Σ μi²/ci + μ4 are constant along the wire.
#[test]
fn invariants_are_conserved() {
    let wire = WireParams::new([1.3, 1.0, 0.6], 0.8, 0.001).expect("valid");
    let rod = Rod::new(wire);
    let c = wire.c();
    for an in [
        Vector6::new(3.0, -7.0, 12.0, -20.0, 15.0, 4.0),
        Vector6::new(-25.0, 1.0, -3.0, 10.0, -28.0, 9.0),
        Vector6::new(0.5, 0.0, 0.1, -2.0, 0.0, 0.0),
    ] {
        let a = from_normalised(&wire, &an);
        let s = rod.solve(&a, 101).expect("solves");
        let inv = |mu: &Vector6<f64>| {
            let n = mu.fixed_rows::<3>(3);
            let m = mu.fixed_rows::<3>(0);
            let h =
                0.5 * (mu[0] * mu[0] / c[0] + mu[1] * mu[1] / c[1] + mu[2] * mu[2] / c[2]) + mu[3];
            (n.norm_squared(), m.dot(&n), h)
        };
        let (n0, mn0, h0) = inv(&a);
        let scale = (n0.sqrt() * wire.length() + a.fixed_rows::<3>(0).norm()).max(1e-12);
        for mu in &s.costate {
            let (n, mn, h) = inv(mu);
            assert_relative_eq!(n, n0, max_relative = 1e-9);
            assert!((mn - mn0).abs() < 1e-8 * scale * n0.sqrt());
            assert!(
                (h - h0).abs() < 1e-7 * (h0.abs() + scale * scale),
                "H {h} vs {h0}"
            );
        }
        // And μ(t) along the wire matches the independent reference integration.
        let mid = 50;
        let r = common::reference_at(&wire, &a, s.shape.arc_length[mid], 1e-12);
        assert!((s.costate[mid] - r.mu).amax() < 1e-7 * (1.0 + r.mu.amax()));
        assert!((s.shape.positions[mid] - r.pose.translation.vector).norm() < 1e-7 * wire.length());
    }
}

/// Pure bending a = (0, 0, τ, 0, 0, 0): a circular arc of radius c3/τ in the xy plane, curling
/// toward +y for τ > 0 (centre at (0, c3/τ, 0)).
#[test]
fn pure_bending_is_a_circular_arc() {
    let wire = WireParams::new([0.042, 0.055, 0.07], 0.63, 0.001).expect("valid");
    let rod = Rod::new(wire);
    for tau in [0.01, 0.1, -0.3, 1.0] {
        let radius = 0.07 / tau;
        let s = rod
            .solve(&Vector6::new(0.0, 0.0, tau, 0.0, 0.0, 0.0), 50)
            .expect("solves");
        for (p, t) in s.shape.positions.iter().zip(&s.shape.arc_length) {
            let expected = nalgebra::Vector3::new(
                radius * (t / radius).sin(),
                radius * (1.0 - (t / radius).cos()),
                0.0,
            );
            assert!(
                (p - expected).norm() < 1e-8 * wire.length(),
                "τ = {tau}, t = {t}: {p} vs {expected}"
            );
        }
        // The tangent turns by L/ρ about z.
        let angle = s.jacobian.tip.rotation.scaled_axis();
        let expected = wire.length() / radius;
        let wrapped = (expected + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI)
            - std::f64::consts::PI;
        assert!((angle.z - wrapped).abs() < 1e-8 && angle.xy().norm() < 1e-10);
    }
}

/// Solving in normalised units (c/c2, L = 1) and scaling back by L gives the same shape.
#[test]
fn normalised_units_give_the_same_shape() {
    let wire = WireParams::new([0.214, 0.278, 0.278], 0.91, 0.0015).expect("valid");
    let unit = WireParams::new([0.214 / 0.278, 1.0, 1.0], 1.0, 0.0015 / 0.91).expect("valid");
    for an in [
        Vector6::new(2.0, -5.0, 8.0, -10.0, 3.0, 6.0),
        Vector6::new(-1.0, 0.3, -0.2, 25.0, -12.0, 1.0),
    ] {
        let a = from_normalised(&wire, &an);
        assert!((to_normalised(&wire, &a) - an).norm() < 1e-12);
        let s = Rod::new(wire).solve(&a, 40).expect("solves");
        let u = Rod::new(unit).solve(&an, 40).expect("solves");
        for (p, q) in s.shape.positions.iter().zip(&u.shape.positions) {
            assert!((p / wire.length() - q).norm() < 1e-12);
        }
        assert_eq!(s.jacobian.stability.stable, u.jacobian.stability.stable);
        assert_eq!(s.self_intersecting, u.self_intersecting);
    }
}

/// Node frames (Hermite dense output) agree with the reference at interior nodes.
#[test]
fn shape_nodes_are_accurate_between_grid_points() {
    let wire = nitinol();
    let rod = Rod::new(wire);
    let a = from_normalised(&wire, &Vector6::new(4.0, -8.0, 10.0, -15.0, 6.0, 3.0));
    let shape = rod.shape(&a, 64).expect("solves");
    for i in [1, 7, 20, 33, 50, 62] {
        let r = common::reference_at(&wire, &a, shape.arc_length[i], 1e-12);
        let pose = shape.pose(i).expect("exists");
        assert!(
            (pose.translation.vector - r.pose.translation.vector).norm() < 1e-6 * wire.length()
        );
        assert!(pose.rotation.angle_to(&r.pose.rotation) < 1e-6);
    }
}

/// Each invalid input gives its own error, none panics.
#[test]
fn bad_input_gives_errors() {
    let rod = Rod::new(nitinol());
    let good = Vector6::new(0.0, 0.01, 0.02, -0.1, 0.0, 0.0);
    for (k, bad) in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY]
        .into_iter()
        .enumerate()
    {
        let mut a = good;
        a[k + 2] = bad;
        match rod.solve(&a, 64) {
            Err(RodError::Core(CoreError::NonFinite {
                field: "a", index, ..
            })) => assert_eq!(index, k + 2),
            other => panic!("expected NonFinite, got {other:?}"),
        }
        assert!(
            rod.is_stable(&a).is_err() && rod.shape(&a, 8).is_err() && rod.jacobian(&a).is_err()
        );
    }
    let outside = Vector6::new(0.3, 0.0, 0.0, -2.0, 0.0, 0.0);
    let err = rod.solve(&outside, 64).expect_err("outside A");
    assert!(matches!(err, RodError::OutsideA { .. }));
    assert!(err.to_string().contains("outside A"));
    assert!(matches!(
        rod.solve(&good, 1),
        Err(RodError::TooFewNodes { nodes: 1, .. })
    ));
    assert!(matches!(
        rod.shape(&good, 0),
        Err(RodError::TooFewNodes { nodes: 0, .. })
    ));
    assert!(matches!(
        rod.solve(&good, usize::MAX),
        Err(RodError::TooManyNodes { .. })
    ));
    assert!(matches!(
        Integrator::new(Method::Rk8, 0),
        Err(RodError::BadSteps { .. })
    ));
    // Huge but finite: an error or a finite answer, never a panic.
    let huge = Vector6::new(1e300, 1e300, -1e300, 1e300, 1e300, 1e300);
    if let Ok(s) = rod.solve(&huge, 64) {
        assert!(
            s.jacobian
                .tip
                .translation
                .vector
                .iter()
                .all(|v| v.is_finite())
        );
    }
    let _ = rod.is_stable(&huge);
}
