"""Ctrl-C during a long call: a child interpreter plans for up to a minute, gets SIGINT a
second in, and raises KeyboardInterrupt within a second or two (not at the plan's end, not an
abort of the interpreter, not a PanicException)."""

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


def test_sigint_ends_a_long_plan_with_keyboard_interrupt():
    child = subprocess.Popen([sys.executable, "-c", CHILD], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "started"
        time.sleep(1.0)
        child.send_signal(signal.SIGINT)
        sent = time.monotonic()
        out, err = child.communicate(timeout=30)
        waited = time.monotonic() - sent
    finally:
        child.kill()
    assert child.returncode == 0, f"exit {child.returncode}: {err}"
    assert out.strip() == "interrupted", f"{out}\n{err}"
    assert waited < 5.0, f"KeyboardInterrupt {waited:.1f} s after SIGINT"
