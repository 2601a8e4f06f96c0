//! The stability test of paper §II-A (Bretl & McCarthy 2014): `a ∈ A_stable` iff
//! `det J(t) ≠ 0` on `(0, L]`, tested as "`det J(t)` keeps one sign on `[h, L]`" (`h` the grid
//! spacing): at every grid point, and between them.
//!
//! # Between the grid points
//!
//! A test at the grid points alone depends on where the integrator steps. Two conjugate points
//! close together (a near-double root of `det J`, common on a round wire, whose two bending
//! planes buckle alike) make `det J` dip below zero and come back within one step, and the
//! wire passes such a test. So each step `[t_k, t_(k+1)]` from `t = h` on is tested as a
//! whole, on
//!
//! ```text
//! g(t) = det J(t) / (t/h)¹⁴,
//! ```
//!
//! which has the sign of `det J` on `(0, L]` without its zero of order 14 at `t = 0` (below),
//! so that a polynomial follows it over a step near the base too.
//!
//! 1. At each grid point, `g` and `g′` come from one elimination carried to first order
//!    (`between::determinant_and_derivative`), by Jacobi's formula
//!    `(det J)′ = tr(adj J · J′)`. `J′ = B(q) + A J` (eq. 4; closed form (B) makes it linear
//!    in `J`), and `tr(adj J · A J) = det J · tr A = 0` because `A` has a zero diagonal, so
//!    only `B`, three rows read from the frame, enters (`JacobianState::first_order`). The
//!    value is the `det J` recorded at the grid point.
//! 2. The step clearly keeps its sign if the cubic Hermite interpolant of these values and
//!    slopes stays above the smaller of its end values (its Bernstein coefficients do;
//!    `between::clearly_keeps_sign`). A sign change between two grid points of one sign needs
//!    `g` to turn back towards zero inside the step; near a fold `g` is nearly a parabola
//!    there, which the cubic follows exactly, down below its ends.
//! 3. Any other step gets the septic test. `J′, J″, J‴` at both grid points follow from the
//!    state there (differentiating the linear equation for `J`;
//!    `JacobianState::series`); the Taylor series of `det J` from Gaussian elimination in
//!    truncated Taylor arithmetic with complete pivoting, which never divides by a vanishing
//!    `det J` and so stays accurate at a fold (`between::determinant_series`); and the septic
//!    Hermite interpolant of `g` (error `O(h⁸)`, the integrator's order) is searched in
//!    Bernstein form for a point of the opposite sign, halving the step down to `2⁻¹⁰` of it
//!    (`between::changes_sign`). Where `det J` touches zero and comes back, the test says
//!    "unstable" as soon as the interpolant's dip below zero shows at that scale.
//!
//! Most steps end at step 2, so the septic test runs on few of them (the cost is in
//! `docs/integrator.md`). The loaded solver takes the same test with its own `J′` (its
//! `JacobianState`). Guarded by `dips_between_grid_points_are_unstable` (configurations on a
//! line in `A` through a fold, where `det J` dips below zero inside one step while all grid
//! points agree in sign: unstable, as a dense reference says) and
//! `agrees_with_a_dense_reference` (random configurations, unloaded and loaded) in
//! `tests/stability.rs`, and by the unit tests of the pieces.
//!
//! The first step, `(0, h]`, is not searched: `det J` vanishes like `t¹⁴` at `t = 0`, and its
//! sign at `t = h` is the reference.
//!
//! # The first step
//!
//! `det J(t)` vanishes like `t¹⁴` at `t = 0` (the base cannot be displaced along the tangent to
//! first order), so its sign at the first grid point is decided by high-order terms of `J`.
//! One RK4 step from `J(0) = 0` is exact only for polynomials of degree 4 and gets that sign
//! wrong, which makes a naive test call every configuration unstable. The default
//! [`Method::Dop853`](crate::Method::Dop853) (as [`Method::Rk8`](crate::Method::Rk8)) is exact
//! to degree 8 on the first step, and its sign at the first grid point agrees with a fine
//! reference over random configurations (test `first_step_sign_matches_a_fine_reference` in
//! `tests/stability.rs`, which also shows the RK4 failure). In addition the first step is
//! always split into [`FIRST_STEP_SUBSTEPS`] substeps, which cuts the error of `det J` at the
//! first grid point by about two orders of magnitude for one extra step (measurements in
//! `docs/integrator.md`).

pub(crate) mod between;
mod jacobian_series;

pub use crate::integrator::FIRST_STEP_SUBSTEPS;
use between::Taylor;
pub(crate) use jacobian_series::{
    JacobianState, MatrixSeries, Rows, axpy, combine, cross, times_e1,
};

/// The outcome of the stability test along the wire.
#[derive(Debug, Clone, PartialEq)]
pub struct Stability {
    /// `true` iff `det J` kept one sign (and stayed non-zero and finite) at every grid point
    /// and between them (see the module docs).
    pub stable: bool,
    /// Smallest `|det J(t)|` over the grid points tested, and the point between them where
    /// the test found the opposite sign, if it did.
    pub det_j_min: f64,
    /// The grid interval `[t_(k−1), t_k]` \[m\] containing the first sign change of `det J`,
    /// if any: the first conjugate point lies in it. When `det J` dips below zero inside
    /// one step, both ends of that step have the same sign.
    pub first_sign_change: Option<[f64; 2]>,
    /// `det J(t_k)` at the grid points `t_k = k L / steps`, `k = 1, 2, …` (up to the early
    /// exit, if one was taken). Empty when not recorded.
    pub det_j: Vec<f64>,
    /// Grid spacing `L / steps` \[m\].
    pub spacing: f64,
}

