//! The multilayer perceptron of the calibration: 6 inputs, hidden layers of a chosen width and
//! activation, 6 linear outputs, and its gradient by backpropagation.
//!
//! All weights and biases live in one flat parameter vector, layer after layer, each layer its
//! weight matrix row by row (`outputs × inputs`) and then its bias. The gradient has the same
//! layout, so the optimiser ([`super::adam`]) works on plain slices. The gradient is checked
//! against central finite differences of the loss in `tests/calibration_gradient.rs`.

use nalgebra::Vector6;
use rand::{Rng, RngExt};
use serde::{Deserialize, Serialize};

use crate::EstimateError;

/// Widest hidden layer allowed. Inference keeps its activations in two stack buffers of this
/// size, so it never allocates.
pub const MAX_WIDTH: usize = 256;

/// Most hidden layers allowed.
pub const MAX_HIDDEN_LAYERS: usize = 8;

/// Inputs and outputs of the network: the six F/T channels and the six components of `a`.
const IO: usize = 6;

/// The nonlinearity of the hidden layers (the output layer is linear).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Activation {
    /// `tanh(x)` (default): smooth and bounded, the classic choice for small regression nets.
    #[default]
    Tanh,
    /// GELU in its tanh form, `x/2 · (1 + tanh(√(2/π) (x + 0.044715 x³)))` (Hendrycks and
    /// Gimpel 2016).
    Gelu,
}

/// `√(2/π)`, the GELU approximation's scale.
const GELU_SCALE: f64 = 0.797_884_560_802_865_4;
/// The GELU approximation's cubic coefficient.
const GELU_CUBIC: f64 = 0.044_715;

impl Activation {
    /// The activation at `x`.
    pub fn value(self, x: f64) -> f64 {
        match self {
            Self::Tanh => x.tanh(),
            Self::Gelu => 0.5 * x * (1.0 + (GELU_SCALE * (x + GELU_CUBIC * x * x * x)).tanh()),
        }
    }

    /// The activation and its derivative at `x`.
    pub fn value_and_derivative(self, x: f64) -> (f64, f64) {
        match self {
            Self::Tanh => {
                let t = x.tanh();
                (t, 1.0 - t * t)
            }
            Self::Gelu => {
                let x2 = x * x;
                let t = (GELU_SCALE * (x + GELU_CUBIC * x2 * x)).tanh();
                let value = 0.5 * x * (1.0 + t);
                let derivative = 0.5 * (1.0 + t)
                    + 0.5 * x * (1.0 - t * t) * GELU_SCALE * (1.0 + 3.0 * GELU_CUBIC * x2);
                (value, derivative)
            }
        }
    }
}

/// A fully connected network `R⁶ → R⁶` with hidden layers of the given widths.
///
/// The invariants (widths in `1..=MAX_WIDTH`, at most [`MAX_HIDDEN_LAYERS`] hidden layers, the
/// parameter vector of the right length and finite) hold from construction on.
///
/// # Example
/// ```
/// use ftwire_estimate::calibration::{Activation, Mlp};
/// use nalgebra::Vector6;
/// use rand::SeedableRng;
///
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
/// let mlp = Mlp::new(&[16, 16], Activation::Tanh, &mut rng)?;
/// assert_eq!(mlp.parameters().len(), (6 * 16 + 16) + (16 * 16 + 16) + (16 * 6 + 6));
/// assert!(mlp.forward(&Vector6::repeat(0.5)).iter().all(|v| v.is_finite()));
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Mlp {
    hidden: Vec<usize>,
    activation: Activation,
    parameters: Vec<f64>,
}

impl Mlp {
    /// A network with Glorot-uniform weights (`U(±√(6/(fan_in + fan_out)))`) and zero biases,
    /// drawn from `rng`.
    ///
    /// # Errors
    /// [`EstimateError::InvalidSetting`] when a width is outside `1..=MAX_WIDTH` or there are
    /// more than [`MAX_HIDDEN_LAYERS`] hidden layers.
    pub fn new<R: Rng + ?Sized>(
        hidden: &[usize],
        activation: Activation,
        rng: &mut R,
    ) -> Result<Self, EstimateError> {
        check_hidden(hidden)?;
        let mut parameters = Vec::with_capacity(parameter_count(hidden));
        for (inputs, outputs) in layer_shapes(hidden) {
            #[allow(clippy::cast_precision_loss)] // widths are at most MAX_WIDTH
            let bound = (6.0 / (inputs + outputs) as f64).sqrt();
            parameters.extend((0..inputs * outputs).map(|_| rng.random_range(-bound..=bound)));
            parameters.extend(std::iter::repeat_n(0.0, outputs));
        }
        Ok(Self {
            hidden: hidden.to_vec(),
            activation,
            parameters,
        })
    }

