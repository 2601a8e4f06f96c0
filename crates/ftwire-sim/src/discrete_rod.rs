//! Physical parameters of the simulated wire and their discretisation.
//!
//! The rod has `N` edges and `N + 1` nodes. Its first and last edges are *ghost half-edges*: the
//! clamp point is the midpoint of edge 0 (and of edge `N − 1`), so that half of each end edge lies
//! inside the gripper. Both nodes and the material frame of an end edge are fixed by its clamp.
//! The wire between the two clamp points has length `L = (N − 1)·h`, with `h` the rest edge
//! length, and every interior vertex owns a Voronoi length `h` of it. This staggered placement
//! makes the clamp's tangent exact at the clamp point and gives errors of order `1/N²`
//! (a rigid first edge with the clamp at its end node gives `1/N`).

use ftwire_core::{ensure_finite, ensure_positive};
use nalgebra::Vector3;

use crate::error::SimError;

/// Parameters of a wire, as plain data with defaults (the nitinol 2 mm × 630 mm wire).
///
/// # Example
/// ```
/// use ftwire_sim::RodParams;
/// let cable = RodParams::electric_cable_3mm_920();
/// assert!(cable.stiffness[1] < RodParams::nitinol_2mm_630().stiffness[1]);
/// assert_eq!(RodParams::default().edges, 100);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodParams {
    /// Stiffnesses `(c1, c2, c3)` \[N·m²\]: torsion, bending about the body y axis, bending about
    /// the body z axis (default `(0.042, 0.055, 0.055)`).
    pub stiffness: [f64; 3],
    /// Wire length `L` between the two clamp points \[m\] (default `0.63`).
    pub length: f64,
    /// Wire radius \[m\], used for contact and for the weight (default `0.001`).
    pub radius: f64,
    /// Material density \[kg/m³\] (default `6450`, nitinol). The linear density is
    /// `density · π · radius²`.
    pub density: f64,
    /// Gravitational acceleration \[m/s²\] in the world frame (default `(0, 0, −9.81)`).
    pub gravity: Vector3<f64>,
    /// Natural (rest) strains `(ū1, ū2, ū3)` \[1/m\] in the body frame: rest twist rate and rest
    /// curvatures about body y and z, as the strains `u` of DESIGN.md (default zero: a straight,
    /// untwisted rest shape).
    pub rest_strain: Vector3<f64>,
    /// Number of edges `N` (default `100`, at least 3).
    pub edges: usize,
    /// Axial stiffness `EA` \[N\] (default `None`: `4·max(c2, c3)/radius²`, that of a solid round
    /// wire). Large enough to make the wire practically inextensible.
    pub axial_stiffness: Option<f64>,
    /// The curvature `κs` \[1/m\] at which the wire's bending softens (default `None`: linear
    /// bending, the Kirchhoff rod's). With it the energy density of bending is
    /// `c̄ κs² (√(1 + (c2 u2² + c3 u3²)/(c̄ κs²)) − 1)`, `c̄ = (c2 + c3)/2`, so that a round
    /// wire's bending moment is `c κ / √(1 + (κ/κs)²)`: the secant stiffness `c/√2` at
    /// `κ = κs`, and `c` to within `(κ/κs)²/2` below.
    /// It is what a superelastic nitinol wire does near 1 % surface strain (`κ·radius`), where
    /// its austenite starts to transform; the twist stays linear. No model of `ftwire-rod`
    /// knows it: a wire of the simulator that a linear model does not describe.
    pub bending_softening: Option<f64>,
}

impl Default for RodParams {
    fn default() -> Self {
        Self::nitinol_2mm_630()
    }
}

impl RodParams {
    /// Nitinol wire, 2 mm × 630 mm, `c = (0.042, 0.055, 0.055)` N·m² (paper Table I), gravity on.
    pub fn nitinol_2mm_630() -> Self {
        Self {
            stiffness: [0.042, 0.055, 0.055],
            length: 0.63,
            radius: 0.001,
            density: 6450.0,
            gravity: Vector3::new(0.0, 0.0, -9.81),
            rest_strain: Vector3::zeros(),
            edges: 100,
            axial_stiffness: None,
            bending_softening: None,
        }
    }

    /// Nitinol wire, 3 mm × 910 mm, `c = (0.214, 0.278, 0.278)` N·m² (paper Table II).
    pub fn nitinol_3mm_910() -> Self {
        Self {
            stiffness: [0.214, 0.278, 0.278],
            length: 0.91,
            radius: 0.0015,
            ..Self::nitinol_2mm_630()
        }
    }

    /// Nitinol wire, 3 mm × 820 mm, `c = (0.214, 0.278, 0.278)` N·m² (paper Table II).
    pub fn nitinol_3mm_820() -> Self {
        Self {
            length: 0.82,
            ..Self::nitinol_3mm_910()
        }
    }

