//! The loaded model (weight per length and rest strains; `ftwire_rod::load`): agreement with
//! the unloaded solver as the load vanishes, derivative checks, invariants, a rest arc, an
//! independent integration of the full loaded system, and bad input.

use ftwire_rod::{
    CoreError, Integrator, Load, Method, Rod, RodError, WireParams, from_normalised,
    sampling::Sampler, se3,
};
use nalgebra::{Matrix3, Matrix6, Rotation3, Translation3, UnitQuaternion, Vector3, Vector6};
use ode_solvers::{Dop853, SVector, System};
use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn nitinol_2mm() -> WireParams {
    WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid")
}

fn nitinol_3mm() -> WireParams {
    WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid")
}

/// The electric cable of ftwire-sim's presets: weight number ρAgL³/c2 ≈ 36.
fn cable() -> WireParams {
    WireParams::new([0.0030, 0.0045, 0.0045], 0.92, 0.0015).expect("valid")
}

/// An anisotropic wire (every coefficient of the equations non-zero).
fn anisotropic() -> WireParams {
    WireParams::new([1.3, 1.0, 0.6], 1.0, 0.001).expect("valid")
}

/// A fixed fine grid, so that the solution is smooth in `a` (for finite differences) and the
/// discretisation error far below the tolerances.
fn fine(wire: WireParams) -> Rod {
    Rod::new(wire).with_integrator(Integrator::new(Method::Dop853, 200).expect("valid"))
}

fn unit_vector<R: Rng>(rng: &mut R) -> Vector3<f64> {
    loop {
        let v = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        let n = v.norm();
        if n > 0.1 && n <= 1.0 {
            return v / n;
        }
    }
}

/// A random load: gravity of `g` m/s² in a random direction on a wire of density `density`,
/// and rest strains up to `kappa` 1/m per component.
fn random_load<R: Rng>(rng: &mut R, wire: &WireParams, density: f64, g: f64, kappa: f64) -> Load {
    let gravity = unit_vector(rng) * g;
    let k = Vector3::from_fn(|_, _| rng.random_range(-kappa..=kappa));
    Load::from_gravity(density, wire.radius(), gravity)
        .expect("valid")
        .with_natural_curvature(k)
        .expect("finite")
}

fn normalised<R: Rng>(rng: &mut R, half_width: f64) -> Vector6<f64> {
    Sampler::new(half_width)
        .expect("positive")
        .sample_normalised(rng)
}

// ---------------------------------------------------------------------------------------------
// The independent reference: the full loaded system, 90 states, by ode_solvers' Dop853, written
// from DESIGN.md's general forms with full 6×6 matrices (not the solver's blocks).

struct LoadedFull {
    c: [f64; 3],
    w: Vector3<f64>,
    u0: Vector3<f64>,
}

type Y = SVector<f64, 90>;