/// The last grid point, for the test of the step that ends at the next one.
#[derive(Debug, Clone)]
struct Knot<const D: usize> {
    /// The solver's state there.
    state: [f64; D],
    /// `g` and `h g′` there.
    g: [f64; 2],
    /// The Taylor series of `g` there, if the test of the step before needed it.
    series: Option<Taylor>,
}

/// Tracks the sign of `det J` along the grid of a solver with states of `D` numbers: at the
/// grid points, and between neighbouring grid points from `t = h` on (see the module docs).
#[derive(Debug, Clone)]
pub(crate) struct SignTracker<const D: usize> {
    reference: f64,
    stable: bool,
    first_change: Option<[f64; 2]>,
    min_abs: f64,
    det_j: Option<Vec<f64>>,
    spacing: f64,
    previous: Option<Knot<D>>,
}

impl<const D: usize> SignTracker<D> {
    /// A tracker for a grid of `points` points after `t = 0`, spaced `spacing`; `record` keeps
    /// every `det J` (room for all of them is reserved at once).
    pub fn new(spacing: f64, points: usize, record: bool) -> Self {
        Self {
            reference: 0.0,
            stable: true,
            first_change: None,
            min_abs: f64::INFINITY,
            det_j: record.then(|| Vec::with_capacity(points)),
            spacing,
            previous: None,
        }
    }

    /// Records grid point `index` (`t = index · spacing`, `index ≥ 1`, every index in turn)
    /// with the solver's state `y` there: `det J` and its sign, then the step from the
    /// previous grid point. Returns whether the wire is still stable.
    #[inline(always)]
    pub fn push(&mut self, index: usize, y: &[f64; D], model: &impl JacobianState<D>) -> bool {
        let (j, x) = model.first_order(y);
        let (det, slope) = between::determinant_and_derivative(j, x);
        self.record(index, det);
        if self.stable {
            // g = det J (t/h)⁻¹⁴ and h g′, in the step's unit θ.
            let power = between::inverse_power_14(index);
            let g = [
                det * power[0],
                self.spacing * slope * power[0] + det * power[1],
            ];
            self.test_step(index, y, g, model);
        }
        self.stable
    }

    /// `det J` at grid point `index`: recorded, and its sign against the first grid point's.
    #[inline(always)]
    fn record(&mut self, index: usize, det: f64) {
        let t = index as f64 * self.spacing;
        if let Some(v) = &mut self.det_j {
            v.push(det);
        }
        self.min_abs = self.min_abs.min(det.abs());
        let sign = if det.is_finite() { det.signum() } else { 0.0 };
        if det == 0.0 || sign == 0.0 {
            self.fail(t);
        } else if self.reference == 0.0 {
            self.reference = sign;
        } else if sign != self.reference {
            self.fail(t);
        }
    }

    /// The step that ends at grid point `index` (state `y`, `g` and `h g′` there): clear by
    /// the cubic, or else the septic test.
    #[inline(always)]
    fn test_step(
        &mut self,
        index: usize,
        y: &[f64; D],
        g: [f64; 2],
        model: &impl JacobianState<D>,
    ) {
        let (h, sign) = (self.spacing, self.reference);
        let (series, change) = match &mut self.previous {
            Some(previous) if !between::clearly_keeps_sign(&previous.g, &g, sign) => {
                let (series, change) = step_between(previous, index, y, model, h, sign);
                (Some(series), change)
            }
            _ => (None, None),
        };
        if let Some(det) = change {
            self.min_abs = self.min_abs.min(det.abs());
            self.fail(index as f64 * h);
        }
        self.previous = Some(Knot {
            state: *y,
            g,
            series,
        });
    }

    fn fail(&mut self, t: f64) {
        if self.stable {
            self.stable = false;
            self.first_change = Some([(t - self.spacing).max(0.0), t]);
        }
    }

    pub fn finish(self) -> Stability {
        Stability {
            stable: self.stable,
            det_j_min: if self.min_abs.is_nan() {
                f64::NAN
            } else {
                self.min_abs
            },
            first_sign_change: self.first_change,
            det_j: self.det_j.unwrap_or_default(),
            spacing: self.spacing,
        }
    }
}

/// The septic test of the step from `previous` to grid point `index` (state `y`): the Taylor
/// series of `g` at both ends (at `previous` unless already known), then
/// [`between::changes_sign`]. Returns the series at `index`, and `det J` at a point of the
/// step where it has the sign opposite to `sign`, if there is one. Out of line: most steps
/// never get here.
#[inline(never)]
#[cold]
fn step_between<const D: usize>(
    previous: &mut Knot<D>,
    index: usize,
    y: &[f64; D],
    model: &impl JacobianState<D>,
    h: f64,
    sign: f64,
) -> (Taylor, Option<f64>) {
    let g = |state: &[f64; D], index: usize| {
        let det = between::determinant_series(model.series(state, h));
        multiply(&det, &between::inverse_power_14(index))
    };
    let start = *previous
        .series
        .get_or_insert_with(|| g(&previous.state, index - 1));
    let end = g(y, index);
    let change = between::changes_sign(&start, &end, sign)
        .map(|(theta, value)| value * ((index - 1) as f64 + theta).powi(14));
    (end, change)
}

/// `a · b`, truncated.
fn multiply(a: &Taylor, b: &Taylor) -> Taylor {
    std::array::from_fn(|k| (0..=k).map(|i| a[i] * b[k - i]).sum())
}
