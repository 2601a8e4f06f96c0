//! Shared test helpers: the independent reference solution.
#![allow(dead_code)]

use ftwire_rod::{Pose, WireParams, f_matrix, g_matrix, h_matrix};
use nalgebra::{Matrix3, Matrix6, Rotation3, Translation3, UnitQuaternion, Vector3, Vector6};
use ode_solvers::{Dop853, SVector, System};

/// The full paper system, 90 states: μ (eq. 3), R and p (eq. 1), M and J (eq. 4), integrated
/// by `ode_solvers`' adaptive Dop853 — independent of the solver's closed forms.
struct Full {
    c: [f64; 3],
}

type Y = SVector<f64, 90>;

impl System<f64, Y> for Full {
    fn system(&self, _t: f64, y: &Y, dy: &mut Y) {
        let mu = Vector6::from_fn(|i, _| y[i]);
        let r = Matrix3::from_fn(|i, j| y[6 + 3 * j + i]);
        let m = Matrix6::from_fn(|i, j| y[18 + 6 * j + i]);
        let jm = Matrix6::from_fn(|i, j| y[54 + 6 * j + i]);
        let dmu = ftwire_rod::costate_rate(self.c, &mu);
        let u = Vector3::new(mu[0] / self.c[0], mu[1] / self.c[1], mu[2] / self.c[2]);
        let dr = r * ftwire_rod::se3::hat(&u);
        let dp = r.column(0).into_owned();
        let dm = f_matrix(self.c, &mu) * m;
        let dj = g_matrix(self.c) * m + h_matrix(self.c, &mu) * jm;
        for i in 0..6 {
            dy[i] = dmu[i];
        }
        for j in 0..3 {
            for i in 0..3 {
                dy[6 + 3 * j + i] = dr[(i, j)];
            }
        }
        for i in 0..3 {
            dy[15 + i] = dp[i];
        }
        for j in 0..6 {
            for i in 0..6 {
                dy[18 + 6 * j + i] = dm[(i, j)];
                dy[54 + 6 * j + i] = dj[(i, j)];
            }
        }
    }
}

/// The reference solution at one arc length.
#[derive(Debug, Clone)]
pub struct Reference {
    pub mu: Vector6<f64>,
    pub pose: Pose,
    pub rotation: Matrix3<f64>,
    pub m: Matrix6<f64>,
    pub j: Matrix6<f64>,
}

/// The reference at `t` (0 < t ≤ L), tolerance `tol` (relative and absolute).
pub fn reference_at(wire: &WireParams, a: &Vector6<f64>, t: f64, tol: f64) -> Reference {
    let mut y0 = Y::zeros();
    for i in 0..6 {
        y0[i] = a[i];
    }
    for i in 0..3 {
        y0[6 + 4 * i] = 1.0;
    }
    for i in 0..6 {
        y0[18 + 7 * i] = 1.0;
    }
    let mut stepper = Dop853::new(Full { c: wire.c() }, 0.0, t, t, y0, tol, tol);
    stepper.set_output(ode_solvers::OutputType::Sparse);
    stepper.integrate().expect("reference integration");
    let y = *stepper.y_out().last().expect("an output");
    let rotation = Matrix3::from_fn(|i, j| y[6 + 3 * j + i]);
    let r = Rotation3::from_matrix(&rotation);
    Reference {
        mu: Vector6::from_fn(|i, _| y[i]),
        pose: Pose::from_parts(
            Translation3::new(y[15], y[16], y[17]),
            UnitQuaternion::from_rotation_matrix(&r),
        ),
        rotation,
        m: Matrix6::from_fn(|i, j| y[18 + 6 * j + i]),
        j: Matrix6::from_fn(|i, j| y[54 + 6 * j + i]),
    }
}

/// The reference at the tip.
pub fn reference(wire: &WireParams, a: &Vector6<f64>) -> Reference {
    reference_at(wire, a, wire.length(), 1e-13)
}

/// Errors of a solution against the reference: tip position / L, tip rotation [rad],
/// J(L) relative in max-norm.
pub fn errors(
    wire: &WireParams,
    tip: &Pose,
    j: &Matrix6<f64>,
    reference: &Reference,
) -> (f64, f64, f64) {
    let dp = (tip.translation.vector - reference.pose.translation.vector).norm() / wire.length();
    let dr = tip.rotation.angle_to(&reference.pose.rotation);
    let scale = reference.j.amax();
    let dj = (j - reference.j).amax() / scale;
    (dp, dr, dj)
}