impl System<f64, Y> for LoadedFull {
    fn system(&self, _t: f64, y: &Y, dy: &mut Y) {
        let m = Vector3::new(y[0], y[1], y[2]);
        let n = Vector3::new(y[3], y[4], y[5]);
        let r = Matrix3::from_fn(|i, j| y[6 + 3 * j + i]);
        let mm = Matrix6::from_fn(|i, j| y[18 + 6 * j + i]);
        let jj = Matrix6::from_fn(|i, j| y[54 + 6 * j + i]);
        let inv_c = Matrix3::from_diagonal(&Vector3::new(
            1.0 / self.c[0],
            1.0 / self.c[1],
            1.0 / self.c[2],
        ));
        let u = inv_c * m + self.u0;
        let e1 = Vector3::x();
        let rw = r.transpose() * self.w;
        let dm = m.cross(&u) + n.cross(&e1);
        let dn = n.cross(&u) - rw;
        let dr = r * se3::hat(&u);
        let dp = r * e1;
        let mut f = Matrix6::zeros();
        f.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(se3::hat(&m) * inv_c - se3::hat(&u)));
        f.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-se3::hat(&e1)));
        f.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&(se3::hat(&n) * inv_c));
        f.fixed_view_mut::<3, 3>(3, 3).copy_from(&(-se3::hat(&u)));
        let mut e = Matrix6::zeros();
        e.fixed_view_mut::<3, 3>(3, 0).copy_from(&(-se3::hat(&rw)));
        let mut g = Matrix6::zeros();
        g.fixed_view_mut::<3, 3>(0, 0).copy_from(&inv_c);
        let mut h = Matrix6::zeros();
        h.fixed_view_mut::<3, 3>(0, 0).copy_from(&(-se3::hat(&u)));
        h.fixed_view_mut::<3, 3>(3, 0).copy_from(&(-se3::hat(&e1)));
        h.fixed_view_mut::<3, 3>(3, 3).copy_from(&(-se3::hat(&u)));
        let dmm = f * mm + e * jj;
        let djj = g * mm + h * jj;
        for i in 0..3 {
            dy[i] = dm[i];
            dy[3 + i] = dn[i];
            dy[15 + i] = dp[i];
            for j in 0..3 {
                dy[6 + 3 * j + i] = dr[(i, j)];
            }
        }
        for j in 0..6 {
            for i in 0..6 {
                dy[18 + 6 * j + i] = dmm[(i, j)];
                dy[54 + 6 * j + i] = djj[(i, j)];
            }
        }
    }
}

/// The reference solution at one arc length.
struct Reference {
    mu: Vector6<f64>,
    pose: ftwire_rod::Pose,
    m: Matrix6<f64>,
    j: Matrix6<f64>,
}

fn reference_at(wire: &WireParams, load: &Load, a: &Vector6<f64>, t: f64) -> Reference {
    let mut y0 = Y::zeros();
    for i in 0..6 {
        y0[i] = a[i];
        y0[18 + 7 * i] = 1.0;
    }
    for i in 0..3 {
        y0[6 + 4 * i] = 1.0;
    }
    let system = LoadedFull {
        c: wire.c(),
        w: load.weight_per_length,
        u0: load.natural_curvature,
    };
    let mut stepper = Dop853::new(system, 0.0, t, t, y0, 1e-13, 1e-13);
    stepper.set_output(ode_solvers::OutputType::Sparse);
    stepper.integrate().expect("reference integration");
    let y = *stepper.y_out().last().expect("an output");
    let rotation = Rotation3::from_matrix(&Matrix3::from_fn(|i, j| y[6 + 3 * j + i]));
    Reference {
        mu: Vector6::from_fn(|i, _| y[i]),
        pose: ftwire_rod::Pose::from_parts(
            Translation3::new(y[15], y[16], y[17]),
            UnitQuaternion::from_rotation_matrix(&rotation),
        ),
        m: Matrix6::from_fn(|i, j| y[18 + 6 * j + i]),
        j: Matrix6::from_fn(|i, j| y[54 + 6 * j + i]),
    }
}

// ---------------------------------------------------------------------------------------------
// 1. Load::none() is the unloaded solver, bit for bit.

