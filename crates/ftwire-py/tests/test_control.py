"""Controller.step against the Rust library's own step (examples/control_step.rs) to the
last digit, and repeated steps on the model converge to the goal."""

import os
import subprocess

import numpy as np
import pytest

import ftwire
from conftest import ROOT

WIRE = ftwire.Wire.preset("nitinol-3mm-820")
SCALE = np.array([WIRE.c[1] / WIRE.length] * 3 + [WIRE.c[1] / WIRE.length**2] * 3)
A = np.array([0.2, 1.0, -0.5, 0.8, 0.3, -0.4]) * SCALE
GOAL = np.array([-0.3, 2.0, 0.4, 0.2, -0.6, 0.5]) * SCALE


def reference(a, goal, b, gain, epsilon):
    """The Rust library's step: (4, 4) and its scale, or None."""
    path = os.environ.get("FTWIRE_CONTROL_STEP",
                          str(ROOT / "target" / "release" / "examples" / "control_step"))
    if not os.path.exists(path):
        pytest.fail(f"no control_step at {path}: cargo build --release -p ftwire-py "
                    "--example control_step")
    numbers = [*WIRE.c, WIRE.length, WIRE.radius, gain, epsilon, *a, *goal, *b]
    out = subprocess.run([path, *map(repr, map(float, numbers))], capture_output=True,
                         text=True, check=True).stdout.split()
    if out == ["none"]:
        return None
    values = [float(v) for v in out]
    return np.array(values[:16]).reshape(4, 4), values[16]


def test_step_is_the_rust_library_to_the_last_digit():
    for gain in [0.2, 0.7]:
        controller = ftwire.Controller(WIRE, gain=gain, epsilon=0.05)
        b = np.array([0.5, 0.1, -0.05, 0.1, -0.2, 0.3])
        expected, scale = reference(A, GOAL, b, gain, 0.05)
        assert controller.step(A, GOAL, b=b).tolist() == expected.tolist()
        plan = controller.plan_step(A, GOAL, b=b)
        assert plan["scale"] == scale
        assert plan["b"].tolist() == expected.tolist()
        np.testing.assert_allclose(plan["predicted_da"], scale * gain * (GOAL - A), rtol=1e-12)


def rotation_vector(r):
    angle = np.arccos(np.clip((np.trace(r) - 1) / 2, -1, 1))
    if angle < 1e-12:
        return np.zeros(3)
    axis = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / (2 * np.sin(angle))
    return axis * angle


def land(a, b):
    """The model's wire with its second gripper moved to b: the configuration with Γ(a) = b,
    by Newton from a (δa = J⁻¹ δb, δb the tip's body twist to b, to first order)."""
    for _ in range(20):
        s = WIRE.solve(a)
        tip = s.tip_pose
        twist = np.concatenate([rotation_vector(tip[:3, :3].T @ b[:3, :3]),
                                tip[:3, :3].T @ (b[:3, 3] - tip[:3, 3])])
        if np.linalg.norm(twist) < 1e-13:
            break
        a = a + np.linalg.solve(s.jacobian, twist)
    return a


def test_steps_on_the_model_converge_to_the_goal():
    controller = ftwire.Controller(WIRE, gain=0.5, epsilon=1e-3)
    controller.check_goal(GOAL)
    a = A.copy()
    b = WIRE.solve(a).tip_pose
    errors = [controller.distance(a, GOAL)]
    for _ in range(60):
        if controller.reached(a, GOAL):
            break
        b = controller.step(a, GOAL, b=b)
        a = land(a, b)
        errors.append(controller.distance(a, GOAL))
    assert controller.reached(a, GOAL), errors
    assert errors[-1] < 1e-3 < errors[0]
    # Near the goal the model is linear: each step closes the gain's share of the gap.
    ratios = np.array(errors[-6:]) / np.array(errors[-7:-1])
    np.testing.assert_allclose(ratios, 1 - controller.gain, atol=0.02)


def test_bad_arguments_name_them():
    with pytest.raises(ValueError, match="gain"):
        ftwire.Controller(WIRE, gain=1.5)
    with pytest.raises(ValueError, match="epsilon"):
        ftwire.Controller(WIRE, epsilon=0.0)
    controller = ftwire.Controller(WIRE)
    with pytest.raises(ValueError, match="a_goal"):
        controller.step(A, GOAL[:5])
    with pytest.raises(ValueError, match=r"a_measured\[2\] = NaN"):
        controller.step(np.array([0, 0, np.nan, 0, 0, 0]), GOAL)
    with pytest.raises(ValueError, match="b has shape"):
        controller.step(A, GOAL, b=np.eye(3))
