//! The sign of `det J` between two grid points, on `g(t) = det J(t) / (t/h)¹⁴` (see the parent
//! module for the method and why): the determinant with its derivative
//! ([`determinant_and_derivative`]) and its Taylor series ([`determinant_series`]) at a grid
//! point, the cubic screen ([`clearly_keeps_sign`]), and the septic test ([`changes_sign`]):
//! the septic Hermite interpolant of `g` from its series at both ends, in Bernstein form,
//! searched for a point of the opposite sign by halving.
//!
//! Guarded by the tests below: the derivative against nalgebra's determinant, the series
//! against the multilinear expansion of the determinant, and the septic test on septics with
//! known roots (a dip, a double root just below and just above zero).

use super::jacobian_series::{MatrixSeries, Rows};

/// A truncated Taylor series `a0 + a1 θ + a2 θ² + a3 θ³` in the step's unit `θ = (t − t_k)/h`:
/// `a_k = h^k f⁽ᵏ⁾(t_k) / k!`.
pub(crate) type Taylor = [f64; 4];

/// `a · b`, truncated.
#[inline(always)]
fn mul(a: &Taylor, b: &Taylor) -> Taylor {
    [
        a[0] * b[0],
        a[0] * b[1] + a[1] * b[0],
        a[0] * b[2] + a[1] * b[1] + a[2] * b[0],
        a[0] * b[3] + a[1] * b[2] + a[2] * b[1] + a[3] * b[0],
    ]
}

/// `1 / b`, truncated (`b0 ≠ 0`).
#[inline(always)]
fn reciprocal(b: &Taylor) -> Taylor {
    let r0 = 1.0 / b[0];
    let r1 = -r0 * (b[1] * r0);
    let r2 = -r0 * (b[1] * r1 + b[2] * r0);
    let r3 = -r0 * (b[1] * r2 + b[2] * r1 + b[3] * r0);
    [r0, r1, r2, r3]
}

/// `det a` and `tr(adj a · x)`, the derivative of `det(a + θ x)` at `θ = 0`: Gaussian
/// elimination with partial pivoting on the rows of `a`, carried to first order in `θ`. (The
/// value's operations do not depend on `x`: `det J` at the grid points is the same number
/// whatever the test between them does.)
#[inline(always)]
pub(crate) fn determinant_and_derivative(mut a: Rows<6>, mut x: Rows<6>) -> (f64, f64) {
    let (mut det, mut slope) = (1.0, 0.0);
    for c in 0..6 {
        let mut p = c;
        let mut largest = a[c][c].abs();
        for (r, row) in a.iter().enumerate().skip(c + 1) {
            if row[c].abs() > largest {
                largest = row[c].abs();
                p = r;
            }
        }
        if p != c {
            a.swap(p, c);
            x.swap(p, c);
            det = -det;
            slope = -slope;
        }
        let (pivot, pivot_slope) = (a[c][c], x[c][c]);
        slope = slope * pivot + det * pivot_slope;
        det *= pivot;
        if pivot == 0.0 {
            return (det, slope);
        }
        let (prow, xrow) = (a[c], x[c]);
        let inverse = 1.0 / pivot;
        for (row, xr) in a.iter_mut().zip(x.iter_mut()).skip(c + 1) {
            let factor = row[c] * inverse;
            let factor_slope = (xr[c] - factor * pivot_slope) * inverse;
            for (v, pv) in row.iter_mut().zip(&prow) {
                *v -= factor * pv;
            }
            for ((v, xp), pv) in xr.iter_mut().zip(&xrow).zip(&prow) {
                *v -= factor * xp + factor_slope * pv;
            }
        }
    }
    (det, slope)
}