    /// An electric cable, 3 mm × 920 mm: copper strands in PVC, much softer than nitinol and
    /// heavier relative to its stiffness, with a natural curvature from being stored on a reel.
    ///
    /// Values (plausible, not measured): `c = (0.0030, 0.0045, 0.0045)` N·m² (a 3 mm cable with
    /// an effective Young's modulus of about 1.1 GPa), density 3000 kg/m³ (copper and PVC,
    /// ≈ 21 g/m), rest curvature 1.5 1/m about body z (a reel of ≈ 0.67 m radius).
    /// Its gravity number `ρA·g·L³/c2 ≈ 36`, against ≈ 0.9 for the 2 mm nitinol wire.
    pub fn electric_cable_3mm_920() -> Self {
        Self {
            stiffness: [0.0030, 0.0045, 0.0045],
            length: 0.92,
            radius: 0.0015,
            density: 3000.0,
            rest_strain: Vector3::new(0.0, 0.0, 1.5),
            ..Self::nitinol_2mm_630()
        }
    }

    /// Returns a copy with gravity switched off.
    #[must_use]
    pub fn without_gravity(self) -> Self {
        Self {
            gravity: Vector3::zeros(),
            ..self
        }
    }

    /// Returns a copy with `edges` edges.
    #[must_use]
    pub fn with_edges(self, edges: usize) -> Self {
        Self { edges, ..self }
    }
}

/// Validated rod parameters with the derived discretisation.
///
/// Parse, don't validate: once a `DiscreteRod` exists, its stiffnesses, length, radius and density are
/// finite and positive and it has at least 3 edges.
#[derive(Debug, Clone, PartialEq)]
pub struct DiscreteRod {
    params: RodParams,
    h: f64,
    axial: f64,
}

impl DiscreteRod {
    /// The smallest number of edges allowed.
    pub const MIN_EDGES: usize = 3;

    /// Validates the parameters.
    ///
    /// # Errors
    /// [`SimError::Core`] naming the field: not positive for a stiffness, length, radius,
    /// density or axial stiffness, not finite for a gravity or rest strain;
    /// [`SimError::TooFewEdges`] for `edges < 3`.
    ///
    /// # Example
    /// ```
    /// use ftwire_sim::{DiscreteRod, RodParams};
    /// let rod = DiscreteRod::new(RodParams::nitinol_3mm_820())?;
    /// assert!((rod.edge_length() - 0.82 / 99.0).abs() < 1e-15);
    /// assert!(DiscreteRod::new(RodParams { length: -1.0, ..RodParams::default() }).is_err());
    /// # Ok::<(), ftwire_sim::SimError>(())
    /// ```
    pub fn new(params: RodParams) -> Result<Self, SimError> {
        const NAMES: [&str; 3] = ["c1", "c2", "c3"];
        for (name, &c) in NAMES.iter().zip(&params.stiffness) {
            ensure_positive(name, c)?;
        }
        ensure_positive("length", params.length)?;
        ensure_positive("radius", params.radius)?;
        ensure_positive("density", params.density)?;
        ensure_finite("gravity", params.gravity.as_slice())?;
        ensure_finite("rest_strain", params.rest_strain.as_slice())?;
        if let Some(curvature) = params.bending_softening {
            ensure_positive("bending_softening", curvature)?;
        }
        if params.edges < Self::MIN_EDGES {
            return Err(SimError::TooFewEdges {
                edges: params.edges,
                min: Self::MIN_EDGES,
            });
        }
        let axial = match params.axial_stiffness {
            Some(ea) => {
                ensure_positive("axial_stiffness", ea)?;
                ea
            }
            None => 4.0 * params.stiffness[1].max(params.stiffness[2]) / params.radius.powi(2),
        };
        let h = params.length / (params.edges - 1) as f64;
        Ok(Self { params, h, axial })
    }

    /// The parameters this rod was built from.
    pub fn params(&self) -> &RodParams {
        &self.params
    }

    /// Number of edges `N`.
    pub fn edges(&self) -> usize {
        self.params.edges
    }

    /// Number of nodes `N + 1`.
    pub fn nodes(&self) -> usize {
        self.params.edges + 1
    }

    /// Rest edge length `h = L / (N − 1)` \[m\].
    pub fn edge_length(&self) -> f64 {
        self.h
    }

    /// Axial stiffness `EA` \[N\].
    pub fn axial_stiffness(&self) -> f64 {
        self.axial
    }

    /// Linear density `ρ·π·r²` \[kg/m\].
    pub fn linear_density(&self) -> f64 {
        self.params.density * std::f64::consts::PI * self.params.radius.powi(2)
    }

    /// Arc length \[m\] of node `k` measured from the base clamp point: `(k − ½)·h`. Nodes 0 and
    /// `N` lie half an edge outside the wire, inside the grippers.
    pub fn node_arc_length(&self, k: usize) -> f64 {
        (k as f64 - 0.5) * self.h
    }

    /// Arc length \[m\] of the midpoint of edge `j`: `j·h`. Edge 0 is centred on the base clamp
    /// point (`0`), edge `N − 1` on the tip clamp point (`L`).
    pub fn edge_arc_length(&self, j: usize) -> f64 {
        j as f64 * self.h
    }

    /// Mass lumped at node `k` \[kg\]: `ρA·h` for nodes `1..N−1`, zero for the two outer ghost
    /// nodes (which lie outside the wire).
    pub fn node_mass(&self, k: usize) -> f64 {
        if k == 0 || k >= self.params.edges {
            0.0
        } else {
            self.linear_density() * self.h
        }
    }

    /// The largest stiffness `max(c1, c2, c3)` \[N·m²\].
    pub fn max_stiffness(&self) -> f64 {
        self.params.stiffness.iter().copied().fold(0.0, f64::max)
    }
}
