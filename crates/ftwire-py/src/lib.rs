//! Python bindings of ftwire (the `ftwire` package's native module `ftwire._ftwire`).
//!
//! Conventions, as in the Rust crates: SI units (m, rad, N, N·m, s, kg/m³); a configuration
//! `a = (τ1, τ2, τ3, f1, f2, f3)` is the wrench on the base gripper, **torque first**, in the
//! base clamp frame; a raw F/T reading is **force first**, in the sensor frame; a pose `b` is
//! the second gripper's clamp pose in the base clamp frame. Arrays are NumPy `float64`,
//! C-contiguous, with a leading batch axis `N` for batched arguments. Bad input raises
//! `ValueError` naming the argument; a computation without an answer raises `RuntimeError`.
//!
//! Models are immutable; work is done by methods and free functions over arrays. Batches
//! release the GIL and run in parallel over rows (rayon).

mod calibration;
mod control;
mod error;
mod identify;
mod input;
mod interrupt;
mod log;
mod plan;
mod pose;
mod shape;
mod sim;
mod wire;

use pyo3::prelude::*;

/// The native module; `python/ftwire/__init__.py` re-exports it.
#[pymodule]
fn _ftwire(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<wire::Wire>()?;
    m.add_class::<wire::Solution>()?;
    m.add_class::<calibration::Calibration>()?;
    m.add_class::<calibration::Mounting>()?;
    m.add_class::<shape::ShapeEstimator>()?;
    m.add_class::<identify::Identification>()?;
    m.add_class::<control::Controller>()?;
    m.add_class::<sim::SimulatedRig>()?;
    m.add_function(wrap_pyfunction!(log::read_log, m)?)?;
    m.add_function(wrap_pyfunction!(identify::identify, m)?)?;
    m.add_function(wrap_pyfunction!(plan::plan, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
