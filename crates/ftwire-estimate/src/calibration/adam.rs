//! Adam, the stochastic gradient method of Kingma and Ba (2015, "Adam: a method for stochastic
//! optimization", Algorithm 1), on a flat parameter slice.

/// The Adam optimiser's state: its step sizes and the first and second moment estimates of the
/// gradient, one per parameter.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Adam {
    learning_rate: f64,
    beta1: f64,
    beta2: f64,
    epsilon: f64,
    first: Vec<f64>,
    second: Vec<f64>,
    /// `β1ᵗ` and `β2ᵗ` after `t` steps, for the bias correction.
    beta1_power: f64,
    beta2_power: f64,
}

impl Adam {
    /// Adam for `parameters` parameters with step size `learning_rate` and the paper's
    /// defaults `β1 = 0.9`, `β2 = 0.999`, `ε = 1e-8`.
    pub(crate) fn new(parameters: usize, learning_rate: f64) -> Self {
        Self {
            learning_rate,
            beta1: 0.9,
            beta2: 0.999,
            epsilon: 1e-8,
            first: vec![0.0; parameters],
            second: vec![0.0; parameters],
            beta1_power: 1.0,
            beta2_power: 1.0,
        }
    }

    /// The step size.
    pub(crate) fn learning_rate(&self) -> f64 {
        self.learning_rate
    }

    /// Changes the step size (the moment estimates are kept).
    pub(crate) fn set_learning_rate(&mut self, learning_rate: f64) {
        self.learning_rate = learning_rate;
    }

    /// One step: moves `parameters` against `gradient` (both in the same layout).
    pub(crate) fn step(&mut self, parameters: &mut [f64], gradient: &[f64]) {
        self.beta1_power *= self.beta1;
        self.beta2_power *= self.beta2;
        let step = self.learning_rate / (1.0 - self.beta1_power);
        let second_correction = 1.0 / (1.0 - self.beta2_power);
        for (((p, g), m), v) in parameters
            .iter_mut()
            .zip(gradient)
            .zip(&mut self.first)
            .zip(&mut self.second)
        {
            *m = self.beta1 * *m + (1.0 - self.beta1) * g;
            *v = self.beta2 * *v + (1.0 - self.beta2) * g * g;
            *p -= step * *m / ((*v * second_correction).sqrt() + self.epsilon);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Adam;

    /// Adam minimises a badly scaled quadratic `Σ kᵢ (xᵢ − 1)²`.
    #[test]
    fn minimises_a_quadratic() {
        let scales = [1.0, 100.0, 0.01];
        let mut x = [0.0; 3];
        let mut adam = Adam::new(3, 0.05);
        for _ in 0..2000 {
            let gradient: Vec<f64> = x
                .iter()
                .zip(scales)
                .map(|(xi, k)| 2.0 * k * (xi - 1.0))
                .collect();
            adam.step(&mut x, &gradient);
        }
        for xi in x {
            approx::assert_abs_diff_eq!(xi, 1.0, epsilon = 1e-3);
        }
    }
}
