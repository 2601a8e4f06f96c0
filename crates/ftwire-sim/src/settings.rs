//! The solver settings a [`crate::World`] carries: Newton's method ([`crate::newton`]) and the
//! quasi-static continuation ([`crate::continuation`]).

/// Settings of Newton's method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonParams {
    /// Iteration limit (default `200`).
    pub max_iterations: usize,
    /// Convergence tolerance on the scaled residual (default `1e-8`): the largest free nodal
    /// force over `c_max/L²` and the largest free edge moment over `c_max/L`. It is raised to
    /// the rounding floor of the stiff stretching forces, `16·ε·EA·max|x|/h` over `c_max/L²`
    /// (≈ 5e-7 for the 2 mm nitinol wire near the origin), when that is larger.
    pub tolerance: f64,
    /// Largest node displacement per iteration, as a fraction of `L` (default `0.05`).
    pub max_step_fraction: f64,
}

impl Default for NewtonParams {
    fn default() -> Self {
        Self {
            max_iterations: 200,
            tolerance: 1e-8,
            max_step_fraction: 0.05,
        }
    }
}

/// Settings of the continuation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContinuationParams {
    /// Largest gripper translation per step, as a fraction of `L` (default `0.05`).
    pub max_translation_fraction: f64,
    /// Largest gripper rotation per step \[rad\] (default `0.15`, about 8.6°).
    pub max_rotation: f64,
    /// How many times a step may be halved before the motion fails (default `12`).
    pub max_subdivisions: usize,
    /// Node jump between predictor and equilibrium above which a step is suspected to snap,
    /// as a fraction of `L` (default `0.02`).
    pub snap_distance_fraction: f64,
    /// Newton tolerance (scaled residual, as [`NewtonParams::tolerance`]) of the
    /// intermediate steps of a motion (default `1e-3`); the last step is solved to the world's
    /// Newton tolerance. The intermediate equilibria only carry the branch to the next step.
    pub path_tolerance: f64,
    /// Largest work of one motion, in Newton iterations (converged and failed, over all its
    /// steps and halvings) times edges, the unit in which an iteration's cost grows; once
    /// spent, the motion fails with [`crate::SimError::WorkExhausted`] (default `None`: no
    /// limit). A motion along a branch that keeps ending, its steps halved and doubled again,
    /// otherwise spends Newton's iteration limit on every failed step for as long as it creeps
    /// forward.
    pub work_limit: Option<usize>,
}

impl Default for ContinuationParams {
    fn default() -> Self {
        Self {
            max_translation_fraction: 0.05,
            max_rotation: 0.15,
            max_subdivisions: 12,
            snap_distance_fraction: 0.02,
            path_tolerance: 1e-3,
            work_limit: None,
        }
    }
}
