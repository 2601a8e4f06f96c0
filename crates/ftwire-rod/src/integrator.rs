//! Fixed-step explicit Runge–Kutta integration of the wire ODEs (eq. 1 and 4), and septic
//! Hermite dense output for the shape nodes.
//!
//! # Choice of method: a convergence study
//!
//! The hot path integrates 48 states (`R`, `p`, `J`; see [`crate::equations`] for why `μ` and
//! `M` need no integration) on a uniform grid of `steps` steps over `[0, L]`. The table below
//! compares the methods implemented here against the tight adaptive reference (`ode_solvers`'
//! Dop853 at rtol = atol = 1e-13 integrating the full 90-state system of eq. 3–4 independently),
//! over stable configurations sampled uniformly in normalised units in `[−30, 30]⁶`, worst case
//! over the sample. Columns: tip position error / `L`, tip rotation error \[rad\], `J(L)` error
//! relative in max-norm. Requirement: 1e-6, 1e-6, 1e-5.
//!
//! Measured here (200 stable configurations per wire, seeds 100–102; `σL` is the a-priori
//! turning scale of [`crate::equations::turning_scale`], mean 11–12 rad, max 19–20 rad over
//! the sample). Worst case over the three wires of the study (c = (0.042, 0.055, 0.055),
//! L = 0.63; c = (0.214, 0.278, 0.278), L = 0.91; c = (1.3, 1.0, 0.6), L = 1); "evals" is the
//! mean number of right-hand-side evaluations per solve on the third wire (the one with the
//! largest errors), counting the one extra step of the default two first-step substeps:
//!
//! | method | steps | evals | tip pos / L | tip rot \[rad\] | J(L) rel |
//! | --- | --- | --- | --- | --- | --- |
//! | RK4 | 120 | 484 | 9.7e-6 | 6.2e-5 | 5.2e-5 |
//! | RK4 | 240 | 964 | 5.2e-7 | 3.3e-6 | 2.8e-6 |
//! | RK6 | 48 | 343 | 4.0e-6 | 2.6e-5 | 2.2e-5 |
//! | RK8 | 24 | 275 | 9.9e-6 | 6.3e-5 | 5.2e-5 |
//! | RK8 | 32 | 363 | 9.1e-7 | 5.8e-6 | 4.8e-6 |
//! | RK8 | 40 | 451 | 1.4e-7 | 8.9e-7 | 7.4e-7 |
//! | RK8 | 48 | 539 | 3.0e-8 | 1.9e-7 | 1.6e-7 |
//! | DOP853 | 16 | 204 | 1.4e-6 | 1.1e-5 | 7.9e-6 |
//! | DOP853 | 24 | 300 | 5.8e-8 | 3.7e-7 | 3.1e-7 |
//! | DOP853 | 32 | 396 | 5.2e-9 | 3.3e-8 | 2.8e-8 |
//! | RK4 | max(16, ⌈8 σL⌉) | 391 | 8.2e-6 | 5.2e-5 | 4.4e-5 |
//! | RK6 | max(8, ⌈3 σL⌉) | 263 | 4.6e-6 | 3.0e-5 | 2.5e-5 |
//! | RK8 | max(8, ⌈2 σL⌉) | 281 | 9.1e-7 | 5.8e-6 | 4.8e-6 |
//! | RK8 | max(8, ⌈2.5 σL⌉) | 347 | 1.4e-7 | 8.9e-7 | 7.4e-7 |
//! | RK8 | max(8, ⌈3 σL⌉) (previous default) | 414 | 3.5e-8 | 2.3e-7 | 1.9e-7 |
//! | DOP853 | max(8, ⌈1.25 σL⌉) | 199 | 2.5e-7 | 1.6e-6 | 1.7e-6 |
//! | **DOP853** | **max(8, ⌈1.5 σL⌉)** (default) | **235** | **5.8e-8** | **3.7e-7** | **3.5e-7** |
//! | DOP853 | max(8, ⌈1.6 σL⌉) | 249 | 4.1e-8 | 2.6e-7 | 2.2e-7 |
//! | DOP853 | max(8, ⌈1.75 σL⌉) (default until the FMA work) | 271 | 1.6e-8 | 1.0e-7 | 9.1e-8 |
//! | DOP853 | max(8, ⌈2 σL⌉) | 307 | 5.5e-9 | 3.3e-8 | 3.6e-8 |
//!
//! The frame-only solves (`Rod::shape`, `Rod::tip`) run the same grid, first-step substeps
//! included, on a different state: `q` and `m` (16 numbers, [`crate::equations`]'
//! `ShapeArray`), `m` integrated by eq. 3 instead of read from `q` by closed form, which
//! shortens the chain of dependent operations in each stage (`n = Rᵀ n0` is read from the
//! frame rows). The two formulations are 8th-order solutions of the same equations; a unit
//! test checks that their frames agree to the requirement at every grid point. The study also prints the frame-only tip errors (two
//! more columns, not copied into the table): 6.3e-8·L and 4.0e-7 rad at the default (margin
//! 2.5 on the rotation). The substeps matter there too: a frame-only path that skipped them
//! (with the earlier closed-form state) had a worst tip rotation of 7.6e-7 rad, not 3.7e-7.
//!
//! The tip rotation is the binding requirement. Both order-8 methods converge at their order
//! (×2 steps ≈ ×250 less error), but DOP853's error constant is about 170 times smaller than
//! Cooper–Verner's on this problem (same step count, 170 times less error), so it needs about
//! half the steps (0.55 times the evaluations, with its 12 stages against 11) for the same
//! error. The adaptive step count, proportional to the conserved-quantity bound
//! `σL` on how far the frame turns, saves about a fifth against the fixed step count with the
//! same worst case, and keeps the accuracy on configurations more bent than the sample's.
//!
//! The default, [`Method::Dop853`] with `max(8, ⌈1.5 σL⌉)` steps ([`Integrator::default`]),
//! meets the requirement with a margin of 2.7 on the rotation (the binding error; 17 on the
//! position and 29 on `J(L)`) at 0.57 times the evaluations of the first default (RK8 with
//! `⌈3 σL⌉` steps, margin 4). `⌈1.75 σL⌉` (margin 10) costs 15 % more evaluations. The
//! numbers are the same, to the digits shown, with and without the fused multiply–adds of
//! the `arith` module (`FTWIRE_NO_SIMD=1`). Reproduce with
//! `cargo test -p ftwire-rod --release --test convergence -- --ignored --nocapture study`;
//! the non-ignored test `default_meets_the_accuracy_requirement` in the same file guards it.
//!
//! Error-controlled stepping was measured too (DOP853's embedded 5th/3rd-order estimate on
//! the frame's 12 numbers, step factor `0.9·err^(−1/8)` clamped to `[1/3, 6]`, at least 8
//! steps): at tolerance 1e-8, the one that keeps a margin of 2.5 on the rotation (worst 2.8e-7
//! rad), it places about as many grid points as `⌈1.5 σL⌉` (18.5 against 18.6 on the third
//! wire) and redoes 1.8 rejected steps per solve, 256 evaluations against 235, and it was no
//! faster in the benchmark. The a-priori `σL` grid tracks the worst global error as well as
//! the local estimate does, so it stays the default.
//!
//! Shape nodes between grid points come from septic Hermite interpolation of `R` and `p`
//! using `q, q', q'', q'''` at the grid points (exact from the state and eq. 1, 3, 4), with the
//! rotation re-orthonormalised by Gram–Schmidt from the tangent: error `O(h⁸)`. (The quintic
//! interpolant of `q, q', q''` used before, `O(h⁶)`, was not accurate enough between the
//! coarser DOP853 grid points.)
//!
//! # Speed
//!
//! The explicit steps ([`Method::Rk8`], [`Method::Dop853`]) use only the nonzero Butcher
//! coefficients, each stage sum one fused pass over the flat state, the stage derivatives kept
//! in a workspace reused across steps (nothing zeroed or copied per step). The stages run in a
//! loop over a table of the nonzero coefficients, not written out: the right-hand side is then
//! compiled once per step, and the step's code fits the CPU's instruction caches (written out,
//! the 48-state step was about 60 KB of code and 30 % slower). The stage sums and the
//! right-hand sides are generic over the multiply–add, and the solver's loops run compiled
//! for AVX2 with hardware FMA when the CPU has them (the crate's `arith` module).
//!
//! States of at most 16 numbers (the shape state) take a DOP853 step with the stages written
//! out instead (each stage sum stays in registers, no loop or table bookkeeping: about half
//! the instructions of the loop, and small enough code). On AVX2+FMA CPUs the shape solve runs
//! an explicit-intrinsics copy of that step (the crate's `simd` module), because LLVM splits
//! the generic 4-lane code into scalar pieces there.
//!
//! The Jacobian solves' DOP853 step has an explicit-intrinsics copy too, with the stage sums
//! written out and the right-hand side out of line (one copy, called by each stage with its sum in
//! memory): 24 % fewer instructions than the generic loop on the benchmark's sample (88.2k against
//! 116.4k per `Rod::jacobian`, callgrind), and about 25 % less time, because it is written around
//! the CPU's costs (no lane-crossing permute where a broadcast from memory does, and a short chain
//! of dependent operations from one stage to the next; see `simd`'s `full_rate`).

