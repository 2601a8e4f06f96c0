//! The bridge between the Kirchhoff model (`ftwire-rod`) and the ground-truth simulator
//! (`ftwire-sim`). Only the binary crate sees both sides of the wall (DESIGN.md, "Layers").

use ftwire_core::Pose;
use ftwire_rod::{Rod, RodError, Shape};
use ftwire_sim::{DiscreteRod, InitialGuess};
use nalgebra::{Translation3, Vector6};

/// The Kirchhoff shape `Φ(a)` sampled on the simulator's discretisation, as an initial guess
/// for Newton, so that the simulator lands on the equilibrium branch of `a` (the same tip pose
/// can belong to several stable equilibria).
///
/// `model` and `rod` must describe the same wire (length, stiffness). The simulator asks for
/// poses at the node arc lengths `(k − ½)·h` and edge arc lengths `j·h`; the model is solved at
/// every multiple of `h/2` in `[0, L]`, and the ghost half-edges outside `[0, L]` continue
/// straight along the end tangents (they are fixed by the clamps anyway).
///
/// # Errors
/// The model's errors for `a` (non-finite, outside `A`).
pub fn kirchhoff_guess(
    model: &Rod,
    a: &Vector6<f64>,
    rod: &DiscreteRod,
) -> Result<InitialGuess, RodError> {
    let half_steps = (2.0 * model.wire().length() / rod.edge_length())
        .round()
        .max(1.0) as usize;
    let shape = model.shape(a, half_steps + 1)?;
    Ok(InitialGuess::from_shape(rod, |s| pose_at(&shape, s)))
}

/// The pose at arc length `s`: the nearest node's frame, continued straight along its tangent.
fn pose_at(shape: &Shape, s: f64) -> Pose {
    let last = shape.len().saturating_sub(1);
    let spacing = shape.spacing();
    let index = if spacing > 0.0 {
        ((s / spacing).round().max(0.0) as usize).min(last)
    } else {
        0
    };
    let node = shape.pose(index).unwrap_or_else(Pose::identity);
    let offset = s - shape.arc_length.get(index).copied().unwrap_or(0.0);
    node * Translation3::new(offset, 0.0, 0.0)
}
