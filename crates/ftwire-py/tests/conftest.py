"""Shared fixtures: the ftwire binary (the CLI the bindings are compared with) and a
calibration recorded by the simulator."""

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]


def binary() -> str:
    """The release binary: $FTWIRE_BIN, else target/release/ftwire of the workspace."""
    path = os.environ.get("FTWIRE_BIN", str(ROOT / "target" / "release" / "ftwire"))
    if not os.path.exists(path):
        pytest.fail(f"no ftwire binary at {path}: run `cargo build --release -p ftwire`")
    return path


def cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Runs the CLI with `args`; its stdout is text."""
    result = subprocess.run([binary(), *args], capture_output=True, text=True)
    if check and result.returncode != 0:
        raise AssertionError(f"ftwire {' '.join(args)} exited {result.returncode}: {result.stderr}")
    return result


def cli_json(*args: str):
    return json.loads(cli(*args).stdout)


def cli_json_lines(*args: str, check: bool = True):
    return [json.loads(line) for line in cli(*args, check=check).stdout.splitlines() if line.strip()]


@pytest.fixture(scope="session")
def recording(tmp_path_factory):
    """A calibration run of the simulator (gravity off, 60 rests, seed 0): its folder holds
    calibration.json and logs/recording.jsonl (raw readings and markers)."""
    out = tmp_path_factory.mktemp("calibrate") / "run"
    cli("experiment", "calibrate", "--trials", "60", "--gravity", "off", "--save-log",
        "--out", str(out))
    return out
