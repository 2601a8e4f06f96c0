"""identify against `ftwire identify --log --json` on a log the test writes, to the last
digit; the same seed gives the same answer."""

import json

import numpy as np
import pytest

import ftwire
from conftest import cli_json

TRUE = ftwire.Wire(c=(0.042, 0.055, 0.055), length=0.63, radius=0.001)


def rotation_vector(r):
    """The rotation vector (axis × angle) of a rotation matrix (angle below π)."""
    angle = np.arccos(np.clip((np.trace(r) - 1) / 2, -1, 1))
    if angle < 1e-12:
        return np.zeros(3)
    axis = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / (2 * np.sin(angle))
    return axis * angle


@pytest.fixture(scope="module")
def samples(tmp_path_factory):
    a = np.array([
        [0.0, 0.02, 0.01, -0.05, 0.03, 0.0],
        [0.005, -0.01, 0.015, 0.02, -0.04, 0.01],
        [-0.004, 0.012, -0.008, 0.06, 0.02, -0.02],
        [0.002, 0.018, 0.004, -0.02, 0.05, 0.015],
    ])
    tips = TRUE.solve(a).tip_pose
    b = np.array([np.concatenate([t[:3, 3], rotation_vector(t[:3, :3])]) for t in tips])
    path = tmp_path_factory.mktemp("identify") / "log.jsonl"
    with open(path, "w") as f:
        for i, (ai, bi) in enumerate(zip(a, b)):
            f.write(json.dumps({"time": float(i), "a": ai.tolist(),
                                "b": {"position": bi[:3].tolist(), "rotation": bi[3:].tolist()}}) + "\n")
    return path, a, b


def test_identify_is_the_cli_to_the_last_digit(samples):
    path, a, b = samples
    out = cli_json("identify", "--log", str(path), "--json", "--seed", "3")
    found = ftwire.identify(a, b, seed=3)
    assert found.c == tuple(out["c"]) and found.length == out["length"]
    assert found.c_std == tuple(out["c_std"]) and found.length_std == out["length_std"]
    assert found.chi2_per_dof == out["chi2_per_dof"] and found.condition == out["condition"]
    assert found.identified == out["identified"] and found.flag == out["flag"]
    assert found.wire.c == found.c and found.wire.length == found.length
    np.testing.assert_allclose(found.c, TRUE.c, rtol=1e-3)


def test_covariance_and_interval95_are_the_cli_to_the_last_digit(samples):
    path, a, b = samples
    out = cli_json("identify", "--log", str(path), "--json", "--seed", "3")
    found = ftwire.identify(a, b, seed=3)
    assert out["covariance"] is not None and out["interval95"] is not None
    assert found.covariance.shape == (4, 4) and found.covariance.dtype == np.float64
    assert found.interval95.shape == (4, 2)
    assert found.covariance.tolist() == out["covariance"]
    assert found.interval95.tolist() == out["interval95"]
    np.testing.assert_array_equal(found.covariance, found.covariance.T)
    values = [*found.c, found.length]
    assert all(lo <= v <= hi for v, (lo, hi) in zip(values, found.interval95))


def test_poses_as_matrices_or_from_the_log(samples):
    path, a, b = samples
    log = ftwire.read_log(path)
    from_log = ftwire.identify(log["a"], log["b"], seed=3)
    assert from_log.c == ftwire.identify(a, b, seed=3).c
    matrices = TRUE.solve(a).tip_pose
    guess = ftwire.Wire(c=(1, 1, 1), length=1.0, radius=0.002, density=7000.0)
    found = ftwire.identify(a, matrices, wire_guess=guess, seed=3)
    assert found.wire.radius == 0.002 and found.wire.density == 7000.0
    np.testing.assert_allclose(found.c, TRUE.c, rtol=1e-3)


def test_same_seed_same_answer(samples):
    _, a, b = samples
    first = ftwire.identify(a, b, seed=11, isotropic=True)
    second = ftwire.identify(a.copy(), b.copy(), seed=11, isotropic=True)
    assert (first.c, first.length, first.c_std) == (second.c, second.length, second.c_std)
    assert first.c[1] == first.c[2]


