//! Summary statistics that several layers share.

/// The median of the finite values (NaN when there are none).
///
/// ```
/// assert_eq!(ftwire_core::stats::median(&[3.0, f64::NAN, 1.0, 2.0]), 2.0);
/// assert_eq!(ftwire_core::stats::median(&[1.0, 4.0]), 2.5);
/// assert!(ftwire_core::stats::median(&[]).is_nan());
/// ```
pub fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}