#[test]
fn zero_load_is_bit_identical() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for wire in [nitinol_2mm(), anisotropic()] {
        let rod = Rod::new(wire);
        let none = rod.with_load(Load::none());
        assert_eq!(none, rod);
        assert!(none.load().is_none());
        for _ in 0..20 {
            let a = from_normalised(&wire, &normalised(&mut rng, 30.0));
            assert_eq!(
                none.solve(&a, 64).expect("in A"),
                rod.solve(&a, 64).expect("in A")
            );
            assert_eq!(
                none.solve(&a, 7).expect("in A"),
                rod.solve(&a, 7).expect("in A")
            );
            assert_eq!(
                none.jacobian(&a).expect("in A"),
                rod.jacobian(&a).expect("in A")
            );
            assert_eq!(
                none.shape(&a, 33).expect("in A"),
                rod.shape(&a, 33).expect("in A")
            );
            assert_eq!(none.tip(&a).expect("in A"), rod.tip(&a).expect("in A"));
            assert_eq!(
                none.is_stable(&a).expect("in A"),
                rod.is_stable(&a).expect("in A")
            );
            assert_eq!(
                none.steps_for_configuration(&a).expect("in A"),
                rod.steps_for_configuration(&a).expect("in A")
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 2. A vanishing load: the loaded path (the full system, integrated) against the unloaded one
//    (closed forms), on the same fine grid.

#[test]
fn tiny_load_matches_the_unloaded_solver() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut worst = [0.0f64; 6];
    let mut verdicts = [0usize; 2];
    for wire in [nitinol_2mm(), nitinol_3mm(), anisotropic()] {
        let rod = fine(wire);
        let sampler = Sampler::new(30.0).expect("positive");
        for trial in 0..30 {
            let load = Load {
                weight_per_length: unit_vector(&mut rng) * 1e-12,
                natural_curvature: unit_vector(&mut rng) * 1e-12,
            };
            let loaded = rod.with_load(load);
            // Half stable (rejection-sampled), half uniform in A (mostly unstable).
            let a = if trial % 2 == 0 {
                sampler
                    .sample_stable(&rod, &mut rng)
                    .expect("stable sample")
            } else {
                from_normalised(&wire, &normalised(&mut rng, 30.0))
            };
            let (s, l) = (
                rod.solve(&a, 40).expect("in A"),
                loaded.solve(&a, 40).expect("in A"),
            );
            let (sj, lj) = (&s.jacobian, &l.jacobian);
            let length = wire.length();
            let errors = [
                (sj.tip.translation.vector - lj.tip.translation.vector).norm() / length,
                sj.tip.rotation.angle_to(&lj.tip.rotation),
                (sj.jacobian - lj.jacobian).amax() / sj.jacobian.amax(),
                (sj.m - lj.m).amax() / sj.m.amax(),
                s.shape
                    .positions
                    .iter()
                    .zip(&l.shape.positions)
                    .map(|(p, q)| (p - q).norm() / length)
                    .fold(0.0, f64::max),
                s.costate
                    .iter()
                    .zip(&l.costate)
                    .map(|(p, q)| (p - q).amax() / a.amax())
                    .fold(0.0, f64::max),
            ];
            for (w, e) in worst.iter_mut().zip(errors) {
                *w = w.max(e);
            }
            for (what, e) in ["tip", "rotation", "J", "M", "shape", "costate"]
                .iter()
                .zip(errors)
            {
                assert!(e < 1e-9, "{what}: {e:e} at a = {a:?}");
            }
            let stable = sj.stability.stable;
            assert_eq!(stable, lj.stability.stable, "a = {a:?}");
            assert_eq!(stable, loaded.is_stable(&a).expect("in A"), "a = {a:?}");
            assert_eq!(sj.stability.det_j.len(), lj.stability.det_j.len());
            verdicts[usize::from(stable)] += 1;
        }
    }
    eprintln!(
        "tiny load vs none: worst tip {:.1e} L, rot {:.1e}, J {:.1e}, M {:.1e}, shape {:.1e} L, \
         costate {:.1e}; {} stable, {} unstable",
        worst[0], worst[1], worst[2], worst[3], worst[4], worst[5], verdicts[1], verdicts[0]
    );
    assert!(
        verdicts[0] > 0 && verdicts[1] > 0,
        "both verdicts exercised"
    );
}

// ---------------------------------------------------------------------------------------------
// 3. Derivative checks with gravity and rest curvature.

/// `J(L)` against central differences of `log(q(L)⁻¹ q_{a ± h e_k}(L))`, and `M(L)` against
/// central differences of `μ(L)`.
#[test]
fn loaded_jacobian_and_m_match_finite_differences() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (mut worst_j, mut worst_m) = (0.0f64, 0.0f64);
    for (wire, density) in [
        (nitinol_2mm(), 6450.0),
        (nitinol_3mm(), 6450.0),
        (cable(), 3000.0),
        (anisotropic(), 60000.0),
    ] {
        for _ in 0..8 {
            let load = random_load(&mut rng, &wire, density, 9.81, 2.0 / wire.length());
            let rod = fine(wire).with_load(load);
            let a = from_normalised(&wire, &normalised(&mut rng, 10.0));
            let solution = rod.jacobian(&a).expect("solves");
            let tip = solution.tip;
            let mut fd_j = Matrix6::zeros();
            let mut fd_m = Matrix6::zeros();
            for k in 0..6 {
                let scale = if k < 3 {
                    wire.torque_scale()
                } else {
                    wire.force_scale()
                };
                let h = 1e-5 * scale;
                let (mut ap, mut am) = (a, a);
                ap[k] += h;
                am[k] -= h;
                let (sp, sm) = (
                    rod.jacobian(&ap).expect("solves"),
                    rod.jacobian(&am).expect("solves"),
                );
                let xp = se3::log(&(tip.inverse() * sp.tip));
                let xm = se3::log(&(tip.inverse() * sm.tip));
                fd_j.set_column(k, &((xp - xm) / (2.0 * h)));
                fd_m.set_column(k, &((sp.costate_tip - sm.costate_tip) / (2.0 * h)));
            }
            for k in 0..6 {
                let ej = (solution.jacobian.column(k) - fd_j.column(k)).amax()
                    / fd_j.column(k).amax().max(1e-12);
                let em = (solution.m.column(k) - fd_m.column(k)).amax()
                    / fd_m.column(k).amax().max(1e-12);
                worst_j = worst_j.max(ej);
                worst_m = worst_m.max(em);
                assert!(ej < 1e-5, "J column {k}: {ej:e}, a = {a:?}, {load:?}");
                assert!(em < 1e-5, "M column {k}: {em:e}, a = {a:?}, {load:?}");
            }
        }
    }
    eprintln!("loaded J(L) vs FD: worst {worst_j:.1e}; M(L) vs FD: worst {worst_m:.1e}");
}

// ---------------------------------------------------------------------------------------------
// 4. Invariants along the wire.

/// At every node: the base-frame force `R n = a_f − w t`; the spatial moment balance
/// `R m + p × N + (∫₀ᵗ p) × w = a_m` (∫p by Simpson's rule on the dense nodes); and the
/// Hamiltonian `½ m·C⁻¹m + m·u₀ + n1 + w·p` is constant. (`μ` at the nodes comes from the
/// loaded closed form, so the first two check its assembly and the interpolation of `∫p`; at
/// the tip, `μ(L)` is the integrated one, and all three are checked there too.)
#[test]
fn loaded_invariants_hold_along_the_wire() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut worst = [0.0f64; 4];
    for (wire, density) in [
        (nitinol_2mm(), 6450.0),
        (cable(), 3000.0),
        (anisotropic(), 60000.0),
    ] {
        let c = wire.c();
        for _ in 0..6 {
            let load = random_load(&mut rng, &wire, density, 9.81, 2.0);
            let rod = Rod::new(wire).with_load(load);
            let a = from_normalised(&wire, &normalised(&mut rng, 10.0));
            let s = rod.solve(&a, 2001).expect("solves");
            let (w, u0) = (load.weight_per_length, load.natural_curvature);
            let af = a.fixed_rows::<3>(3).into_owned();
            let am = a.fixed_rows::<3>(0).into_owned();
            let length = wire.length();
            let force_scale = af.norm() + w.norm() * length;
            let moment_scale = am.norm() + force_scale * length;
            let hamiltonian = |mu: &Vector6<f64>, p: &Vector3<f64>| {
                0.5 * (mu[0] * mu[0] / c[0] + mu[1] * mu[1] / c[1] + mu[2] * mu[2] / c[2])
                    + mu.fixed_rows::<3>(0).dot(&u0)
                    + mu[3]
                    + w.dot(p)
            };
            let h0 = hamiltonian(&a, &Vector3::zeros());
            let energy_scale = moment_scale * moment_scale / c[0].min(c[1]).min(c[2])
                + force_scale
                + moment_scale * u0.norm();
            let dt = s.shape.spacing();
            let mut integral = Vector3::zeros();
            for (i, ((mu, r), p)) in s
                .costate
                .iter()
                .zip(&s.shape.rotations)
                .zip(&s.shape.positions)
                .enumerate()
            {
                let t = s.shape.arc_length[i];
                let n_base = r * mu.fixed_rows::<3>(3);
                let force_gap = (n_base - (af - w * t)).norm() / force_scale;
                let energy_gap = (hamiltonian(mu, p) - h0).abs() / energy_scale;
                worst[0] = worst[0].max(force_gap);
                worst[2] = worst[2].max(energy_gap);
                assert!(force_gap < 1e-8, "R n − N at t = {t}: {force_gap:e}");
                assert!(energy_gap < 1e-8, "H at t = {t}: {energy_gap:e}");
                if i % 2 == 0 {
                    if i > 0 {
                        let (p0, p1) = (&s.shape.positions[i - 2], &s.shape.positions[i - 1]);
                        integral += (p0 + 4.0 * p1 + p) * (dt / 3.0);
                    }
                    let spatial = r * mu.fixed_rows::<3>(0) + p.cross(&n_base) + integral.cross(&w);
                    let moment_gap = (spatial - am).norm() / moment_scale;
                    worst[1] = worst[1].max(moment_gap);
                    assert!(
                        moment_gap < 1e-8,
                        "moment balance at t = {t}: {moment_gap:e}"
                    );
                }
            }
            // The integrated μ(L), with the tip frame of the Jacobian solve.
            let tip = &s.jacobian;
            let r = tip.tip.rotation.to_rotation_matrix();
            let p = tip.tip.translation.vector;
            let n_base = r * tip.costate_tip.fixed_rows::<3>(3);
            let force_gap = (n_base - (af - w * length)).norm() / force_scale;
            let spatial =
                r * tip.costate_tip.fixed_rows::<3>(0) + p.cross(&n_base) + integral.cross(&w);
            let moment_gap = (spatial - am).norm() / moment_scale;
            let energy_gap = (hamiltonian(&tip.costate_tip, &p) - h0).abs() / energy_scale;
            worst[3] = worst[3].max(force_gap).max(moment_gap).max(energy_gap);
            assert!(force_gap < 1e-8, "R n − N at the tip: {force_gap:e}");
            assert!(
                moment_gap < 1e-8,
                "moment balance at the tip: {moment_gap:e}"
            );
            assert!(energy_gap < 1e-8, "H at the tip: {energy_gap:e}");
        }
    }
    eprintln!(
        "invariants: worst force {:.1e}, moment {:.1e}, Hamiltonian {:.1e} (relative); \
         integrated μ(L): {:.1e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}

// ---------------------------------------------------------------------------------------------
// 5. Reference cases.

/// No weight, rest curvature `u₀ = (0, 0, κ)` and a vanishing `a` (in `A`): the wire is its
/// rest shape, a circular arc of radius `1/κ` curling toward +y, and `μ` stays ≈ 0.
#[test]
fn rest_curvature_alone_is_a_circular_arc() {
    let wire = WireParams::new([0.042, 0.055, 0.07], 0.63, 0.001).expect("valid");
    for kappa in [0.5, 3.0, -7.0, 12.0] {
        let load = Load::none()
            .with_natural_curvature(Vector3::new(0.0, 0.0, kappa))
            .expect("finite");
        let rod = Rod::new(wire).with_load(load);
        let a = Vector6::new(0.0, 0.0, 1e-15, 0.0, 0.0, 0.0);
        let s = rod.solve(&a, 50).expect("solves");
        let radius = 1.0 / kappa;
        for (p, t) in s.shape.positions.iter().zip(&s.shape.arc_length) {
            let expected = Vector3::new(
                radius * (t / radius).sin(),
                radius * (1.0 - (t / radius).cos()),
                0.0,
            );
            assert!(
                (p - expected).norm() < 1e-9 * wire.length(),
                "κ = {kappa}, t = {t}: {p} vs {expected}"
            );
        }
        assert!(s.costate.iter().all(|mu| mu.amax() < 1e-12));
        let angle = s.jacobian.tip.rotation.scaled_axis();
        let turned = kappa * wire.length();
        let expected = (turned + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI)
            - std::f64::consts::PI;
        assert!(
            (angle.z - expected).abs() < 1e-9 && angle.xy().norm() < 1e-12,
            "κ = {kappa}: {angle} vs {expected}"
        );
    }
}

/// The default integrator under load meets the crate's accuracy requirement (tip position
/// 1e-6·L, rotation 1e-6 rad, `J(L)` 1e-5 relative) against the independent Dop853 reference,
/// on stable configurations with gravity in random directions up to weight number
/// ρAgL³/c2 ≈ 36 (the cable, with its rest curvature), and `μ`, `M` with it.
#[test]
fn default_integrator_meets_the_accuracy_requirement_under_load() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut worst = [0.0f64; 5];
    let cable_rest = Vector3::new(0.0, 0.0, 1.5);
    /// Wire, density [kg/m³], |g| [m/s²], rest strains, sampling half-width.
    type Case = (WireParams, f64, f64, Option<Vector3<f64>>, f64);
    let cases: [Case; 5] = [
        (nitinol_2mm(), 6450.0, 9.81, None, 30.0),
        (nitinol_3mm(), 6450.0, 9.81, None, 30.0),
        (cable(), 3000.0, 9.81, Some(cable_rest), 10.0),
        (cable(), 3000.0, 30.0, Some(cable_rest), 10.0),
        (anisotropic(), 60000.0, 9.81, None, 30.0),
    ];
    for (wire, density, g, rest, half_width) in cases {
        let sampler = Sampler::new(half_width).expect("positive");
        for _ in 0..8 {
            let mut load = random_load(&mut rng, &wire, density, g, 2.0);
            if let Some(k) = rest {
                load = load.with_natural_curvature(k).expect("finite");
            }
            let rod = Rod::new(wire).with_load(load);
            let a = sampler
                .sample_stable(&rod, &mut rng)
                .expect("stable sample");
            let reference = reference_at(&wire, &load, &a, wire.length());
            let s = rod.solve(&a, 64).expect("solves");
            let jac = &s.jacobian;
            let e = [
                (jac.tip.translation.vector - reference.pose.translation.vector).norm()
                    / wire.length(),
                jac.tip.rotation.angle_to(&reference.pose.rotation),
                (jac.jacobian - reference.j).amax() / reference.j.amax(),
                (jac.m - reference.m).amax() / reference.m.amax(),
                (jac.costate_tip - reference.mu).amax() / reference.mu.amax().max(a.amax()),
            ];
            let tip_alone = rod.tip(&a).expect("solves");
            let shape_gap = (tip_alone.translation.vector - reference.pose.translation.vector)
                .norm()
                / wire.length();
            let shape_rot = tip_alone.rotation.angle_to(&reference.pose.rotation);
            let ctx = format!("c = {:?}, a = {a:?}, {load:?}", wire.c());
            assert!(e[0] < 1e-6, "tip {:e} L: {ctx}", e[0]);
            assert!(e[1] < 1e-6, "rotation {:e}: {ctx}", e[1]);
            assert!(e[2] < 1e-5, "J(L) {:e}: {ctx}", e[2]);
            assert!(e[3] < 1e-5, "M(L) {:e}: {ctx}", e[3]);
            assert!(e[4] < 1e-6, "μ(L) {:e}: {ctx}", e[4]);
            assert!(
                shape_gap < 1e-6 && shape_rot < 1e-6,
                "shape-only tip: {ctx}"
            );
            for (w, v) in worst.iter_mut().zip(e) {
                *w = w.max(v);
            }
            // An interior node (between grid points) and its costate.
            let i = 21;
            let r = reference_at(&wire, &load, &a, s.shape.arc_length[i]);
            let gap = (s.shape.positions[i] - r.pose.translation.vector).norm() / wire.length();
            let pose = s.shape.pose(i).expect("exists");
            assert!(gap < 1e-6, "node {i}: {gap:e} L: {ctx}");
            assert!(pose.rotation.angle_to(&r.pose.rotation) < 1e-6, "{ctx}");
            let mu_gap = (s.costate[i] - r.mu).amax() / r.mu.amax().max(a.amax());
            assert!(mu_gap < 1e-6, "μ at node {i}: {mu_gap:e}: {ctx}");
        }
    }
    eprintln!(
        "default integrator under load: worst tip {:.1e} L, rot {:.1e} rad, J {:.1e}, M {:.1e}, \
         μ(L) {:.1e}",
        worst[0], worst[1], worst[2], worst[3], worst[4]
    );
}

// ---------------------------------------------------------------------------------------------
// 6. Bad input.

#[test]
fn bad_load_input_gives_errors_naming_the_value() {
    let g = Vector3::new(0.0, 0.0, -9.81);
    let not_positive = |r: Result<Load, RodError>, name: &str| match r {
        Err(e @ RodError::Core(CoreError::NotPositive { field, .. })) => {
            assert_eq!(field, name);
            assert!(e.to_string().contains(name), "{e}");
        }
        other => panic!("expected NotPositive {name}, got {other:?}"),
    };
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        not_positive(Load::from_gravity(bad, 0.001, g), "density");
        not_positive(Load::from_gravity(6450.0, bad, g), "radius");
    }
    for (k, bad) in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY]
        .into_iter()
        .enumerate()
    {
        let mut v = g;
        v[k] = bad;
        match Load::from_gravity(6450.0, 0.001, v) {
            Err(
                e @ RodError::Core(CoreError::NonFinite {
                    field: "gravity",
                    index,
                    ..
                }),
            ) => {
                assert_eq!(index, k);
                assert!(e.to_string().contains("gravity"));
            }
            other => panic!("expected NonFinite gravity, got {other:?}"),
        }
        match Load::none().with_natural_curvature(v) {
            Err(RodError::Core(CoreError::NonFinite {
                field: "natural_curvature",
                index,
                ..
            })) => assert_eq!(index, k),
            other => panic!("expected NonFinite natural_curvature, got {other:?}"),
        }
    }
    // Finite inputs whose product overflows.
    assert!(matches!(
        Load::from_gravity(1e300, 1e10, g),
        Err(RodError::Core(CoreError::NonFinite {
            field: "weight_per_length",
            ..
        }))
    ));
    // A Load built by hand with a non-finite field is rejected by every solve.
    let rod = Rod::new(nitinol_2mm()).with_load(Load {
        weight_per_length: Vector3::new(0.0, f64::NAN, 0.0),
        natural_curvature: Vector3::zeros(),
    });
    let a = Vector6::new(0.0, 0.01, 0.02, -0.1, 0.0, 0.0);
    let named = |r: Result<(), RodError>| {
        matches!(
            r,
            Err(RodError::Core(CoreError::NonFinite {
                field: "weight_per_length",
                index: 1,
                ..
            }))
        )
    };
    assert!(named(rod.solve(&a, 8).map(|_| ())));
    assert!(named(rod.shape(&a, 8).map(|_| ())));
    assert!(named(rod.tip(&a).map(|_| ())));
    assert!(named(rod.jacobian(&a).map(|_| ())));
    assert!(named(rod.is_stable(&a).map(|_| ())));
    assert!(named(rod.steps_for_configuration(&a).map(|_| ())));
    // The configuration is still checked first under a load, and A is unchanged.
    let loaded =
        Rod::new(nitinol_2mm()).with_load(Load::from_gravity(6450.0, 0.001, g).expect("valid"));
    assert!(matches!(
        loaded.solve(&Vector6::zeros(), 8),
        Err(RodError::OutsideA { .. })
    ));
    assert!(matches!(
        loaded.solve(&Vector6::new(f64::NAN, 0.0, 0.1, 0.0, 0.0, 0.0), 8),
        Err(RodError::Core(CoreError::NonFinite { field: "a", .. }))
    ));
    assert!(matches!(
        loaded.solve(&a, 1),
        Err(RodError::TooFewNodes { .. })
    ));
}
