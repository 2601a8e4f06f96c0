//! The ground-truth world of ftwire: a discrete elastic rod with gravity and contact, an F/T sensor, markers and a simulated rig.
