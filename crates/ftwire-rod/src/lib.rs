//! The Kirchhoff elastic-rod model of a wire: configuration space A, shape, Jacobian, stability, self-intersection.