/// The Taylor series of the determinant of a 6×6 matrix from the matrix's series `a` (the
/// matrices of the powers `θ⁰ … θ³`, by rows): Gaussian elimination in truncated Taylor
/// arithmetic, with complete pivoting on the entries' values, so that a matrix of rank five
/// at `θ = 0` meets its small pivot last and never divides by it (the series then stay
/// accurate where `det J` is near zero). Not finite if a pivot's value is zero before the
/// last column.
///
/// The rows are updated whole (columns left of the pivot's are zeros or finished, and never
/// read again), a power at a time: fixed-length loops that vectorise.
#[inline(always)]
pub(crate) fn determinant_series(mut a: MatrixSeries) -> Taylor {
    let mut det = [1.0, 0.0, 0.0, 0.0];
    for c in 0..6 {
        let (mut pr, mut pc, mut largest) = (c, c, -1.0);
        for (r, row) in a[0].iter().enumerate().skip(c) {
            for (k, v) in row.iter().enumerate().skip(c) {
                if v.abs() > largest {
                    (pr, pc, largest) = (r, k, v.abs());
                }
            }
        }
        if pr != c {
            for power in a.iter_mut() {
                power.swap(pr, c);
            }
            det = det.map(|v| -v);
        }
        if pc != c {
            for row in a.iter_mut().flatten() {
                row.swap(pc, c);
            }
            det = det.map(|v| -v);
        }
        let pivot: Taylor = std::array::from_fn(|k| a[k][c][c]);
        det = mul(&det, &pivot);
        if c == 5 {
            break;
        }
        let inverse = reciprocal(&pivot);
        let prow: [[f64; 6]; 4] = std::array::from_fn(|k| a[k][c]);
        for r in c + 1..6 {
            let factor = mul(&std::array::from_fn(|k| a[k][r][c]), &inverse);
            for (k, power) in a.iter_mut().enumerate() {
                for (f, p) in factor[..=k].iter().zip(prow[..=k].iter().rev()) {
                    for (v, p) in power[r].iter_mut().zip(p) {
                        *v -= f * p;
                    }
                }
            }
        }
    }
    det
}

/// The Taylor series of `(t/h)⁻¹⁴` at the grid point `t = k h`, in `θ`:
/// `k⁻¹⁴ (1 − 14 θ/k + 105 θ²/k² − 560 θ³/k³)`.
#[inline(always)]
pub(crate) fn inverse_power_14(k: usize) -> Taylor {
    let x = 1.0 / k as f64;
    let x14 = x.powi(14);
    [
        x14,
        -14.0 * x14 * x,
        105.0 * x14 * x * x,
        -560.0 * x14 * x * x * x,
    ]
}

/// Whether the step between two grid points where `(g, h g′)` are `a` and `b` (in the
/// step's unit `θ`) clearly keeps the sign `sign`: the cubic Hermite interpolant of these
/// data stays above the smaller of `|g_a|`, `|g_b|` (its inner Bernstein coefficients
/// `g_a + h g′_a / 3` and `g_b − h g′_b / 3` do, in the direction of `sign`). A sign change
/// between two grid points of one sign needs `g` to turn back towards zero inside the step,
/// and a turn the slopes show takes the cubic below its smaller end; near a fold (`g`
/// touching zero) `g` is nearly a parabola there, which the cubic follows exactly. Steps that
/// fail this get the septic test ([`changes_sign`]).
#[inline(always)]
pub(crate) fn clearly_keeps_sign(a: &[f64; 2], b: &[f64; 2], sign: f64) -> bool {
    let smaller = (sign * a[0]).min(sign * b[0]);
    let inner = (sign * (a[0] + a[1] / 3.0)).min(sign * (b[0] - b[1] / 3.0));
    inner >= smaller && smaller > 0.0
}

/// How finely [`changes_sign`] subdivides: intervals of `2⁻ᴰᴱᴾᵀᴴ` of a step.
const DEPTH: u32 = 10;

/// The Bernstein coefficients on `[0, 1]` of the septic with Taylor series `a` at `θ = 0` and
/// `b` at `θ = 1` (both in `θ`): `b_j = Σ_k C(j, k)/C(7, k) a_k` from the left end, mirrored
/// (odd terms negated) from the right.
#[inline(always)]
fn bernstein(a: &Taylor, b: &Taylor) -> [f64; 8] {
    let from = |a: &Taylor, s: f64| {
        [
            a[0],
            a[0] + s * a[1] / 7.0,
            a[0] + s * 2.0 * a[1] / 7.0 + a[2] / 21.0,
            a[0] + s * (3.0 * a[1] / 7.0 + a[3] / 35.0) + a[2] / 7.0,
        ]
    };
    let [l0, l1, l2, l3] = from(a, 1.0);
    let [r0, r1, r2, r3] = from(b, -1.0);
    [l0, l1, l2, l3, r3, r2, r1, r0]
}

/// de Casteljau's split of a Bernstein polynomial at `θ = 1/2`: the coefficients on each half.
#[inline(always)]
fn split(c: &[f64; 8]) -> ([f64; 8], [f64; 8]) {
    let mut work = *c;
    let (mut left, mut right) = ([0.0; 8], [0.0; 8]);
    for level in 0..8 {
        left[level] = work[0];
        right[7 - level] = work[7 - level];
        for i in 0..7 - level {
            work[i] = 0.5 * (work[i] + work[i + 1]);
        }
    }
    (left, right)
}

