//! Fixed-step explicit Runge–Kutta integration of the wire ODEs (eq. 1, 3 and 4).
//!
//! The Jacobian solves integrate 48 states (`R`, `p`, `J`; see [`crate::equations`] for why
//! `μ` and `M` need no integration), the shape-only solves 16 (`q` and `m`), on a uniform grid
//! of `steps` steps over `[0, L]`. The default, [`Method::Dop853`] at fixed step with
//! `max(8, ⌈1.5 σL⌉)` steps ([`Integrator::default`]; `σL` is the a-priori turning scale of
//! [`crate::equations::turning_scale`]), was chosen by a convergence study against a tight
//! adaptive reference (an independent Dop853 integration of the full 90-state system) for the
//! requirement tip position 1e-6·L, tip rotation 1e-6 rad, `J(L)` 1e-5 relative: DOP853's error
//! constant is far smaller than Cooper–Verner's RK8, so it needs about half the steps for the
//! same error, and a step count proportional to `σL` keeps the accuracy on strongly bent
//! configurations. The study's tables and how to rerun it are in `docs/integrator.md`; the
//! test `default_meets_the_accuracy_requirement` (`tests/convergence.rs`) guards the default,
//! and `each_method_has_its_order` below the order of every method. The tableaux are in
//! `tableau`, the dense output between grid points in `hermite`.
//!
//! # Speed
//!
//! The explicit steps ([`Method::Rk8`], [`Method::Dop853`]) use only the nonzero Butcher
//! coefficients, each stage sum taken 16 numbers at a time with all its terms in registers
//! (one store per number), the stage derivatives kept in a workspace reused across steps
//! (nothing zeroed or copied per step). The stages run in a loop over a table of the nonzero
//! coefficients, not written out, so that the right-hand side is compiled once per step and the
//! 48-state step's code fits the instruction caches. States of at most 18 numbers (the shape
//! states, 16 unloaded and 18 loaded) take a DOP853 step with the stages written out (each
//! stage sum stays in registers). The stage sums and the right-hand sides are generic over the
//! multiply–add and run compiled for AVX2 with hardware FMA when the CPU has them (the crate's
//! `arith` module); on such CPUs the shape and Jacobian solves run explicit-intrinsics copies
//! of the DOP853 step (the crate's `simd` module). A test checks that the written-out and
//! looped steps agree bit for bit. The measurements behind these choices are in
//! `docs/integrator.md`.

use crate::RodError;
use crate::arith::{MulAdd, Separate};
use crate::tableau::{
    DOP853_A, DOP853_B, DOP853_TERMS, RK4_A, RK4_B, RK6_A, RK6_B, RK8_A, RK8_B, RK8_TERMS,
    with_dop853_terms,
};

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

/// The first integration step is taken as this many equal substeps (cheap insurance for the
/// sign of `det J` at the first grid point; see [`crate::stability`]).
pub const FIRST_STEP_SUBSTEPS: usize = 2;

/// Integration settings: method and number of uniform steps over `[0, L]`.
///
/// Stability is tested at every grid point after `t = 0` and between them
/// ([`crate::stability`]), so its verdict does not hang on where the steps fall.
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
            first_substeps: FIRST_STEP_SUBSTEPS,
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
            first_substeps: FIRST_STEP_SUBSTEPS,
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
    /// [`FIRST_STEP_SUBSTEPS`]; see [`crate::stability`] for why).
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
        let mut start = 0;
        while start + CHUNK <= D {
            chunk_sum::<A, D>(y, start, CHUNK, terms, &a[i], h, w);
            start += CHUNK;
        }
        chunk_sum::<A, D>(y, start, D - start, terms, &a[i], h, w);
        f.rate(&w.yi, &mut w.k[i]);
    }
}

/// Numbers of the state summed at once by [`stages`].
const CHUNK: usize = 16;

/// `yi[start..start + len] = y + Σ_j h a_j k_j` there (`len ≤ CHUNK`), all terms summed into
/// registers before one store: over the whole state at once, the sum of a large state does
/// not fit the registers, and each term would load and store it again. (Each number's sum
/// is the same, in the same order, as term by term over the whole state.)
#[inline(always)]
fn chunk_sum<A: MulAdd, const D: usize>(
    y: &[f64; D],
    start: usize,
    len: usize,
    terms: &[usize],
    a: &[f64],
    h: f64,
    w: &mut Workspace<D>,
) {
    let mut acc = [0.0; CHUNK];
    acc[..len].copy_from_slice(&y[start..start + len]);
    for &j in terms {
        let c = h * a[j];
        for (s, k) in acc[..len].iter_mut().zip(&w.k[j][start..start + len]) {
            *s = A::mul_add(c, *k, *s);
        }
    }
    w.yi[start..start + len].copy_from_slice(&acc[..len]);
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
const SMALL_STATE: usize = 18;

/// `sum += c · k`, lane by lane.
#[inline(always)]
fn axpy<A: MulAdd, const D: usize>(sum: &mut [f64; D], c: f64, k: &[f64; D]) {
    for (s, k) in sum.iter_mut().zip(k) {
        *s = A::mul_add(c, *k, *s);
    }
}

/// The stages of [`dop853_step`] written out, one block per stage over its nonzero
/// coefficients (the lists of [`with_dop853_terms`]; a test checks the results agree with the
/// loop bit for bit). For small states (the shape solves' 16 and 18 numbers): each stage sum stays in
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
    fn zero_steps_are_rejected() {
        assert!(matches!(
            Integrator::new(Method::Rk8, 0),
            Err(RodError::BadSteps { steps: 0, .. })
        ));
    }
}
