"""ftwire.sim.Rig: the same seed gives the same numbers; rests, the tare, markers and the
true centreline agree with each other and with the model."""

import numpy as np
import pytest

import ftwire
from ftwire.sim import Rig

SCALE_WIRE = ftwire.Wire.preset("nitinol-3mm-820")
SCALE = np.array([SCALE_WIRE.c[1] / SCALE_WIRE.length] * 3
                 + [SCALE_WIRE.c[1] / SCALE_WIRE.length**2] * 3)


def session(seed):
    """A short session: tare, a rest, a move, a rest, the markers."""
    rig = Rig(wire="nitinol-3mm-820", sensor="distorted", gravity=True, seed=seed)
    tare = rig.tare()
    first = rig.rest(100)
    b = rig.b.copy()
    b[:3, 3] += [-0.02, 0.01, 0.0]
    rig.place(b)
    return tare, first, rig.rest(100), rig.markers(), rig.centreline(), rig.time


def test_same_seed_same_numbers_another_seed_other_noise():
    one, two, other = session(0), session(0), session(1)
    for x, y in zip(one, two):
        np.testing.assert_array_equal(x, y)
    assert not np.array_equal(one[1], other[1])
    np.testing.assert_array_equal(one[4], other[4])  # the truth has no noise


def test_an_undistorted_weightless_rig_reads_its_true_configuration():
    a0 = np.array([0.2, 1.2, -0.6, 0.8, 0.3, -0.4]) * SCALE
    rig = Rig(sensor="undistorted", gravity=False, seed=3, a0=a0)
    assert rig.gravity is None
    a = rig.mounting.to_configuration(rig.rest(1000) - rig.tare())
    truth = rig.true_configuration
    np.testing.assert_allclose(a, truth, atol=1e-2 * np.abs(truth).max())
    # The simulator (a discrete rod) and the Kirchhoff model agree on the wire's shape.
    model = rig.wire.solve(truth, points=rig.centreline().shape[0]).shape
    assert np.linalg.norm(model - rig.centreline(), axis=1).max() < 5e-3
    np.testing.assert_allclose(rig.centreline()[-1], rig.true_b[:3, 3], atol=1e-9)


def test_placing_a_configuration_and_the_markers():
    rig = Rig(sensor="undistorted", seed=1)
    a = np.array([0.0, 1.0, 0.5, 0.5, 0.0, 0.2]) * SCALE
    b = rig.place_configuration(a, model="loaded")
    np.testing.assert_allclose(rig.b, b, atol=1e-12)
    np.testing.assert_allclose(rig.true_configuration, a, atol=0.05 * np.abs(a).max())
    markers = rig.markers()
    assert markers.shape[1] == 3
    seen = ~np.isnan(markers[:, 0])
    centre = rig.centreline()
    distance = np.linalg.norm(markers[seen, None, :] - centre[None, :, :], axis=2).min(axis=1)
    assert distance.max() < 0.01


def test_bad_arguments_name_them():
    with pytest.raises(ValueError, match="wire"):
        Rig(wire="copper")
    with pytest.raises(ValueError, match="sensor"):
        Rig(sensor="perfect")
    rig = Rig(seed=0)
    with pytest.raises(ValueError, match="samples = 2"):
        rig.rest(2)
    with pytest.raises(ValueError, match="b has shape"):
        rig.place(np.eye(3))
    with pytest.raises(ValueError, match="model"):
        rig.place_configuration(np.zeros(6), model="heavy")
    far = np.eye(4)
    far[0, 3] = 5.0
    with pytest.raises((ValueError, RuntimeError)):
        rig.place(far)