    /// A network with the given parameters (the flat layout described in the module docs).
    ///
    /// # Errors
    /// As [`Mlp::new`]; [`EstimateError::CalibrationShape`] when `parameters` has the wrong
    /// length for `hidden`; [`EstimateError::CalibrationValue`] when a parameter is not finite.
    pub fn from_parameters(
        hidden: &[usize],
        activation: Activation,
        parameters: Vec<f64>,
    ) -> Result<Self, EstimateError> {
        check_hidden(hidden)?;
        let expected = parameter_count(hidden);
        if parameters.len() != expected {
            return Err(EstimateError::CalibrationShape {
                what: "parameters".into(),
                expected,
                found: parameters.len(),
            });
        }
        if let Some(index) = parameters.iter().position(|p| !p.is_finite()) {
            return Err(EstimateError::CalibrationValue {
                what: "parameters".into(),
                index,
                value: parameters.get(index).copied().unwrap_or(f64::NAN),
                allowed: "finite numbers",
            });
        }
        Ok(Self {
            hidden: hidden.to_vec(),
            activation,
            parameters,
        })
    }

    /// The hidden layer widths.
    pub fn hidden(&self) -> &[usize] {
        &self.hidden
    }

    /// The hidden layers' activation.
    pub fn activation(&self) -> Activation {
        self.activation
    }

    /// All weights and biases, in the flat layout of the module docs.
    pub fn parameters(&self) -> &[f64] {
        &self.parameters
    }

    /// The parameters, for the optimiser (which keeps them finite or stops).
    pub(crate) fn parameters_mut(&mut self) -> &mut [f64] {
        &mut self.parameters
    }

    /// Sets the output layer's weights and biases to zero, so that the network starts at zero
    /// output (a residual network then starts at the map it is a residual of).
    pub(crate) fn zero_output_layer(&mut self) {
        let (inputs, outputs) = layer_shape(&self.hidden, self.hidden.len());
        let start = self.parameters.len() - (inputs + 1) * outputs;
        self.parameters[start..].fill(0.0);
    }

    /// Multiplies output `i` by `scale[i]` (the output layer's rows and biases), so that a net
    /// trained on scaled targets gives unscaled outputs.
    pub(crate) fn scale_outputs(&mut self, scale: &Vector6<f64>) {
        let (inputs, outputs) = layer_shape(&self.hidden, self.hidden.len());
        let start = self.parameters.len() - (inputs + 1) * outputs;
        let (weights, bias) = self.parameters[start..].split_at_mut(inputs * outputs);
        for ((row, b), s) in weights.chunks_exact_mut(inputs).zip(bias).zip(scale.iter()) {
            row.iter_mut().for_each(|w| *w *= s);
            *b *= s;
        }
    }

    /// `(inputs, outputs)` of each layer, input layer first.
    pub fn layer_shapes(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        layer_shapes(&self.hidden)
    }

    /// Each layer's `(inputs, weights, bias)`, first to last: the weights row by row.
    pub(crate) fn layers(&self) -> impl Iterator<Item = (usize, &[f64], &[f64])> + '_ {
        let mut rest = self.parameters.as_slice();
        self.layer_shapes().map(move |(inputs, outputs)| {
            let (weights, tail) = rest.split_at(inputs * outputs);
            let (bias, tail) = tail.split_at(outputs);
            rest = tail;
            (inputs, weights, bias)
        })
    }

    /// The network's output at `x`. Allocation-free.
    pub fn forward(&self, x: &Vector6<f64>) -> Vector6<f64> {
        let mut current = [0.0; MAX_WIDTH];
        let mut next = [0.0; MAX_WIDTH];
        current[..IO].copy_from_slice(x.as_slice());
        let last = self.hidden.len();
        for (layer, (inputs, weights, bias)) in self.layers().enumerate() {
            let input = &current[..inputs];
            let hidden = layer < last;
            for ((row, b), out) in weights.chunks_exact(inputs).zip(bias).zip(next.iter_mut()) {
                let s = dot(row, input) + b;
                *out = if hidden { self.activation.value(s) } else { s };
            }
            std::mem::swap(&mut current, &mut next);
        }
        Vector6::from_column_slice(&current[..IO])
    }

    /// The loss `(1 / 6n) Σᵢ |f(xᵢ) − yᵢ|²` over the pairs `(inputs[i], targets[i])`.
    ///
    /// # Errors
    /// [`EstimateError::SampleCountMismatch`] when the slices differ in length.
    pub fn loss(
        &self,
        inputs: &[Vector6<f64>],
        targets: &[Vector6<f64>],
    ) -> Result<f64, EstimateError> {
        check_pairs(inputs, targets)?;
        Ok(mean_squared_error(
            inputs
                .iter()
                .zip(targets)
                .map(|(x, y)| (self.forward(x) - y).norm_squared()),
            inputs.len(),
        ))
    }

    /// The loss of [`Mlp::loss`] and its gradient with respect to [`Mlp::parameters`], by
    /// backpropagation.
    ///
    /// # Errors
    /// As [`Mlp::loss`].
    pub fn loss_and_gradient(
        &self,
        inputs: &[Vector6<f64>],
        targets: &[Vector6<f64>],
    ) -> Result<(f64, Vec<f64>), EstimateError> {
        check_pairs(inputs, targets)?;
        let mut workspace = Backprop::new(self);
        let mut gradient = vec![0.0; self.parameters.len()];
        let loss = workspace.accumulate(
            self,
            inputs.iter().zip(targets).map(|(x, y)| (x, y, 1.0)),
            inputs.len(),
            &mut gradient,
        );
        Ok((loss, gradient))
    }
}

