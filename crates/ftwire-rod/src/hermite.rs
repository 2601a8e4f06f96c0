//! Septic Hermite dense output: the weights that interpolate a function on `[x0, x0 + h]` from
//! its value and first three derivatives at both ends, exact for polynomials of degree 7, so
//! the interpolation error is `O(h⁸)`, the order of the integrator. The solver interpolates the
//! frame `q = (R, p)` between grid points from the jets `q, q', q'', q'''` (exact from the state
//! and eq. 1, 3, 4) and re-orthonormalises `R`.
//!
//! Guarded by `septic_hermite_reproduces_septics` (and the quintic basis, kept for comparison,
//! by `hermite_reproduces_quintics`).

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
/// A lower-order dense output than [`septic_hermite`], kept with its test for comparison.
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
}
