"""Ctrl-C during a long call: a child interpreter plans (or identifies) for up to a minute,
gets SIGINT a second in, and raises KeyboardInterrupt within a second or two (not at the call's
end, not an abort of the interpreter, not a PanicException)."""

import signal
import subprocess
import sys
import time

from conftest import ROOT

SCENE = str(ROOT / "scenes" / "passage.toml")

CHILD = f"""
import sys
import ftwire
print("started", flush=True)
try:
    ftwire.plan({SCENE!r}, seed=2, iterations=10**6, time_budget=60.0)
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
"""


def interrupt_child(source):
    """Runs `source` in a child interpreter, sends SIGINT a second after it prints "started",
    and checks that it ends with KeyboardInterrupt within a few seconds."""
    child = subprocess.Popen([sys.executable, "-c", source], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "started"
        time.sleep(1.0)
        child.send_signal(signal.SIGINT)
        sent = time.monotonic()
        out, err = child.communicate(timeout=60)
        waited = time.monotonic() - sent
    finally:
        child.kill()
    assert child.returncode == 0, f"exit {child.returncode}: {err}"
    assert out.strip() == "interrupted", f"{out}\n{err}"
    assert waited < 5.0, f"KeyboardInterrupt {waited:.1f} s after SIGINT"


def test_sigint_ends_a_long_plan_with_keyboard_interrupt():
    interrupt_child(CHILD)


IDENTIFY_CHILD = """
import numpy as np
import ftwire
wire = ftwire.Wire(c=(0.042, 0.055, 0.055), length=0.63, radius=0.001)
base = np.array([[0.0, 0.02, 0.01, -0.05, 0.03, 0.0], [0.005, -0.01, 0.015, 0.02, -0.04, 0.01],
                 [-0.004, 0.012, -0.008, 0.06, 0.02, -0.02], [0.002, 0.018, 0.004, -0.02, 0.05, 0.015]])
rng = np.random.default_rng(0)
a = np.repeat(base, 1000, axis=0) * (1 + 0.01 * rng.standard_normal((4000, 6)))
print("started", flush=True)
try:
    ftwire.identify(a, wire.solve(a).tip_pose, seed=1)
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
"""


def test_sigint_ends_a_long_identify_with_keyboard_interrupt():
    """identify on 4000 samples (a minute or more) ends on SIGINT, with KeyboardInterrupt."""
    interrupt_child(IDENTIFY_CHILD)
