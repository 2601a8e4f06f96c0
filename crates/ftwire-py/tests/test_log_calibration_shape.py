"""read_log, Calibration, Mounting and ShapeEstimator against the CLI's `shape --log --json`
on a simulated recording, to the last digit."""

import json

import numpy as np
import pytest

import ftwire
from conftest import cli_json_lines

WIRE = "nitinol-2mm-630"


def records(path):
    return [json.loads(line) for line in open(path) if line.strip()]


def test_read_log_gives_every_record_as_arrays(recording):
    path = recording / "logs" / "recording.jsonl"
    log = ftwire.read_log(str(path))
    lines = records(path)
    assert log["time"].shape == (len(lines),) and log["raw"].shape == (len(lines), 6)
    np.testing.assert_array_equal(log["time"], [r["time"] for r in lines])
    np.testing.assert_array_equal(log["raw"], [r["raw"] for r in lines])
    assert np.isnan(log["a"]).all() and np.isnan(log["b"]).all()
    markers = log["markers"]
    assert markers.shape[:2] == (len(lines), max(len(r["markers"]) for r in lines))
    first = lines[0]["markers"]
    for k, m in enumerate(first):
        if m is None:
            assert np.isnan(markers[0, k]).all()
        else:
            np.testing.assert_array_equal(markers[0, k], m)
    for key in ("time", "raw", "a", "b", "gravity", "markers"):
        assert log[key].dtype == np.float64 and log[key].flags["C_CONTIGUOUS"], key


def test_read_log_names_the_file_and_line(tmp_path):
    path = tmp_path / "bad.jsonl"
    good = '{"time": 0.0, "a": [0, 0.01, 0, 0, 0.1, 0], "b": {"position": [0.5, 0.1, 0], "rotation": [0, 0, 0.4]}}'
    path.write_text(good + "\n" + '{"time": oops\n')
    with pytest.raises(ValueError, match="line 2"):
        ftwire.read_log(str(path))
    path.write_text(good + "\n")
    log = ftwire.read_log(path)
    np.testing.assert_array_equal(log["b"], [[0.5, 0.1, 0, 0, 0, 0.4]])
    np.testing.assert_array_equal(log["line"], [1])
    with pytest.raises(ValueError, match="path"):
        ftwire.read_log(tmp_path / "missing.jsonl")


def test_calibration_and_shapes_are_the_cli_to_the_last_digit(recording):
    path = recording / "logs" / "recording.jsonl"
    calibration = ftwire.Calibration.load(str(recording / "calibration.json"))
    out = cli_json_lines("shape", "--log", str(path), "--wire", WIRE, "--calibration",
                         str(recording / "calibration.json"), "--json", check=False)
    log = ftwire.read_log(path)
    a = calibration.apply(log["raw"], time=log["time"])
    assert a.shape == log["raw"].shape and a.flags["C_CONTIGUOUS"]
    np.testing.assert_array_equal(a, [r["a"] for r in out])
    np.testing.assert_array_equal(calibration.apply(log["raw"][3], time=log["time"][3]), a[3])
    estimator = ftwire.ShapeEstimator(ftwire.Wire.preset(WIRE), calibration=calibration)
    shapes = estimator.estimate(log["raw"], time=log["time"])
    np.testing.assert_array_equal(shapes["a"], a)
    assert shapes["shape"].shape == (len(out), 100, 3)
    for i, r in enumerate(out):
        if r["points"]:
            np.testing.assert_array_equal(shapes["shape"][i], r["points"])
            assert shapes["flag"][i] == r["confidence"]
        else:
            assert shapes["flag"][i] == "no_shape" and shapes["error"][i]
    # The same estimator again: the first sample is now tested against the last one.
    estimator.reset()
    again = estimator.estimate(log["raw"], time=log["time"])
    assert again["flag"] == shapes["flag"]


def test_mounting_alone_is_the_cli(recording, tmp_path):
    path = recording / "logs" / "recording.jsonl"
    toml = tmp_path / "mounting.toml"
    toml.write_text("clamp_position_in_sensor = [0.0, 0.0, 0.08]\n")
    out = cli_json_lines("shape", "--log", str(path), "--wire", WIRE, "--mounting", str(toml),
                         "--json", check=False)
    log = ftwire.read_log(path)
    mounting = ftwire.Mounting.from_toml(toml)
    np.testing.assert_array_equal(mounting.to_configuration(log["raw"]), [r["a"] for r in out])
    np.testing.assert_array_equal(ftwire.Mounting().to_configuration(log["raw"]),
                                  mounting.to_configuration(log["raw"]))
    back = mounting.to_sensor(mounting.to_configuration(log["raw"]))
    np.testing.assert_allclose(back, log["raw"], rtol=1e-12, atol=1e-12)


def test_bad_calibration_and_mounting_arguments(tmp_path, recording):
    with pytest.raises(ValueError, match="^path .*none.json: ") as error:
        ftwire.Calibration.load(str(tmp_path / "none.json"))
    assert "--calibration" not in str(error.value), "a Python error names no CLI flag"
    calibration = ftwire.Calibration.load(str(recording / "calibration.json"))
    with pytest.raises(ValueError, match="raw has shape"):
        calibration.apply(np.zeros((3, 5)))
    with pytest.raises(ValueError, match="time has shape"):
        calibration.apply(np.zeros((3, 6)), time=[0.0, 1.0])
    with pytest.raises(ValueError, match="tool_mass"):
        ftwire.Mounting(tool_mass=-1.0)
    with pytest.raises(ValueError, match="gravity"):
        ftwire.Mounting(tool_mass=1.0).to_configuration(np.ones(6))
    with pytest.raises(ValueError, match="points"):
        ftwire.ShapeEstimator(ftwire.Wire.preset(WIRE), points=1)