/// The buffers of one backpropagation: each layer's input and each hidden layer's activation
/// derivative, and two delta vectors. Allocated once per training run.
#[derive(Debug, Clone)]
pub(crate) struct Backprop {
    /// `activations[l]`: the input of layer `l` (the network input for `l = 0`).
    activations: Vec<Vec<f64>>,
    /// `derivatives[l]`: the activation derivative at hidden layer `l`'s pre-activation.
    derivatives: Vec<Vec<f64>>,
    delta: Vec<f64>,
    delta_previous: Vec<f64>,
}

impl Backprop {
    /// Buffers sized for `mlp`.
    pub(crate) fn new(mlp: &Mlp) -> Self {
        let widest = mlp.hidden.iter().copied().fold(IO, usize::max);
        Self {
            activations: mlp.layer_shapes().map(|(i, _)| vec![0.0; i]).collect(),
            derivatives: mlp.hidden.iter().map(|&w| vec![0.0; w]).collect(),
            delta: vec![0.0; widest],
            delta_previous: vec![0.0; widest],
        }
    }

    /// Adds the gradient of the loss `(1 / 6n) Σ |g f(x) − y|²` over the triples `(x, y, g)`
    /// to `gradient` and returns that loss: `g` is a fixed gate on the network's output (1 for
    /// the plain loss; see [`super::TrainParams::through_zero`]); `n` is the number of triples
    /// (given, so that the caller's iterator need not be counted first).
    pub(crate) fn accumulate<'a>(
        &mut self,
        mlp: &Mlp,
        triples: impl Iterator<Item = (&'a Vector6<f64>, &'a Vector6<f64>, f64)>,
        n: usize,
        gradient: &mut [f64],
    ) -> f64 {
        #[allow(clippy::cast_precision_loss)] // sample counts are far below 2⁵²
        let scale = 2.0 / (IO as f64 * n.max(1) as f64);
        let mut sum = 0.0;
        for (x, y, gate) in triples {
            let output = self.forward(mlp, x);
            for ((d, o), t) in self.delta.iter_mut().zip(output.iter()).zip(y.iter()) {
                let e = gate * o - t;
                sum += e * e;
                *d = scale * gate * e;
            }
            self.backward(mlp, gradient);
        }
        mean_squared_error(std::iter::once(sum), n)
    }

    /// Forward pass keeping each layer's input and each hidden derivative.
    fn forward(&mut self, mlp: &Mlp, x: &Vector6<f64>) -> Vector6<f64> {
        let mut output = Vector6::zeros();
        self.activations[0].copy_from_slice(x.as_slice());
        let last = mlp.hidden.len();
        for (layer, (inputs, weights, bias)) in mlp.layers().enumerate() {
            let (done, ahead) = self.activations.split_at_mut(layer + 1);
            let input = &done[layer];
            let rows = weights.chunks_exact(inputs).zip(bias);
            if layer < last {
                let derivative = &mut self.derivatives[layer];
                for (((row, b), out), d) in rows.zip(ahead[0].iter_mut()).zip(derivative) {
                    (*out, *d) = mlp.activation.value_and_derivative(dot(row, input) + b);
                }
            } else {
                for ((row, b), out) in rows.zip(output.iter_mut()) {
                    *out = dot(row, input) + b;
                }
            }
        }
        output
    }

    /// Backward pass from the output delta in `self.delta`, adding into `gradient`.
    fn backward(&mut self, mlp: &Mlp, gradient: &mut [f64]) {
        let mut end = mlp.parameters.len();
        for layer in (0..=mlp.hidden.len()).rev() {
            let (inputs, outputs) = layer_shape(&mlp.hidden, layer);
            let start = end - (inputs + 1) * outputs;
            let weights = &mlp.parameters[start..start + inputs * outputs];
            let (weight_gradient, bias_gradient) =
                gradient[start..end].split_at_mut(inputs * outputs);
            let input = &self.activations[layer];
            let delta = &self.delta[..outputs];
            for ((row_gradient, d), bias_d) in weight_gradient
                .chunks_exact_mut(inputs)
                .zip(delta)
                .zip(bias_gradient)
            {
                *bias_d += d;
                axpy(row_gradient, *d, input);
            }
            if layer > 0 {
                let previous = &mut self.delta_previous[..inputs];
                previous.fill(0.0);
                for (row, d) in weights.chunks_exact(inputs).zip(delta) {
                    axpy(previous, *d, row);
                }
                for (p, derivative) in previous.iter_mut().zip(&self.derivatives[layer - 1]) {
                    *p *= derivative;
                }
                std::mem::swap(&mut self.delta, &mut self.delta_previous);
            }
            end = start;
        }
    }
}