use crate::RodError;
use crate::arith::{MulAdd, Separate};

/// An explicit Runge–Kutta method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Method {
    /// Classic 4-stage RK4 (order 4). For comparison; it needs about 8 times the steps of
    /// [`Method::Rk8`] for the same accuracy.
    Rk4,
    /// Butcher's 7-stage method of order 6 (Butcher 1964).
    Rk6,
    /// Cooper & Verner's 11-stage method of order 8 (SIAM J. Numer. Anal. 9, 1972).
    Rk8,
    /// The 12-stage order-8 method of Dormand & Prince's DOP853 (Hairer, Nørsett & Wanner,
    /// *Solving ODEs I*, §II.10), used at fixed step (its embedded error estimates unused).
    /// The default: its error constant is far smaller than [`Method::Rk8`]'s.
    #[default]
    Dop853,
}

impl Method {
    /// The order of accuracy.
    pub fn order(self) -> u32 {
        match self {
            Method::Rk4 => 4,
            Method::Rk6 => 6,
            Method::Rk8 | Method::Dop853 => 8,
        }
    }

    /// Right-hand-side evaluations per step.
    pub fn stages(self) -> usize {
        match self {
            Method::Rk4 => 4,
            Method::Rk6 => 7,
            Method::Rk8 => 11,
            Method::Dop853 => 12,
        }
    }
}

