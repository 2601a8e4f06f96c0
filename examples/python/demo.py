"""ftwire from Python, as `ftwire demo` does it in the simulator: tare the F/T sensor, identify
an unknown wire from a few rests, then see its shape from F/T alone against the truth.

Run after `pip install ./crates/ftwire-py`: python examples/python/demo.py
"""

import numpy as np

import ftwire
from ftwire.sim import Rig


def moved(b, dx, rv):
    """b followed by a move in its own frame: translation dx [m], rotation vector rv [rad]."""
    angle = np.linalg.norm(rv)
    k = np.cross(np.eye(3), np.asarray(rv, float) / max(angle, 1e-300))  # the axis' [·]×
    m = np.eye(4)
    m[:3, :3] = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k  # Rodrigues
    m[:3, 3] = dx
    return b @ m


rig = Rig(wire="nitinol-3mm-820", sensor="undistorted", gravity=True, seed=0)  # truth hidden
tare = rig.tare()  # raw F/T with nothing in the gripper (force first, sensor frame)
start = rig.b  # the second gripper's pose in the base clamp frame (4×4, m)
moves = [([0, 0, 0], [0, 0, 0]), ([-0.03, 0.02, 0], [0.15, 0, 0]),
         ([0, -0.02, 0.03], [0, 0.2, 0]), ([0.02, 0, -0.02], [0, 0, -0.2]),
         ([-0.02, 0.03, 0.02], [-0.1, 0.1, 0.1])]
a, b = [], []
for dx, rv in moves:  # rest after each move: ã = mounting(mean raw − tare), torque first
    rig.place(moved(start, dx, rv))
    a.append(rig.mounting.to_configuration(rig.rest(200) - tare))
    b.append(rig.b)
found = ftwire.identify(np.array(a), np.array(b), gravity=rig.gravity, seed=0)
print(f"identified c = {np.round(found.c, 4)} N·m², L = {found.length:.4f} m from {len(a)} "
      f"rests (true {rig.wire.c}, {rig.wire.length}); identified: {found.identified}")

rig.place(moved(start, [0.01, -0.03, -0.02], [0.1, -0.15, 0.0]))  # a pose it has not seen
a_now = rig.mounting.to_configuration(rig.rest(200) - tare)
truth = rig.centreline()  # the simulator's wire, base clamp frame [m]
shape = found.wire.solve(a_now, points=len(truth), gravity=rig.gravity).shape
error = np.linalg.norm(shape - truth, axis=1)
print(f"shape from F/T alone: mean error {1e3 * error.mean():.2f} mm, "
      f"largest {1e3 * error.max():.2f} mm against the simulator's truth")
assert error.max() < 0.02
