"""Wire and Wire.solve against `ftwire solve --json`, to the last digit; shapes, dtypes,
contiguity; errors naming the argument."""

import json

import numpy as np
import pytest

import ftwire
from conftest import cli, cli_json

C = (0.214, 0.278, 0.278)
A = [0.0, 0.2, 0.1, -0.5, 0.3, 0.0]


def csv(values) -> str:
    return ",".join(repr(float(v)) for v in values)


def expected(c, length, a, nodes, *extra):
    return cli_json("solve", "--c", csv(c), "--length", repr(length), "--a", csv(a),
                    "--nodes", str(nodes), "--json", *extra)


def assert_matches(solution, out, row=None):
    pick = (lambda x: x) if row is None else (lambda x: x[row])
    np.testing.assert_array_equal(pick(solution.shape), np.array(out["shape"]))
    np.testing.assert_array_equal(pick(solution.jacobian), np.array(out["jacobian"]))
    tip = pick(solution.tip_pose)
    np.testing.assert_array_equal(tip[:3, :3], np.array(out["tip"]["rotation"]))
    np.testing.assert_array_equal(tip[:3, 3], np.array(out["tip"]["position"]))
    np.testing.assert_array_equal(tip[3], [0.0, 0.0, 0.0, 1.0])
    assert bool(pick(solution.stable)) == out["stable"]
    assert bool(pick(solution.self_intersecting)) == out["self_intersecting"]
    assert float(pick(solution.det_j_min)) == out["det_j_min"]


def test_single_solve_is_the_cli_to_the_last_digit():
    wire = ftwire.Wire(c=C, length=0.82, radius=0.001)
    assert_matches(wire.solve(A, points=64), expected(C, 0.82, A, 64))


def test_batch_rows_are_the_cli_to_the_last_digit():
    wire = ftwire.Wire(c=(0.042, 0.055, 0.055), length=0.63, radius=0.001)
    a = np.array([[0, 0.02, 0.01, -0.05, 0.03, 0], [0, 0, 0.01, 0, 0, 0], [0.01, -0.02, 0, 0.1, 0, 0.05]])
    solution = wire.solve(a, points=17)
    for i, row in enumerate(a):
        assert_matches(solution, expected((0.042, 0.055, 0.055), 0.63, row, 17), row=i)


def test_loaded_model_with_rest_curvature_is_the_cli():
    wire = ftwire.Wire(c=(0.042, 0.055, 0.055), length=0.63, radius=0.001, density=6450.0,
                       natural_curvature=(0.0, 0.5, -0.2))
    a = [0, 0.02, 0, 0, 0.1, 0]
    out = expected((0.042, 0.055, 0.055), 0.63, a, 33, "--gravity", "0,0,-9.81",
                   "--density", "6450", "--natural-curvature", "0,0.5,-0.2")
    assert_matches(wire.solve(a, points=33, gravity=(0, 0, -9.81)), out)


def test_arrays_are_c_contiguous_float64_of_the_documented_shapes():
    wire = ftwire.Wire.preset("nitinol-3mm-820")
    solution = wire.solve(np.tile(A, (5, 1)), points=100)
    for name, shape in [("shape", (5, 100, 3)), ("tip_pose", (5, 4, 4)), ("jacobian", (5, 6, 6)),
                        ("det_j_min", (5,))]:
        array = getattr(solution, name)
        assert array.shape == shape and array.dtype == np.float64, name
        assert array.flags["C_CONTIGUOUS"], name
    for name in ("stable", "self_intersecting"):
        assert getattr(solution, name).shape == (5,) and getattr(solution, name).dtype == np.bool_
    single = wire.solve(A)
    assert single.shape.shape == (100, 3) and single.tip_pose.shape == (4, 4)
    assert isinstance(single.stable, bool)
    np.testing.assert_array_equal(solution.shape[3], single.shape)


