"""ftwire: see and steer an elastic wire with a dual-arm robot from one wrist F/T sensor.

Python bindings of the Rust crates (the Kirchhoff rod model, rig logs, the F/T calibration,
shape estimation, identification, the controller, the planner, and the ground-truth
simulator in ftwire.sim).

Conventions: SI units (m, rad, N, N·m, s, kg/m³). A configuration ``a = (τ1, τ2, τ3, f1, f2,
f3)`` is the wrench on the base gripper, torque first, in the base clamp frame. A raw F/T
reading is force first, in the sensor frame. A pose ``b`` is the second gripper's clamp pose
in the base clamp frame, as a 4×4 homogeneous matrix or as 7 numbers (position [m], then a
rotation vector [rad], axis × angle). Arrays are NumPy float64, C-contiguous, with a leading
batch axis N. Bad input raises ValueError naming the argument; no answer raises RuntimeError.
"""

from ._ftwire import *  # noqa: F401,F403
from ._ftwire import __version__  # noqa: F401

