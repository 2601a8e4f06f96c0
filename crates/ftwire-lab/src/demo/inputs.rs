//! The demo's inputs, read and checked before any work.

use ftwire_control::NoiseModel;
use ftwire_plan::Scene;

use crate::setup::SimSetup;
use crate::wire::WireSpec;

/// The demo's inputs, read and checked before any work.
pub(super) struct Inputs {
    pub(super) wire: WireSpec,
    pub(super) setup: SimSetup,
    pub(super) scene: Scene,
    pub(super) scene_name: String,
    pub(super) known: WireSpec,
    pub(super) seed: u64,
    pub(super) noise: NoiseModel,
    pub(super) calibration_configs: usize,
    pub(super) shape_configs: usize,
}