/// Integration settings: method and number of uniform steps over `[0, L]`.
///
/// Stability is tested at every grid point after `t = 0`, so `steps` is also the resolution of
/// the stability test.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Integrator {
    method: Method,
    steps: usize,
    per_radian: Option<PerRadian>,
    first_substeps: usize,
}

/// Steps per radian of the a-priori turning scale, stored as an exact fraction so that
/// `Integrator` stays `Eq`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct PerRadian {
    millis: u32,
}

impl Default for Integrator {
    /// [`Method::Dop853`] with `max(8, ⌈1.5 σL⌉)` steps (see the study in the module docs).
    fn default() -> Self {
        Self {
            method: Method::Dop853,
            steps: Self::DEFAULT_STEPS,
            per_radian: Some(PerRadian {
                millis: Self::DEFAULT_STEPS_PER_RADIAN_MILLIS,
            }),
            first_substeps: crate::stability::FIRST_STEP_SUBSTEPS,
        }
    }
}

impl Integrator {
    /// Default (smallest) number of steps (see the convergence study in the module docs).
    pub const DEFAULT_STEPS: usize = 8;
    /// Default steps per radian of turning scale, in thousandths.
    const DEFAULT_STEPS_PER_RADIAN_MILLIS: u32 = 1500;
    /// Cap of the adaptive step count.
    pub const MAX_ADAPTIVE_STEPS: usize = 20_000;
    /// Largest number of steps accepted.
    pub const MAX_STEPS: usize = 1_000_000;

    /// Builds integration settings.
    ///
    /// # Errors
    /// [`RodError::BadSteps`] unless `1 ≤ steps ≤ MAX_STEPS`.
    ///
    /// # Example
    /// ```
    /// use ftwire_rod::{Integrator, Method};
    /// let fine = Integrator::new(Method::Rk8, 64)?;
    /// assert_eq!(fine.steps(), 64);
    /// assert!(Integrator::new(Method::Rk4, 0).is_err());
    /// # Ok::<(), ftwire_rod::RodError>(())
    /// ```
    pub fn new(method: Method, steps: usize) -> Result<Self, RodError> {
        if !(1..=Self::MAX_STEPS).contains(&steps) {
            return Err(RodError::BadSteps {
                steps,
                min: 1,
                max: Self::MAX_STEPS,
            });
        }
        Ok(Self {
            method,
            steps,
            per_radian: None,
            first_substeps: crate::stability::FIRST_STEP_SUBSTEPS,
        })
    }

    /// Settings whose step count adapts to the configuration: `max(min_steps,
    /// ⌈steps_per_radian · σ L⌉)` steps, capped at [`Integrator::MAX_ADAPTIVE_STEPS`], where
    /// `σ` \[1/m\] bounds the wire's curvature and load wavenumber a priori (see
    /// [`crate::equations::turning_scale`]).
    ///
    /// # Errors
    /// [`RodError::BadSteps`] unless `1 ≤ min_steps ≤ MAX_STEPS`, or if `steps_per_radian` is
    /// not in `[0, 1000]`.
    pub fn adaptive(
        method: Method,
        min_steps: usize,
        steps_per_radian: f64,
    ) -> Result<Self, RodError> {
        let fixed = Self::new(method, min_steps)?;
        if !(0.0..=1000.0).contains(&steps_per_radian) {
            return Err(RodError::BadSteps {
                steps: min_steps,
                min: 1,
                max: Self::MAX_STEPS,
            });
        }
        Ok(Self {
            per_radian: Some(PerRadian {
                millis: (steps_per_radian * 1000.0).round() as u32,
            }),
            ..fixed
        })
    }

    /// The number of steps for a configuration whose turning scale times length is `sigma_l`.
    pub fn steps_for(&self, sigma_l: f64) -> usize {
        match self.per_radian {
            None => self.steps,
            Some(PerRadian { millis }) => {
                let wanted = f64::from(millis) / 1000.0 * sigma_l;
                if wanted.is_finite() && wanted < Self::MAX_ADAPTIVE_STEPS as f64 {
                    (wanted.ceil() as usize).max(self.steps)
                } else {
                    Self::MAX_ADAPTIVE_STEPS.max(self.steps)
                }
            }
        }
    }

    /// The same settings with the first step split into `substeps` equal substeps (default
    /// [`FIRST_STEP_SUBSTEPS`](crate::stability::FIRST_STEP_SUBSTEPS); see
    /// [`crate::stability`] for why).
    ///
    /// # Errors
    /// [`RodError::BadSteps`] unless `1 ≤ substeps ≤ 64`.
    pub fn with_first_step_substeps(self, substeps: usize) -> Result<Self, RodError> {
        if !(1..=64).contains(&substeps) {
            return Err(RodError::BadSteps {
                steps: substeps,
                min: 1,
                max: 64,
            });
        }
        Ok(Self {
            first_substeps: substeps,
            ..self
        })
    }

