//! The loaded model's settings of an identification experiment; the identification itself is
//! `ftwire_logs::identification`'s, shared with `identify --log`.

use ftwire_estimate::identify::IdentifierParams;

use crate::experiment::Gravity;

/// The settings of the loaded model: `config` with the wire's linear density identified under
/// the experiment's gravity. The rig's base clamp sits at the world origin with the world's
/// axes ([`crate::experiment::rig::place_wire`]), so gravity in the base clamp frame is the
/// world's.
pub fn loaded_config(config: &IdentifierParams, gravity: Gravity) -> IdentifierParams {
    let mut loaded = config.clone();
    if gravity == Gravity::On {
        loaded.constraints.weight = Some(gravity.vector());
    }
    loaded
}
