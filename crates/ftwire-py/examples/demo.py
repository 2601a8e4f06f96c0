"""ftwire from Python: solve the model, identify a wire from (ã, b) samples, see its shape.

Run after `pip install ./crates/ftwire-py`: python crates/ftwire-py/examples/demo.py
"""

import numpy as np

import ftwire

truth = ftwire.Wire.preset("nitinol-2mm-630")  # c [N·m²], L [m] the identification must find
rng = np.random.default_rng(0)
scale = np.array([truth.c[1] / truth.length] * 3 + [truth.c[1] / truth.length**2] * 3)
a = rng.uniform(-2, 2, (400, 6)) * scale  # configurations, torque first [N·m, N]
solution = truth.solve(a, points=100)  # 400 solves in parallel, GIL released
a = a[solution.stable & ~solution.self_intersecting][:6]
b = truth.solve(a).tip_pose  # the second gripper's pose, base clamp frame (4×4)

found = ftwire.identify(a, b, seed=0)  # the swarm + refinement of `ftwire identify`
print(f"identified c = {np.round(found.c, 5)} N·m², L = {found.length:.5f} m "
      f"(true {truth.c}, {truth.length}); identified: {found.identified}")
assert np.allclose(found.c, truth.c, rtol=1e-2) and abs(found.length - truth.length) < 1e-3

estimator = ftwire.ShapeEstimator(found.wire)  # shapes of ã from the identified wire
shapes = estimator.estimate(a)
error = np.linalg.norm(shapes["shape"] - truth.solve(a, points=64).shape, axis=2).max()
print(f"shape from the identified wire: {len(a)} samples, flags {set(shapes['flag'])}, "
      f"largest error {1e3 * error:.3f} mm")
assert error < 1e-3