    /// Substeps of the first step.
    pub fn first_step_substeps(&self) -> usize {
        self.first_substeps
    }

    /// The steps of a grid of `steps` uniform steps of size `h`, the first split into
    /// [`Integrator::first_step_substeps`] substeps: each step's size, and the index (1 to
    /// `steps`) of the grid point it ends on, if it ends on one. Every solve path walks this
    /// one sequence, so all of them have the same grid points (the shape and Jacobian solves'
    /// frames there agree to the accuracy requirement, not bit for bit: they integrate
    /// different states); as one loop, it also keeps a single copy of the (large, inlined)
    /// step in the code.
    pub(crate) fn grid(&self, h: f64, steps: usize) -> impl Iterator<Item = (f64, Option<usize>)> {
        let substeps = self.first_substeps;
        let sub = h / substeps as f64;
        (0..substeps + steps - 1).map(move |s| {
            let step = if s < substeps { sub } else { h };
            (step, (s + 1 >= substeps).then(|| s + 2 - substeps))
        })
    }

    /// The method.
    pub fn method(&self) -> Method {
        self.method
    }

    /// The number of uniform steps over `[0, L]` (the minimum, for adaptive settings).
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// One step of size `h` from `y` of the autonomous ODE `y' = f(y)`.
    #[inline(always)]
    pub(crate) fn step<const D: usize>(&self, y: &[f64; D], h: f64, f: impl Rhs<D>) -> [f64; D] {
        match self.method {
            Method::Rk4 => rk_step(&RK4_A, &RK4_B, y, h, f),
            Method::Rk6 => rk_step(&RK6_A, &RK6_B, y, h, f),
            Method::Dop853 => {
                let mut out = *y;
                dop853_step::<Separate, D>(&mut out, h, f, &mut Workspace::new());
                out
            }
            Method::Rk8 => {
                let mut out = *y;
                rk8_step::<Separate, D>(&mut out, h, f, &mut Workspace::new());
                out
            }
        }
    }
}

/// The right-hand side `f` of an autonomous ODE `y' = f(y)` on a flat state of `D` numbers.
///
/// Closures implement it; the solver's hot paths use small structs whose `rate` is
/// `#[inline(always)]`, so that it is compiled into the AVX2+FMA loops of
/// [`crate::arith`] (a closure would be compiled on its own, without those features).
pub(crate) trait Rhs<const D: usize>: Copy {
    /// Writes `f(y)` into `out`.
    fn rate(&self, y: &[f64; D], out: &mut [f64; D]);
}

impl<const D: usize, F: Fn(&[f64; D], &mut [f64; D]) + Copy> Rhs<D> for F {
    #[inline(always)]
    fn rate(&self, y: &[f64; D], out: &mut [f64; D]) {
        self(y, out)
    }
}

/// Scratch space of one explicit RK step on a flat state of `D` numbers: the stage
/// derivatives and the stage state. Kept across steps so that nothing is zeroed or copied per
/// step.
#[derive(Debug, Clone)]
pub(crate) struct Workspace<const D: usize> {
    k: [[f64; D]; 12],
    yi: [f64; D],
}

impl<const D: usize> Workspace<D> {
    pub fn new() -> Self {
        Self {
            k: [[0.0; D]; 12],
            yi: [0.0; D],
        }
    }
}

impl Integrator {
    /// One step of size `h` of the autonomous ODE `y' = f(y)`, in place, with scratch `w`,
    /// the stage sums multiply–added by `A`.
    #[inline(always)]
    pub(crate) fn step_in_place<A: MulAdd, const D: usize>(
        &self,
        y: &mut [f64; D],
        h: f64,
        f: impl Rhs<D>,
        w: &mut Workspace<D>,
    ) {
        match self.method {
            Method::Rk8 => rk8_step::<A, D>(y, h, f, w),
            Method::Dop853 => dop853_step::<A, D>(y, h, f, w),
            _ => *y = self.step(y, h, f),
        }
    }
}

/// The stages `j` with nonzero `a_ij` of each stage `i` of [`Method::Rk8`].
const RK8_TERMS: [&[usize]; 11] = [
    &[],
    &[0],
    &[0, 1],
    &[0, 1, 2],
    &[0, 2, 3],
    &[0, 2, 3, 4],
    &[0, 2, 3, 4, 5],
    &[0, 4, 5, 6],
    &[0, 4, 5, 6, 7],
    &[0, 4, 5, 6, 7, 8],
    &[4, 5, 6, 7, 8, 9],
];