def test_same_input_same_answer():
    wire = ftwire.Wire.preset("nitinol-2mm-630")
    rng = np.random.default_rng(7)
    a = rng.uniform(-1, 1, (200, 6)) * np.array([0.01, 0.01, 0.01, 0.05, 0.05, 0.05])
    first, second = wire.solve(a), wire.solve(a.copy())
    np.testing.assert_array_equal(first.shape, second.shape)
    np.testing.assert_array_equal(first.jacobian, second.jacobian)


def test_presets_and_wire_files(tmp_path):
    wire = ftwire.Wire.preset("nitinol-3mm-820")
    assert wire.c == (0.214, 0.278, 0.278) and wire.length == 0.82
    path = tmp_path / "wire.toml"
    path.write_text('name = "mine"\nc = [0.1, 0.2, 0.3]\nlength = 0.5\nradius = 0.001\ndensity = 7000.0\n')
    mine = ftwire.Wire.from_toml(str(path))
    assert (mine.name, mine.c, mine.length, mine.density) == ("mine", (0.1, 0.2, 0.3), 0.5, 7000.0)
    assert mine == ftwire.Wire.from_toml(path)
    with pytest.raises(ValueError, match="name"):
        ftwire.Wire.preset("copper")
    path.write_text('name = "bad"\nc = [0.1, -0.2, 0.3]\nlength = 0.5\nradius = 0.001\ndensity = 7000.0\n')
    with pytest.raises(ValueError, match="c2"):
        ftwire.Wire.from_toml(path)


def test_wires_are_immutable():
    wire = ftwire.Wire.preset("nitinol-3mm-820")
    with pytest.raises(AttributeError):
        wire.length = 1.0


@pytest.mark.parametrize("kwargs, name", [
    (dict(c=(0.0, 0.1, 0.1), length=0.5), r"c\[0\]"),
    (dict(c=(0.1, -1.0, 0.1), length=0.5), r"c\[1\]"),
    (dict(c=(0.1, 0.1, float("nan")), length=0.5), r"c\[2\]"),
    (dict(c=(0.1, 0.1), length=0.5), "c has shape"),
    (dict(c=(0.1, 0.1, 0.1), length=0.0), "length"),
    (dict(c=(0.1, 0.1, 0.1), length=0.5, radius=0.3), "radius"),
    (dict(c=(0.1, 0.1, 0.1), length=0.5, density=-1.0), "density"),
    (dict(c=(0.1, 0.1, 0.1), length=0.5, natural_curvature=(0, float("inf"), 0)), "natural_curvature"),
])
def test_bad_wires_name_the_argument(kwargs, name):
    with pytest.raises(ValueError, match=name):
        ftwire.Wire(**kwargs)


@pytest.mark.parametrize("a, name", [
    (np.zeros(5), r"a has shape \[5\]"),
    (np.zeros((3, 5)), r"a has shape \[3, 5\]"),
    (np.zeros((0, 6)), r"a has shape \[0, 6\]"),
    (np.zeros((2, 2, 6)), "a has shape"),
    ([[0, 0, 0, 0, 0, 0], [0, 0, float("nan"), 0, 0, 0]], r"a\[1, 2\] = NaN"),
    ("abc", "a: cannot be read"),
])
def test_bad_configurations_name_the_argument(a, name):
    wire = ftwire.Wire.preset("nitinol-3mm-820")
    with pytest.raises(ValueError, match=name):
        wire.solve(a)


def test_bad_points_and_gravity_name_the_argument():
    wire = ftwire.Wire.preset("nitinol-3mm-820")
    with pytest.raises(ValueError, match="points"):
        wire.solve(A, points=1)
    with pytest.raises(ValueError, match="gravity"):
        wire.solve(A, gravity=(0, 0))
    with pytest.raises(ValueError, match="gravity"):
        wire.solve(A, gravity=(0, 0, float("nan")))


def test_integer_lists_are_read_as_float64():
    wire = ftwire.Wire.preset("nitinol-3mm-820")
    np.testing.assert_array_equal(wire.solve([0, 0, 1, 0, 0, 0]).shape,
                                  wire.solve(np.array([0, 0, 1, 0, 0, 0], dtype=np.float32)).shape)
