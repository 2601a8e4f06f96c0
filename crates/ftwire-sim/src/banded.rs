//! Symmetric banded matrices and their Cholesky factorisation.
//!
//! The rod's degrees of freedom are interleaved node by node, `(x_k, y_k, z_k, θ_k)`, so that
//! every stencil couples only indices within a band of half-width 10. Factorisation costs
//! `O(n·b²)` and the solve `O(n·b)`.

/// A symmetric `n × n` matrix with `A[i][j] = 0` for `|i − j| > bandwidth`; only the lower band
/// is stored.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct BandedSym {
    n: usize,
    bw: usize,
    /// `data[i·(bw+1) + k] = A[i][i − k]`.
    data: Vec<f64>,
}

impl BandedSym {
    pub(crate) fn zeros(n: usize, bw: usize) -> Self {
        Self {
            n,
            bw,
            data: vec![0.0; n * (bw + 1)],
        }
    }

    /// Adds `v` to `A[i][j]` for `i ≥ j` (the caller adds each unordered pair once).
    #[inline]
    pub(crate) fn add_lower(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(i >= j && i - j <= self.bw && i < self.n);
        self.data[i * (self.bw + 1) + (i - j)] += v;
    }

    /// `A[i][j]` (either triangle).
    #[cfg(test)]
    pub(crate) fn get(&self, i: usize, j: usize) -> f64 {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        if i - j > self.bw {
            0.0
        } else {
            self.data[i * (self.bw + 1) + (i - j)]
        }
    }

    /// Replaces row and column `i` by those of the identity.
    pub(crate) fn pin(&mut self, i: usize) {
        for k in 0..=self.bw {
            self.data[i * (self.bw + 1) + k] = 0.0;
            let r = i + k;
            if k > 0 && r < self.n {
                self.data[r * (self.bw + 1) + k] = 0.0;
            }
        }
        self.data[i * (self.bw + 1)] = 1.0;
    }

    /// Adds `shift[i]` to each diagonal entry.
    pub(crate) fn add_diagonal(&mut self, shift: &[f64]) {
        for (i, s) in shift.iter().enumerate().take(self.n) {
            self.data[i * (self.bw + 1)] += s;
        }
    }

    /// `y = A x`.
    pub(crate) fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n];
        for i in 0..self.n {
            for k in 0..=self.bw.min(i) {
                let j = i - k;
                let a = self.data[i * (self.bw + 1) + k];
                y[i] += a * x[j];
                if k > 0 {
                    y[j] += a * x[i];
                }
            }
        }
        y
    }

    /// The Cholesky factor `L` (`A = L·Lᵀ`), or `None` if `A` is not numerically positive
    /// definite.
    pub(crate) fn cholesky(&self) -> Option<BandedCholesky> {
        let (n, bw) = (self.n, self.bw);
        let w = bw + 1;
        let mut l = vec![0.0; n * w];
        for i in 0..n {
            let first = i.saturating_sub(bw);
            for j in first..=i {
                let mut s = self.data[i * w + (i - j)];
                for k in first.max(j.saturating_sub(bw))..j {
                    s -= l[i * w + (i - k)] * l[j * w + (j - k)];
                }
                if i == j {
                    let scale = self.data[i * w].abs();
                    if s.is_nan() || s <= 1e-13 * scale || !s.is_finite() {
                        return None;
                    }
                    l[i * w] = s.sqrt();
                } else {
                    l[i * w + (i - j)] = s / l[j * w];
                }
            }
        }
        Some(BandedCholesky { n, bw, l })
    }
}

/// The Cholesky factor of a [`BandedSym`].
#[derive(Debug, Clone)]
pub(crate) struct BandedCholesky {
    n: usize,
    bw: usize,
    l: Vec<f64>,
}

impl BandedCholesky {
    /// Solves `A x = b`.
    pub(crate) fn solve(&self, b: &[f64]) -> Vec<f64> {
        let w = self.bw + 1;
        let mut y = b.to_vec();
        for i in 0..self.n {
            let mut s = y[i];
            let first = i.saturating_sub(self.bw);
            for (k, yk) in y.iter().enumerate().take(i).skip(first) {
                s -= self.l[i * w + (i - k)] * yk;
            }
            y[i] = s / self.l[i * w];
        }
        for i in (0..self.n).rev() {
            let mut s = y[i];
            let end = (i + w).min(self.n);
            for (r, yr) in y.iter().enumerate().take(end).skip(i + 1) {
                s -= self.l[r * w + (r - i)] * yr;
            }
            y[i] = s / self.l[i * w];
        }
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_banded_spd_system_and_rejects_an_indefinite_one() {
        let n = 12;
        let mut a = BandedSym::zeros(n, 3);
        for i in 0..n {
            a.add_lower(i, i, 6.0 + i as f64 * 0.1);
            for k in 1..=3 {
                if i >= k {
                    a.add_lower(i, i - k, 1.0 / (k as f64 + 0.5));
                }
            }
        }
        let x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let b = a.mul_vec(&x);
        let chol = a.cholesky().expect("SPD");
        let y = chol.solve(&b);
        for (xi, yi) in x.iter().zip(&y) {
            assert!((xi - yi).abs() < 1e-12);
        }
        let mut bad = a.clone();
        bad.add_lower(5, 5, -20.0);
        assert!(bad.cholesky().is_none());
        bad.pin(5);
        assert!(bad.cholesky().is_some());
        assert!((bad.get(5, 6)).abs() < 1e-300 && (bad.get(6, 5)).abs() < 1e-300);
    }
}