/// Calls the macro `$m` with `$args`, then `;` and the list of the stages `j` with nonzero
/// `a_ij` of each stage `i` of [`Method::Dop853`] (as `i: [j, ...]`, separated by `;`): the
/// one definition of the list, for the loop's table and the written-out steps.
macro_rules! with_dop853_terms {
    ($m:ident!($($args:tt)*)) => {
        $m!($($args)*;
        0: [];
        1: [0];
        2: [0, 1];
        3: [0, 2];
        4: [0, 2, 3];
        5: [0, 3, 4];
        6: [0, 3, 4, 5];
        7: [0, 3, 4, 5, 6];
        8: [0, 3, 4, 5, 6, 7];
        9: [0, 3, 4, 5, 6, 7, 8];
        10: [0, 3, 4, 5, 6, 7, 8, 9];
        11: [0, 3, 4, 5, 6, 7, 8, 9, 10]
        )
    };
}
pub(crate) use with_dop853_terms;

/// The list of [`with_dop853_terms`] as a table.
macro_rules! terms_table {
    (; $($i:literal: [$($j:literal),*]);*) => {
        [$(&[$($j),*]),*]
    };
}

/// The stages `j` with nonzero `a_ij` of each stage `i` of [`Method::Dop853`].
const DOP853_TERMS: [&[usize]; 12] = with_dop853_terms!(terms_table!());

/// The stages of an explicit RK step with tableau `a`, over its nonzero coefficients
/// (`terms[i]` lists the `j` with `a_ij ≠ 0`): `k_i = f(y + h Σ_j a_ij k_j)`, each stage sum
/// one pass over the flat state, the stages kept in the caller's [`Workspace`].
/// (In a loop, not written out: see the module's "Speed".)
#[inline(always)]
fn stages<A: MulAdd, const D: usize, const S: usize>(
    terms: &[&[usize]; S],
    a: &[[f64; S]; S],
    y: &[f64; D],
    h: f64,
    f: impl Rhs<D>,
    w: &mut Workspace<D>,
) {
    for (i, terms) in terms.iter().enumerate() {
        let mut sum = *y;
        for &j in terms.iter() {
            let c = h * a[i][j];
            for (s, k) in sum.iter_mut().zip(&w.k[j]) {
                *s = A::mul_add(c, *k, *s);
            }
        }
        w.yi = sum;
        f.rate(&w.yi, &mut w.k[i]);
    }
}

/// One step of [`Method::Rk8`] (Cooper & Verner), nonzero coefficients only, in place.
#[inline(always)]
fn rk8_step<A: MulAdd, const D: usize>(
    y: &mut [f64; D],
    h: f64,
    f: impl Rhs<D>,
    w: &mut Workspace<D>,
) {
    stages::<A, D, 11>(&RK8_TERMS, &RK8_A, y, h, f, w);
    finish::<A, D, 11>(y, h, &RK8_B, &[0, 7, 8, 9, 10], w);
}

/// States of at most this many numbers take the written-out DOP853 step.
const SMALL_STATE: usize = 16;

/// `sum += c · k`, lane by lane.
#[inline(always)]
fn axpy<A: MulAdd, const D: usize>(sum: &mut [f64; D], c: f64, k: &[f64; D]) {
    for (s, k) in sum.iter_mut().zip(k) {
        *s = A::mul_add(c, *k, *s);
    }
}

/// The stages of [`dop853_step`] written out, one block per stage over its nonzero
/// coefficients (the lists of [`with_dop853_terms`]; a test checks the results agree with the
/// loop bit for bit). For small states (the shape solve's 16 numbers): each stage sum stays in
/// registers, with no loop or table bookkeeping, about half the instructions of the loop. (The
/// 48-state step, written out, no longer fits the instruction cache; see the module's
/// "Speed".)
macro_rules! written_out_stages {
    ($a:ident, $y:ident, $h:ident, $f:ident, $w:ident; $($i:literal: [$($j:literal),*]);*) => {
        $(
            {
                #[allow(unused_mut)]
                let mut sum = *$y;
                $( axpy::<A, D>(&mut sum, $h * $a[$i][$j], &$w.k[$j]); )*
                $f.rate(&sum, &mut $w.k[$i]);
            }
        )*
    };
}

/// One step of [`Method::Dop853`], as [`rk8_step`].
#[inline(always)]
fn dop853_step<A: MulAdd, const D: usize>(
    y: &mut [f64; D],
    h: f64,
    f: impl Rhs<D>,
    w: &mut Workspace<D>,
) {
    if D <= SMALL_STATE {
        with_dop853_terms!(written_out_stages!(DOP853_A, y, h, f, w));
    } else {
        stages::<A, D, 12>(&DOP853_TERMS, &DOP853_A, y, h, f, w);
    }
    finish::<A, D, 12>(y, h, &DOP853_B, &[0, 5, 6, 7, 8, 9, 10, 11], w);
}

/// The step's result `y + Σ_j h b_j k_j` over the stages `j` with nonzero `b_j`, in place.
#[inline(always)]
fn finish<A: MulAdd, const D: usize, const S: usize>(
    y: &mut [f64; D],
    h: f64,
    b: &[f64; S],
    stages: &[usize],
    w: &Workspace<D>,
) {
    for &j in stages {
        axpy::<A, D>(y, h * b[j], &w.k[j]);
    }
}