def test_bad_arguments_name_them(samples):
    _, a, b = samples
    with pytest.raises(ValueError, match="b has 3 poses"):
        ftwire.identify(a, b[:3])
    with pytest.raises(ValueError, match="b has shape"):
        ftwire.identify(a, b[:, :5])
    with pytest.raises(ValueError, match="a has shape"):
        ftwire.identify(a[0], b)
    with pytest.raises(ValueError, match="form"):
        ftwire.identify(a, b, form="quadratic")
    with pytest.raises(ValueError, match="torsion_ratio"):
        ftwire.identify(a, b, torsion_ratio=0.0)
    bad = a.copy()
    bad[2, 4] = np.inf
    with pytest.raises(ValueError, match=r"a\[2, 4\] = inf"):
        ftwire.identify(bad, b)
    skew = TRUE.solve(a).tip_pose.copy()
    skew[1, 0, 0] = 2.0
    with pytest.raises(ValueError, match=r"b\[1\] is not a rigid transform"):
        ftwire.identify(a, skew)


def test_the_sensor_s_drift_modelled_is_the_cli_to_the_last_digit(samples):
    path, a, b = samples
    out = cli_json("identify", "--log", str(path), "--json", "--seed", "3",
                   "--sensor", "distorted", "--tare-time", "-0.5")
    times = np.arange(len(a), dtype=float)
    found = ftwire.identify(a, b, seed=3, sensor="distorted", times=times, tare_time=-0.5)
    assert found.c == tuple(out["c"]) and found.length == out["length"]
    assert found.covariance.tolist() == out["covariance"]
    assert found.chi2_per_dof == out["chi2_per_dof"]
    # The drift model changes the fit's weighting: not the independent-noise answer.
    assert found.chi2_per_dof != ftwire.identify(a, b, seed=3).chi2_per_dof


def test_errors_name_the_python_keyword_and_the_arrays(samples):
    _, a, b = samples
    times = np.arange(len(a), dtype=float)
    with pytest.raises(ValueError) as refused:
        ftwire.identify(a, b, seed=3, sensor="distorted", times=times, tare_time=2.5)
    message = str(refused.value)
    assert "tare_time 2.5: record 0 of the arrays is at time 0" in message, message
    assert "--" not in message and "<arrays>" not in message, message


def test_pose_noise_and_gain_error_are_the_cli_to_the_last_digit(samples):
    path, a, b = samples
    out = cli_json("identify", "--log", str(path), "--json", "--seed", "3",
                   "--pose-noise-deg", "0.01", "--pose-noise-mm", "0.02", "--gain-error", "0.3")
    found = ftwire.identify(a, b, seed=3, pose_noise_deg=0.01, pose_noise_mm=0.02,
                            gain_error=0.3)
    assert found.c == tuple(out["c"]) and found.length == out["length"]
    assert found.covariance.tolist() == out["covariance"]
    # A gain error no sample averages away widens the stiffnesses' intervals.
    plain = ftwire.identify(a, b, seed=3, pose_noise_deg=0.01, pose_noise_mm=0.02)
    assert all(g > p for g, p in zip(found.c_std, plain.c_std))
    with pytest.raises(ValueError, match="gain-error"):
        ftwire.identify(a, b, gain_error=150.0)
    with pytest.raises(ValueError, match="pose-noise-mm"):
        ftwire.identify(a, b, pose_noise_mm=0.0)


def test_the_model_floor_is_the_cli_to_the_last_digit(samples):
    path, a, b = samples
    out = cli_json("identify", "--log", str(path), "--json", "--seed", "3",
                   "--model-floor", "0.2")
    found = ftwire.identify(a, b, seed=3, model_floor=0.2)
    assert found.c == tuple(out["c"]) and found.length == out["length"]
    assert found.covariance.tolist() == out["covariance"]
    # The floor widens every interval and moves no estimate.
    plain = ftwire.identify(a, b, seed=3)
    assert found.c == plain.c and found.length == plain.length
    assert all(f > p for f, p in zip(found.c_std, plain.c_std))
    assert found.length_std > plain.length_std
    with pytest.raises(ValueError, match="model-floor"):
        ftwire.identify(a, b, model_floor=-1.0)


def test_a_sensor_without_times_or_a_bad_sensor_is_a_value_error(samples):
    _, a, b = samples
    with pytest.raises(ValueError, match="times"):
        ftwire.identify(a, b, sensor="distorted")
    with pytest.raises(ValueError, match="times"):
        ftwire.identify(a, b, sensor="distorted", times=[0.0, 1.0])
    with pytest.raises(ValueError, match="sensor"):
        ftwire.identify(a, b, sensor="/no/such/sensor.toml", times=np.arange(len(a), dtype=float))
