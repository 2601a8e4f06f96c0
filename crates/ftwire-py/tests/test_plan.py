"""plan against `ftwire plan --json` with the same seed and an iteration budget, to the last
digit."""

import numpy as np
import pytest

import ftwire
from conftest import ROOT, cli_json

SCENE = str(ROOT / "scenes" / "passage.toml")
# An iteration budget the 600 s time budget never cuts: the same path on any machine.
BUDGET = dict(seed=2, iterations=3000, time_budget=600.0, first=True, resample=4)


def test_plan_is_the_cli_to_the_last_digit():
    out = cli_json("plan", "--scene", SCENE, "--wire", "nitinol-3mm-820", "--seed", "2",
                   "--iterations", "3000", "--time-budget", "600", "--first", "--resample", "4",
                   "--json")
    found = ftwire.plan(SCENE, wire="nitinol-3mm-820", **BUDGET)
    w = out["waypoints"]
    assert found["waypoints"].shape == (len(w), 6)
    assert found["waypoints"].tolist() == [x["a"] for x in w]
    assert found["waypoints_normalised"].tolist() == [x["a_normalised"] for x in w]
    assert found["tip"].tolist() == [x["tip"]["position"] + x["tip"]["rotation"] for x in w]
    assert found["base"].tolist() == [x["base"]["position"] + x["base"]["rotation"] for x in w]
    assert found["joints"].tolist() == [[x["joints"]["torso"], *x["joints"]["left"],
                                         *x["joints"]["right"]] for x in w]
    assert found["clearance"].tolist() == [x["clearance"] for x in w]
    for key in ["length", "cost", "base_travel", "min_clearance", "iterations", "nodes",
                "first_path_iteration"]:
        assert found[key] == out[key], key
    assert found["resampled"]["waypoints"].tolist() == [x["a"] for x in out["resampled"]]
    assert found["resampled"]["waypoints"].shape == (5, 6)


def test_bad_arguments_name_them():
    with pytest.raises(ValueError, match="planner"):
        ftwire.plan(SCENE, planner="sideways")
    with pytest.raises(ValueError, match="iterations"):
        ftwire.plan(SCENE, iterations=0)
    with pytest.raises(ValueError, match="time_budget 0 s") as error:
        ftwire.plan(SCENE, time_budget=0.0)
    assert "--" not in str(error.value), "a Python error names the keyword, not the CLI flag"
    with pytest.raises(ValueError, match="scene"):
        ftwire.plan(str(ROOT / "scenes" / "no-such-scene.toml"), iterations=10)
    with pytest.raises(ValueError, match="^plan: wire: ") as error:
        ftwire.plan(SCENE, wire="copper", iterations=10)
    assert "--" not in str(error.value)
