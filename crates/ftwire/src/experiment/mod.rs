//! Planning in a scene and tracking the plan in the simulator.

pub mod track;
