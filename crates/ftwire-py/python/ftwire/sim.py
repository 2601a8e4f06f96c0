"""The ground-truth simulator: a dual-arm rig holding a wire whose truth is known.

``Rig`` is the discrete elastic rod of ftwire-sim (an independent physics model, not the
Kirchhoff model the estimators use) between two grippers, with a wrist F/T sensor on the base
gripper, motion capture and robot execution error, set up as ftwire's experiments set it up.
Its readings are what a real robot gives (raw F/T, the commanded pose); its ground truth (the
centreline, the true pose and wrench) is on separate methods for scoring.

Frames: the base clamp is at the world origin, so world = base clamp frame (z up). Raw F/T
readings are force first [N, N·m] in the sensor frame; ``Rig.mounting`` maps a tared reading
to the configuration ã, torque first [N·m, N], base clamp frame.
"""

from ._ftwire import Rig  # noqa: F401

__all__ = ["Rig"]