def test_the_loaded_model_is_the_clis_to_the_last_digit(recording, tmp_path):
    """ShapeEstimator(gravity=...) and `shape --log --gravity-in-clamp` are one path."""
    path = recording / "logs" / "recording.jsonl"
    toml = tmp_path / "mounting.toml"
    toml.write_text("clamp_position_in_sensor = [0.0, 0.0, 0.08]\n")
    out = cli_json_lines("shape", "--log", str(path), "--wire", WIRE, "--mounting", str(toml),
                         "--gravity-in-clamp", "0,0,-9.81", "--json", check=False)
    log = ftwire.read_log(path)
    estimator = ftwire.ShapeEstimator(ftwire.Wire.preset(WIRE),
                                      mounting=ftwire.Mounting.from_toml(toml),
                                      gravity=(0.0, 0.0, -9.81))
    shapes = estimator.estimate(log["raw"])
    weightless = ftwire.ShapeEstimator(ftwire.Wire.preset(WIRE),
                                       mounting=ftwire.Mounting.from_toml(toml)).estimate(log["raw"])
    differs = False
    for i, r in enumerate(out):
        assert shapes["flag"][i] == r["confidence"]
        if r["points"]:
            np.testing.assert_array_equal(shapes["shape"][i], r["points"])
            differs |= not np.array_equal(shapes["shape"][i], weightless["shape"][i])
    assert differs, "the wire's weight changes the shapes"
    with pytest.raises(ValueError, match="gravity"):
        ftwire.ShapeEstimator(ftwire.Wire.preset(WIRE), gravity=(0.0, 0.0, 1e9))


def test_fortran_ordered_and_strided_arrays_are_read_by_their_strides(recording):
    """A transposed or strided view gives the same answers, to the bit, as a C-ordered copy."""
    calibration = ftwire.Calibration.load(str(recording / "calibration.json"))
    raw = np.ascontiguousarray(ftwire.read_log(recording / "logs" / "recording.jsonl")["raw"][:12])
    views = [np.asfortranarray(raw), np.ascontiguousarray(raw.T).T, np.repeat(raw, 2, axis=0)[::2]]
    a = calibration.apply(raw)
    wire = ftwire.Wire.preset(WIRE)
    solved = wire.solve(a, points=20)
    for view in views:
        assert not view.flags["C_CONTIGUOUS"]
        np.testing.assert_array_equal(calibration.apply(view), a)
        a_view = np.asfortranarray(a)
        np.testing.assert_array_equal(wire.solve(a_view, points=20).shape, solved.shape)
        shapes = ftwire.ShapeEstimator(wire, calibration=calibration).estimate(view)
        np.testing.assert_array_equal(
            shapes["shape"], ftwire.ShapeEstimator(wire, calibration=calibration).estimate(raw)["shape"])
    bad = np.asfortranarray(raw.copy())
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match=r"\[3, 1\]"):
        calibration.apply(bad)


def test_a_log_whose_markers_multiply_its_size_is_a_value_error(tmp_path):
    # 200 000 records of one marker and one of 1000 (the most a record may hold):
    # (200000, 1000, 3) would be 4.8 GB.
    small = '{"time": %d, "a": [0, 0.01, 0, 0, 0.1, 0], "markers": [[0, 0, 0]]}\n'
    path = tmp_path / "log.jsonl"
    n = 200_000
    with open(path, "w") as f:
        f.writelines(small % t for t in range(n - 1))
        f.write('{"time": %d, "a": [0, 0.01, 0, 0, 0.1, 0], "markers": [' % (n - 1))
        f.write(",".join(["[0,0,0]"] * 1000))
        f.write("]}\n")
    with pytest.raises(ValueError, match="200000 records of up to 1000 markers"):
        ftwire.read_log(path)
    # One record of more markers than a record may hold is refused by its line.
    with open(path, "w") as f:
        f.write('{"time": 0, "a": [0, 0.01, 0, 0, 0.1, 0], "markers": [')
        f.write(",".join(["[0,0,0]"] * 1001))
        f.write("]}\n")
    with pytest.raises(ValueError, match="line 1: markers holds 1001 markers"):
        ftwire.read_log(path)


def test_a_huge_rest_is_a_value_error_before_any_read():
    from ftwire.sim import Rig

    rig = Rig(wire=WIRE, seed=0)
    for read in (rig.rest, rig.tare):
        with pytest.raises(ValueError, match="samples = 100000000"):
            read(samples=10**8)


def test_an_output_too_large_is_a_value_error_before_any_work():
    wire = ftwire.Wire.preset(WIRE)
    with pytest.raises(ValueError, match="bytes"):
        wire.solve(np.zeros((1000, 6)), points=10**6)
    with pytest.raises(ValueError, match="bytes"):
        ftwire.ShapeEstimator(wire, points=10_000).estimate(np.zeros((20_000, 6)))


def test_an_output_the_process_cannot_allocate_is_a_memory_error():
    """Under a memory limit (here 3 GiB of address space), an answer under the 4 GiB bound that
    the process cannot allocate raises MemoryError before any work, not an aborted interpreter."""
    import subprocess
    import sys

    child = f"""
import resource, numpy as np, ftwire
resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
wire = ftwire.Wire.preset({WIRE!r})
try:
    wire.solve(np.zeros((15_000, 6)), points=10_000)
    print("solved")
except MemoryError as e:
    print("MemoryError", e)
"""
    done = subprocess.run([sys.executable, "-c", child], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, f"exit {done.returncode}: {done.stderr[-2000:]}"
    assert done.stdout.startswith("MemoryError") and "bytes" in done.stdout, done.stdout
