//! Many solves at once. With the `parallel` feature they run on rayon's thread pool; the
//! results are in input order and identical to the serial ones either way.

use nalgebra::Vector6;

use crate::{Rod, RodError, Solution};

/// Solves each configuration (see [`Rod::solve`]), in input order.
///
/// # Example
/// ```
/// use nalgebra::Vector6;
/// use ftwire_rod::{Rod, WireParams, batch::solve_all};
/// let rod = Rod::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
/// let results = solve_all(&rod, &[Vector6::new(0.0, 0.0, 0.01, 0.0, 0.0, 0.0), Vector6::zeros()], 16);
/// assert!(results[0].is_ok() && results[1].is_err());
/// # Ok::<(), ftwire_rod::RodError>(())
/// ```
pub fn solve_all(
    rod: &Rod,
    configurations: &[Vector6<f64>],
    nodes: usize,
) -> Vec<Result<Solution, RodError>> {
    map(configurations, |a| rod.solve(a, nodes))
}

/// Tests each configuration for stability (see [`Rod::is_stable`]), in input order.
pub fn stable_all(rod: &Rod, configurations: &[Vector6<f64>]) -> Vec<Result<bool, RodError>> {
    map(configurations, |a| rod.is_stable(a))
}

#[cfg(feature = "parallel")]
fn map<T: Send>(items: &[Vector6<f64>], f: impl Fn(&Vector6<f64>) -> T + Sync + Send) -> Vec<T> {
    use rayon::prelude::*;
    items.par_iter().map(f).collect()
}

#[cfg(not(feature = "parallel"))]
fn map<T>(items: &[Vector6<f64>], f: impl Fn(&Vector6<f64>) -> T) -> Vec<T> {
    items.iter().map(f).collect()
}