/// One explicit RK step on a flat state of `D` numbers (fixed size, so the stage sums
/// vectorise).
#[inline(always)]
fn rk_step<const D: usize, const N: usize>(
    a: &[[f64; N]; N],
    b: &[f64; N],
    y: &[f64; D],
    h: f64,
    f: impl Rhs<D>,
) -> [f64; D] {
    let mut k = [[0.0; D]; N];
    let mut yi = *y;
    for i in 0..N {
        if i > 0 {
            yi = *y;
            let (done, _) = k.split_at(i);
            for (j, kj) in done.iter().enumerate() {
                let c = h * a[i][j];
                if c != 0.0 {
                    for (y, k) in yi.iter_mut().zip(kj) {
                        *y += c * k;
                    }
                }
            }
        }
        f.rate(&yi, &mut k[i]);
    }
    let mut out = *y;
    for i in 0..N {
        let c = h * b[i];
        if c != 0.0 {
            for (y, k) in out.iter_mut().zip(&k[i]) {
                *y += c * k;
            }
        }
    }
    out
}

const RK4_A: [[f64; 4]; 4] = [
    [0.0, 0.0, 0.0, 0.0],
    [0.5, 0.0, 0.0, 0.0],
    [0.0, 0.5, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
];
const RK4_B: [f64; 4] = [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];

const RK6_A: [[f64; 7]; 7] = [
    [0.0; 7],
    [1.0 / 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, 2.0 / 3.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0 / 12.0, 1.0 / 3.0, -1.0 / 12.0, 0.0, 0.0, 0.0, 0.0],
    [
        -1.0 / 16.0,
        9.0 / 8.0,
        -3.0 / 16.0,
        -3.0 / 8.0,
        0.0,
        0.0,
        0.0,
    ],
    [0.0, 9.0 / 8.0, -3.0 / 8.0, -3.0 / 4.0, 1.0 / 2.0, 0.0, 0.0],
    [
        9.0 / 44.0,
        -9.0 / 11.0,
        63.0 / 44.0,
        18.0 / 11.0,
        0.0,
        -16.0 / 11.0,
        0.0,
    ],
];
const RK6_B: [f64; 7] = [
    11.0 / 120.0,
    0.0,
    27.0 / 40.0,
    27.0 / 40.0,
    -4.0 / 15.0,
    -4.0 / 15.0,
    11.0 / 120.0,
];

/// √21.
const S21: f64 = 4.582_575_694_955_84;

const RK8_A: [[f64; 11]; 11] = [
    [0.0; 11],
    [0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.25, 0.25, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [
        1.0 / 7.0,
        (-7.0 - 3.0 * S21) / 98.0,
        (21.0 + 5.0 * S21) / 49.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        (11.0 + S21) / 84.0,
        0.0,
        (18.0 + 4.0 * S21) / 63.0,
        (21.0 - S21) / 252.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        (5.0 + S21) / 48.0,
        0.0,
        (9.0 + S21) / 36.0,
        (-231.0 + 14.0 * S21) / 360.0,
        (63.0 - 7.0 * S21) / 80.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        (10.0 - S21) / 42.0,
        0.0,
        (-432.0 + 92.0 * S21) / 315.0,
        (633.0 - 145.0 * S21) / 90.0,
        (-504.0 + 115.0 * S21) / 70.0,
        (63.0 - 13.0 * S21) / 35.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        1.0 / 14.0,
        0.0,
        0.0,
        0.0,
        (14.0 - 3.0 * S21) / 126.0,
        (13.0 - 3.0 * S21) / 63.0,
        1.0 / 9.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        1.0 / 32.0,
        0.0,
        0.0,
        0.0,
        (91.0 - 21.0 * S21) / 576.0,
        11.0 / 72.0,
        (-385.0 - 75.0 * S21) / 1152.0,
        (63.0 + 13.0 * S21) / 128.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        1.0 / 14.0,
        0.0,
        0.0,
        0.0,
        1.0 / 9.0,
        (-733.0 - 147.0 * S21) / 2205.0,
        (515.0 + 111.0 * S21) / 504.0,
        (-51.0 - 11.0 * S21) / 56.0,
        (132.0 + 28.0 * S21) / 245.0,
        0.0,
        0.0,
    ],
    [
        0.0,
        0.0,
        0.0,
        0.0,
        (-42.0 + 7.0 * S21) / 18.0,
        (-18.0 + 28.0 * S21) / 45.0,
        (-273.0 - 53.0 * S21) / 72.0,
        (301.0 + 53.0 * S21) / 72.0,
        (28.0 - 28.0 * S21) / 45.0,
        (49.0 - 7.0 * S21) / 18.0,
        0.0,
    ],
];
const RK8_B: [f64; 11] = [
    1.0 / 20.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    49.0 / 180.0,
    16.0 / 45.0,
    49.0 / 180.0,
    1.0 / 20.0,
];

pub(crate) const DOP853_A: [[f64; 12]; 12] = [
    [0.0; 12],
    [
        0.05260015195876773,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.0197250569845379,
        0.0591751709536137,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.02958758547680685,
        0.0,
        0.08876275643042054,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.2413651341592667,
        0.0,
        -0.8845494793282861,
        0.924834003261792,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.037037037037037035,
        0.0,
        0.0,
        0.17082860872947386,
        0.12546768756682242,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.037109375,
        0.0,
        0.0,
        0.17025221101954405,
        0.06021653898045596,
        -0.017578125,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.03709200011850479,
        0.0,
        0.0,
        0.17038392571223998,
        0.10726203044637328,
        -0.015319437748624402,
        0.008273789163814023,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.6241109587160757,
        0.0,
        0.0,
        -3.3608926294469414,
        -0.868219346841726,
        27.59209969944671,
        20.154067550477894,
        -43.48988418106996,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.47766253643826434,
        0.0,
        0.0,
        -2.4881146199716677,
        -0.590290826836843,
        21.230051448181193,
        15.279233632882423,
        -33.28821096898486,
        -0.020331201708508627,
        0.0,
        0.0,
        0.0,
    ],
    [
        -0.9371424300859873,
        0.0,
        0.0,
        5.186372428844064,
        1.0914373489967295,
        -8.149787010746927,
        -18.52006565999696,
        22.739487099350505,
        2.4936055526796523,
        -3.0467644718982196,
        0.0,
        0.0,
    ],
    [
        2.273310147516538,
        0.0,
        0.0,
        -10.53449546673725,
        -2.0008720582248625,
        -17.9589318631188,
        27.94888452941996,
        -2.8589982771350235,
        -8.87285693353063,
        12.360567175794303,
        0.6433927460157636,
        0.0,
    ],
];
pub(crate) const DOP853_B: [f64; 12] = [
    0.054293734116568765,
    0.0,
    0.0,
    0.0,
    0.0,
    4.450312892752409,
    1.8915178993145003,
    -5.801203960010585,
    0.3111643669578199,
    -0.1521609496625161,
    0.20136540080403034,
    0.04471061572777259,
];

/// Septic Hermite basis at `θ ∈ [0, 1]`: weights of `y0, h y0', h² y0'', h³ y0''', y1, h y1',
/// h² y1'', h³ y1'''`.
#[inline]
pub(crate) fn septic_hermite(theta: f64) -> [f64; 8] {
    let t = theta;
    let t2 = t * t;
    let t3 = t2 * t;
    let t4 = t3 * t;
    // Each weight is c0 + c1 t + c2 t² + c3 t³ + t⁴ (d0 + d1 t + d2 t² + d3 t³).
    let q = |d0: f64, d1: f64, d2: f64, d3: f64| t4 * (d0 + t * (d1 + t * (d2 + t * d3)));
    let s = 1.0 / 6.0;
    [
        1.0 + q(-35.0, 84.0, -70.0, 20.0),
        t + q(-20.0, 45.0, -36.0, 10.0),
        0.5 * t2 + q(-5.0, 10.0, -7.5, 2.0),
        s * t3 + q(-2.0 / 3.0, 1.0, -2.0 / 3.0, s),
        q(35.0, -84.0, 70.0, -20.0),
        q(-15.0, 39.0, -34.0, 10.0),
        q(2.5, -7.0, 6.5, -2.0),
        q(-s, 0.5, -0.5, s),
    ]
}

/// Quintic Hermite basis at `θ ∈ [0, 1]`: weights of `y0, h y0', h² y0'', y1, h y1', h² y1''`.
/// The dense output before [`septic_hermite`]; kept with its test for comparison.
#[cfg(test)]
pub(crate) fn quintic_hermite(theta: f64) -> [f64; 6] {
    let t = theta;
    let t2 = t * t;
    let t3 = t2 * t;
    let t4 = t3 * t;
    let t5 = t4 * t;
    [
        1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5,
        t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5,
        0.5 * (t2 - 3.0 * t3 + 3.0 * t4 - t5),
        10.0 * t3 - 15.0 * t4 + 6.0 * t5,
        -4.0 * t3 + 7.0 * t4 - 3.0 * t5,
        0.5 * (t3 - 2.0 * t4 + t5),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Empirical order on a nonlinear autonomous system with a known solution: the
    /// pendulum-free Lotka–Volterra-like system y' = (y1², 1) with y1(x) = 1/(1 − x).
    fn error(method: Method, steps: usize) -> f64 {
        let integ = Integrator::new(method, steps).expect("valid");
        let h = 0.5 / steps as f64;
        let mut y = [1.0, 0.0];
        for _ in 0..steps {
            y = integ.step(&y, h, |s: &[f64; 2], out: &mut [f64; 2]| {
                *out = [s[0] * s[0], 1.0]
            });
        }
        (y[0] - 2.0).abs()
    }

    #[test]
    fn each_method_has_its_order() {
        for method in [Method::Rk4, Method::Rk6, Method::Rk8, Method::Dop853] {
            let (e1, e2) = (error(method, 8), error(method, 16));
            let observed = (e1 / e2).log2();
            let order = f64::from(method.order());
            assert!(
                (observed - order).abs() < 0.6,
                "{method:?}: observed order {observed}, expected {order} ({e1:e}, {e2:e})"
            );
        }
    }

    /// The written-out RK8 and DOP853 steps use exactly the Butcher tableau (every nonzero coefficient).
    #[test]
    fn fused_steps_match_their_tableaus() {
        // The term lists name every nonzero coefficient (and only those).
        for (i, row) in RK8_A.iter().enumerate() {
            for (j, a) in row.iter().enumerate() {
                assert_eq!(*a != 0.0, RK8_TERMS[i].contains(&j), "RK8 a[{i}][{j}]");
            }
        }
        for (i, row) in DOP853_A.iter().enumerate() {
            for (j, a) in row.iter().enumerate() {
                assert_eq!(
                    *a != 0.0,
                    DOP853_TERMS[i].contains(&j),
                    "DOP853 a[{i}][{j}]"
                );
            }
        }
        let f = |s: &[f64; 3], out: &mut [f64; 3]| {
            *out = [s[0] * s[1] + s[2], -s[0] * s[0] + 0.3, (s[1] * s[2]).sin()];
        };
        let y = [0.3, -0.7, 1.1];
        for h in [0.05, 0.4] {
            let mut fused = y;
            rk8_step::<Separate, 3>(&mut fused, h, f, &mut Workspace::new());
            let table = rk_step(&RK8_A, &RK8_B, &y, h, f);
            for (a, b) in fused.iter().zip(&table) {
                assert!((a - b).abs() < 1e-14, "h = {h}: {a} vs {b}");
            }
            let mut fused = y;
            dop853_step::<Separate, 3>(&mut fused, h, f, &mut Workspace::new());
            let table = rk_step(&DOP853_A, &DOP853_B, &y, h, f);
            for (a, b) in fused.iter().zip(&table) {
                assert!((a - b).abs() < 1e-14, "DOP853, h = {h}: {a} vs {b}");
            }
            // A state too large for the written-out step runs the loop over the term
            // tables; both give the same numbers bit for bit.
            let f24 = |s: &[f64; 24], out: &mut [f64; 24]| {
                for (s, o) in s.chunks_exact(3).zip(out.chunks_exact_mut(3)) {
                    let mut r = [0.0; 3];
                    f(&[s[0], s[1], s[2]], &mut r);
                    o.copy_from_slice(&r);
                }
            };
            let y24: [f64; 24] = std::array::from_fn(|i| y[i % 3] + 0.01 * (i / 3) as f64);
            let mut looped = y24;
            dop853_step::<Separate, 24>(&mut looped, h, f24, &mut Workspace::new());
            for (c, chunk) in looped.chunks_exact(3).enumerate() {
                let mut small: [f64; 3] = std::array::from_fn(|i| y24[3 * c + i]);
                dop853_step::<Separate, 3>(&mut small, h, f, &mut Workspace::new());
                assert_eq!(chunk, small, "DOP853 loop vs written out, h = {h}");
            }
        }
    }

    #[test]
    fn hermite_reproduces_quintics() {
        let f =
            |x: f64| 1.0 - 2.0 * x + 0.5 * x * x + 3.0 * x.powi(3) - x.powi(4) + 0.7 * x.powi(5);
        let d1 = |x: f64| -2.0 + x + 9.0 * x * x - 4.0 * x.powi(3) + 3.5 * x.powi(4);
        let d2 = |x: f64| 1.0 + 18.0 * x - 12.0 * x * x + 14.0 * x.powi(3);
        let (x0, h) = (0.3, 0.7);
        for theta in [0.0, 0.1, 0.37, 0.5, 0.9, 1.0] {
            let w = quintic_hermite(theta);
            let x1 = x0 + h;
            let y = w[0] * f(x0)
                + w[1] * h * d1(x0)
                + w[2] * h * h * d2(x0)
                + w[3] * f(x1)
                + w[4] * h * d1(x1)
                + w[5] * h * h * d2(x1);
            assert!((y - f(x0 + theta * h)).abs() < 1e-12, "θ = {theta}");
        }
    }

    #[test]
    fn septic_hermite_reproduces_septics() {
        let coef: [f64; 8] = [1.0, -2.0, 0.5, 3.0, -1.0, 0.7, -0.4, 0.25];
        let deriv = |x: f64, d: usize| -> f64 {
            let mut sum = 0.0;
            for (i, c) in coef.iter().enumerate().skip(d) {
                let mut k = 1.0;
                for j in 0..d {
                    k *= (i - j) as f64;
                }
                sum += c * k * x.powi((i - d) as i32);
            }
            sum
        };
        let (x0, h): (f64, f64) = (0.3, 0.7);
        let x1 = x0 + h;
        for theta in [0.0, 0.1, 0.37, 0.5, 0.9, 1.0] {
            let w = septic_hermite(theta);
            let mut y = 0.0;
            for d in 0..4 {
                let hd = h.powi(d as i32);
                y += w[d] * hd * deriv(x0, d) + w[4 + d] * hd * deriv(x1, d);
            }
            assert!((y - deriv(x0 + theta * h, 0)).abs() < 1e-12, "θ = {theta}");
        }
    }

    #[test]
    fn zero_steps_are_rejected() {
        assert!(matches!(
            Integrator::new(Method::Rk8, 0),
            Err(RodError::BadSteps { steps: 0, .. })
        ));
    }
}
