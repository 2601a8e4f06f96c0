//! The drift term of `calibrate --log`: an offset linear in time, kept only when the training
//! block shows it and the validation block agrees ([`choose_drift`]).

use ftwire_estimate::calibration::{Drift, TrainParams};
use nalgebra::{DMatrix, DVector, Vector6};

use super::labelled::Labelled;

/// The smallest t statistic of a kept drift term ([`choose_drift`]): without a drift, each
/// channel's statistic is about standard normal, so the largest of six exceeds 5 with a
/// probability of about 2e-6.
pub const DRIFT_T_STATISTIC: f64 = 5.0;

/// The drift term, if the training block shows one and it predicts the validation block
/// better than none: least squares of the labels on `(raw, 1, t − t_ref)` over the training
/// block (`t_ref` its last record's time). The drift is kept only when its coefficient is
/// significant, `|t| ≥` [`DRIFT_T_STATISTIC`] on some channel of `a` (the ordinary
/// least-squares t statistic, `β / (σ̂ √[(XᵀX)⁻¹]_tt)`), and the fit with it has the smaller
/// error on the validation block, in units of the labels' spread per channel. Both tests
/// guard against a drift fitted to label noise, which extrapolated over the test block would
/// make the map worse.
pub(super) fn choose_drift(labelled: &[Labelled], train: &TrainParams) -> Option<Drift> {
    #[allow(
        clippy::cast_precision_loss,
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss
    )] // fractions of a count far below 2⁵²
    let count = |f: f64| (labelled.len() as f64 * f).floor() as usize;
    let n_train = count(train.split.train).min(labelled.len());
    let n_validation = count(train.split.validation).min(labelled.len() - n_train);
    let (fit, rest) = labelled.split_at(n_train);
    let validation = rest.get(..n_validation)?;
    let reference_time = fit.last()?.time;
    let span = (reference_time - fit.first()?.time).max(1.0);
    let spread = label_spread(fit);
    let score = |with_time: bool| -> Option<(f64, DMatrix<f64>)> {
        let w = least_squares(fit, with_time, reference_time, span)?;
        let error = validation
            .iter()
            .map(|l| {
                let predicted = regressors(l, with_time, reference_time, span).transpose() * &w;
                (0..6)
                    .map(|k| ((predicted[k] - l.label[k]) / spread[k]).powi(2))
                    .sum::<f64>()
            })
            .sum::<f64>();
        Some((error, w))
    };
    let (without, _) = score(false)?;
    let (with, w) = score(true)?;
    if with >= without || drift_t_statistic(fit, &w, reference_time, span)? < DRIFT_T_STATISTIC {
        return None;
    }
    let rate = Vector6::from_fn(|k, _| w[(7, k)] / span);
    let last = labelled.last()?.time;
    Some(Drift {
        reference_time,
        rate,
        span: Some([fit.first()?.time.min(last), last.max(fit.first()?.time)]),
    })
}

/// The largest `|t|` over the channels of `a` of the time regressor's coefficient in the
/// least-squares fit `w` (with time) of `rows`.
fn drift_t_statistic(
    rows: &[Labelled],
    w: &DMatrix<f64>,
    reference: f64,
    span: f64,
) -> Option<f64> {
    let x = DMatrix::from_fn(rows.len(), 8, |i, j| {
        regressors(&rows[i], true, reference, span)[j]
    });
    let inverse = (x.transpose() * &x).try_inverse()?;
    let residual = x * w - DMatrix::from_fn(rows.len(), 6, |i, k| rows[i].label[k]);
    #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
    let dof = rows.len().saturating_sub(8).max(1) as f64;
    (0..6)
        .map(|k| {
            let sigma2 = residual.column(k).norm_squared() / dof;
            let se = (sigma2 * inverse[(7, 7)]).sqrt();
            if se > 0.0 {
                (w[(7, k)] / se).abs()
            } else {
                0.0
            }
        })
        .reduce(f64::max)
}

/// Each label channel's standard deviation (1 where it is zero).
fn label_spread(rows: &[Labelled]) -> Vector6<f64> {
    #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
    let n = rows.len().max(1) as f64;
    let mean = rows.iter().fold(Vector6::zeros(), |s, l| s + l.label) / n;
    let var = rows.iter().fold(Vector6::zeros(), |s, l| {
        let d = l.label - mean;
        s + d.component_mul(&d)
    }) / n;
    var.map(|v| if v > 0.0 { v.sqrt() } else { 1.0 })
}

/// The regressors of one record: the reading, 1, and with `with_time` the time since
/// `reference` in units of `span`.
fn regressors(l: &Labelled, with_time: bool, reference: f64, span: f64) -> DVector<f64> {
    let mut x: Vec<f64> = l.raw.iter().copied().collect();
    x.push(1.0);
    if with_time {
        x.push((l.time - reference) / span);
    }
    DVector::from_vec(x)
}

/// The least-squares coefficients (regressors × 6) of the labels of `rows`.
fn least_squares(
    rows: &[Labelled],
    with_time: bool,
    reference: f64,
    span: f64,
) -> Option<DMatrix<f64>> {
    let width = if with_time { 8 } else { 7 };
    if rows.len() <= width {
        return None;
    }
    let x = DMatrix::from_fn(rows.len(), width, |i, j| {
        regressors(&rows[i], with_time, reference, span)[j]
    });
    let y = DMatrix::from_fn(rows.len(), 6, |i, k| rows[i].label[k]);
    x.svd(true, true).solve(&y, 1e-12).ok()
}