/// Whether the septic with Taylor series `a` at `θ = 0` and `b` at `θ = 1` takes the sign
/// opposite to `sign` (or zero) somewhere on `(0, 1)`: the first such point found (a point
/// `θ` and the value there), searching the halves left first.
///
/// The polynomial lies in the convex hull of its Bernstein coefficients: if they all have
/// `sign`, so has the polynomial, and the search ends at once (the usual case). Otherwise the
/// interval is halved until each piece is certified, or a piece's end or midpoint has the
/// opposite sign, down to [`DEPTH`] halvings; a dip that falls between the points of the
/// finest halving is not reported. A non-finite coefficient counts as a sign change at
/// `θ = 0`.
pub(crate) fn changes_sign(a: &Taylor, b: &Taylor, sign: f64) -> Option<(f64, f64)> {
    let c = bernstein(a, b).map(|v| v * sign);
    if c.iter().all(|&v| v > 0.0) {
        return None;
    }
    if !c.iter().all(|v| v.is_finite()) {
        return Some((0.0, f64::NAN));
    }
    let mut stack = [([0.0; 8], 0.0, 0u32); DEPTH as usize + 2];
    stack[0] = (c, 0.0, 0);
    let mut len = 1;
    while len > 0 {
        len -= 1;
        let (c, start, depth) = stack[len];
        let width = 0.5f64.powi(depth as i32);
        if c.iter().all(|&v| v > 0.0) {
            continue;
        }
        if c[0] <= 0.0 {
            return Some((start, c[0] * sign));
        }
        if c[7] <= 0.0 {
            return Some((start + width, c[7] * sign));
        }
        let (left, right) = split(&c);
        let middle = start + 0.5 * width;
        if left[7] <= 0.0 {
            return Some((middle, left[7] * sign));
        }
        if depth < DEPTH {
            stack[len] = (right, middle, depth + 1);
            stack[len + 1] = (left, start, depth + 1);
            len += 2;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The septic `p(θ) = Σ c_i θ^i` as Taylor series at 0 and 1.
    fn series(c: &[f64; 8]) -> (Taylor, Taylor) {
        let at = |x: f64| -> Taylor {
            std::array::from_fn(|k| {
                let mut sum = 0.0;
                for (i, ci) in c.iter().enumerate().skip(k) {
                    let binomial: f64 = (0..k).map(|j| (i - j) as f64 / (j + 1) as f64).product();
                    sum += ci * binomial * x.powi((i - k) as i32);
                }
                sum
            })
        };
        (at(0.0), at(1.0))
    }

    /// Coefficients of `Π (θ − r_i)` times `s`, for seven roots (a septic).
    fn from_roots(roots: [f64; 7], s: f64) -> [f64; 8] {
        let mut c = [0.0; 8];
        c[0] = s;
        for (n, r) in roots.iter().enumerate() {
            for i in (0..=n + 1).rev() {
                let shifted = if i > 0 { c[i - 1] } else { 0.0 };
                c[i] = shifted - r * c[i];
            }
        }
        c
    }

    #[test]
    fn interval_test_finds_dips_and_passes_positive_septics() {
        // Roots outside [0, 1]: positive on it (sign chosen so p(0) > 0).
        let outside = from_roots([-0.5, -0.2, 1.3, 1.7, 2.0, -3.0, 4.0], 1.0);
        let (a, b) = series(&outside);
        let s = a[0].signum();
        assert_eq!(changes_sign(&a, &b, s), None);
        // A dip between 0.4 and 0.45 (two simple roots), the rest outside.
        let dip = from_roots([0.4, 0.45, 1.3, 1.7, 2.0, -3.0, -4.0], 1.0);
        let (a, b) = series(&dip);
        let (theta, value) = changes_sign(&a, &b, a[0].signum()).expect("a dip");
        assert!(
            (0.4..=0.45).contains(&theta) && value * a[0] < 0.0,
            "{theta}"
        );
        // Near a fold: a double root at θ = 0.3, pushed slightly below zero (a dip about
        // 0.01 wide) is found; lifted slightly above zero, it is not.
        let touch = from_roots([0.3, 0.3, 1.3, 1.7, 2.0, -3.0, -4.0], 1.0);
        let (a, _) = series(&touch);
        let s = a[0].signum();
        for (lift, found) in [(-1e-3, true), (1e-3, false)] {
            let mut shifted = touch;
            shifted[0] += lift * s;
            let (a, b) = series(&shifted);
            let change = changes_sign(&a, &b, s);
            assert_eq!(change.is_some(), found, "lift {lift}: {change:?}");
            if let Some((theta, _)) = change {
                assert!((theta - 0.3).abs() < 0.01, "{theta}");
            }
        }
    }

    #[test]
    fn bernstein_and_split_reproduce_the_septic() {
        let c = [0.3, -1.0, 2.0, 0.5, -0.7, 0.2, 0.1, -0.05];
        let (a, b) = series(&c);
        let value = |x: f64| c.iter().rev().fold(0.0, |s, ci| s * x + ci);
        let eval = |bern: &[f64; 8], x: f64| {
            (0..8)
                .map(|i| {
                    let binomial: f64 = (0..i).map(|j| (7 - j) as f64 / (j + 1) as f64).product();
                    bern[i] * binomial * x.powi(i as i32) * (1.0 - x).powi(7 - i as i32)
                })
                .sum::<f64>()
        };
        let bern = bernstein(&a, &b);
        let (left, right) = split(&bern);
        for x in [0.0, 0.1, 0.5, 0.77, 1.0] {
            assert!((eval(&bern, x) - value(x)).abs() < 1e-12, "{x}");
            assert!((eval(&left, x) - value(0.5 * x)).abs() < 1e-12, "{x}");
            assert!(
                (eval(&right, x) - value(0.5 + 0.5 * x)).abs() < 1e-12,
                "{x}"
            );
        }
    }

    /// `determinant_and_derivative` agrees with nalgebra's determinant and with the central
    /// difference of `det(a + θ x)`, on random matrices and on singular ones (two equal rows).
    #[test]
    fn determinant_and_derivative_match_nalgebra() {
        let mut x = 0.123_f64;
        let mut next = || {
            x = (x * 997.0 + 0.618).fract();
            2.0 * x - 1.0
        };
        for trial in 0..50 {
            let mut a: Rows<6> = std::array::from_fn(|_| std::array::from_fn(|_| next()));
            let b: Rows<6> = std::array::from_fn(|_| std::array::from_fn(|_| next()));
            if trial % 10 == 0 {
                a[1] = a[0];
            }
            let det_at =
                |t: f64| nalgebra::Matrix6::from_fn(|i, j| a[i][j] + t * b[i][j]).determinant();
            let (det, slope) = determinant_and_derivative(a, b);
            let expected = det_at(0.0);
            assert!(
                (det - expected).abs() <= 1e-12 * (1.0 + expected.abs()),
                "{det} vs {expected}"
            );
            let e = 1e-5;
            let difference = (det_at(e) - det_at(-e)) / (2.0 * e);
            assert!(
                (slope - difference).abs() <= 1e-8 * (1.0 + difference.abs()),
                "{slope} vs {difference}"
            );
        }
    }

    /// The determinant's series are those of `det (A + B θ + C θ² + D θ³)` by multilinearity
    /// (the coefficient of `θᵏ` is the sum of the determinants that take row `i` from the term
    /// of power `p_i`, over the powers with `Σ p_i = k`), on random matrices and on matrices
    /// whose `A` has rank five.
    #[test]
    fn determinant_series_is_the_multilinear_expansion() {
        let mut x = 0.3_f64;
        let mut next = || {
            x = (x * 997.0 + 0.618).fract();
            2.0 * x - 1.0
        };
        for trial in 0..20 {
            let mut terms: MatrixSeries = [[[0.0; 6]; 6]; 4];
            for v in terms.iter_mut().flatten().flatten() {
                *v = next();
            }
            if trial % 4 == 0 {
                // Row 5 of A is the sum of rows 0 and 1.
                let [a0, a1] = [terms[0][0], terms[0][1]];
                terms[0][5] = std::array::from_fn(|k| a0[k] + a1[k]);
            }
            let mut expected = [0.0; 4];
            for code in 0..4usize.pow(6) {
                let powers: [usize; 6] = std::array::from_fn(|i| (code >> (2 * i)) & 3);
                let k: usize = powers.iter().sum();
                if k < 4 {
                    let m = nalgebra::Matrix6::from_fn(|i, j| terms[powers[i]][i][j]);
                    expected[k] += m.determinant();
                }
            }
            let jet = determinant_series(terms);
            for (got, want) in jet.iter().zip(&expected) {
                assert!(
                    (got - want).abs() < 1e-12 * (1.0 + want.abs()),
                    "trial {trial}: {jet:?} vs {expected:?}"
                );
            }
        }
    }
}