/// Rejects hidden layer lists outside the allowed sizes.
fn check_hidden(hidden: &[usize]) -> Result<(), EstimateError> {
    if hidden.len() > MAX_HIDDEN_LAYERS {
        #[allow(clippy::cast_precision_loss)] // a short list
        return Err(EstimateError::InvalidSetting {
            field: "hidden.len()",
            value: hidden.len() as f64,
            allowed: "at most MAX_HIDDEN_LAYERS (8) hidden layers",
        });
    }
    if let Some(&width) = hidden.iter().find(|&&w| w == 0 || w > MAX_WIDTH) {
        #[allow(clippy::cast_precision_loss)] // compared with MAX_WIDTH
        return Err(EstimateError::InvalidSetting {
            field: "hidden",
            value: width as f64,
            allowed: "widths from 1 to MAX_WIDTH (256)",
        });
    }
    Ok(())
}

/// Rejects input and target lists of different lengths.
fn check_pairs(inputs: &[Vector6<f64>], targets: &[Vector6<f64>]) -> Result<(), EstimateError> {
    if inputs.len() == targets.len() {
        Ok(())
    } else {
        Err(EstimateError::SampleCountMismatch {
            raw: inputs.len(),
            labels: targets.len(),
            first_unpaired: inputs.len().min(targets.len()),
        })
    }
}

/// `(inputs, outputs)` of layer `layer` (0 is the first hidden layer's, `hidden.len()` the
/// output layer's).
fn layer_shape(hidden: &[usize], layer: usize) -> (usize, usize) {
    let width = |l: usize| {
        if l == 0 {
            IO
        } else {
            hidden.get(l - 1).copied().unwrap_or(IO)
        }
    };
    (width(layer), width(layer + 1))
}

/// `(inputs, outputs)` of every layer, first to last.
fn layer_shapes(hidden: &[usize]) -> impl DoubleEndedIterator<Item = (usize, usize)> + '_ {
    (0..=hidden.len()).map(move |layer| layer_shape(hidden, layer))
}

/// Number of weights and biases of a network with these hidden widths.
pub fn parameter_count(hidden: &[usize]) -> usize {
    layer_shapes(hidden).map(|(i, o)| (i + 1) * o).sum()
}

/// `sum / (6 n)`, the mean over samples and outputs (0 for no samples).
pub(crate) fn mean_squared_error(sums: impl Iterator<Item = f64>, n: usize) -> f64 {
    #[allow(clippy::cast_precision_loss)] // sample counts are far below 2⁵²
    let count = (IO * n.max(1)) as f64;
    sums.sum::<f64>() / count
}

/// `Σ aᵢ bᵢ` with four independent partial sums (so the compiler can vectorise it; the order is
/// fixed, so results are reproducible).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut partial = [0.0; 4];
    let (a4, a_tail) = a.split_at(a.len() - a.len() % 4);
    let (b4, b_tail) = b.split_at(a4.len().min(b.len()));
    for (x, y) in a4.chunks_exact(4).zip(b4.chunks_exact(4)) {
        for ((p, xi), yi) in partial.iter_mut().zip(x).zip(y) {
            *p += xi * yi;
        }
    }
    let tail: f64 = a_tail.iter().zip(b_tail).map(|(x, y)| x * y).sum();
    (partial[0] + partial[1]) + (partial[2] + partial[3]) + tail
}

/// `y += alpha x`.
fn axpy(y: &mut [f64], alpha: f64, x: &[f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}
