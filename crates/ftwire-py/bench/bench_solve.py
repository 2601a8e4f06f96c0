"""Speed of Wire.solve from Python: solves per second of a (10000, 6) batch at 100 points
(parallel over rows, GIL released), and a single solve's call overhead over the Rust solve.

python crates/ftwire-py/bench/bench_solve.py [--rows 10000] [--repeat 5]

The overhead is the single call's time minus the Rust solve's own time for the same
configurations, measured as the batch's per-row time with one thread
(RAYON_NUM_THREADS=1 in a child process). The machine's load average is printed beside.
"""

import argparse
import os
import subprocess
import sys
import time

import numpy as np

import ftwire


def configurations(wire, rows, seed=2024):
    """Stable configurations of `wire` sampled in [−30, 30]⁶ normalised units (the Rust
    bench's range)."""
    rng = np.random.default_rng(seed)
    scale = np.array([wire.c[1] / wire.length] * 3 + [wire.c[1] / wire.length**2] * 3)
    out = []
    while sum(len(x) for x in out) < rows:
        a = rng.uniform(-30, 30, (rows, 6)) * scale
        try:
            s = wire.solve(a, points=2)
        except (ValueError, RuntimeError):
            continue
        out.append(a[s.stable])
    return np.ascontiguousarray(np.concatenate(out)[:rows])


def best(f, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--rows", type=int, default=10000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--batch-only", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    wire = ftwire.Wire.preset("nitinol-2mm-630")
    a = configurations(wire, args.rows)
    wire.solve(a[:100], points=100)  # warm the thread pool
    batch = best(lambda: wire.solve(a, points=100), args.repeat)
    if args.batch_only:
        print(batch / len(a))
        return
    threads = os.environ.get("RAYON_NUM_THREADS", str(os.cpu_count()))
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs")
    print(f"batch: {len(a) / batch:,.0f} solves/s ({len(a)} rows, 100 points, {threads} threads)")
    n = min(2000, len(a))
    single = best(lambda: [wire.solve(row, points=100) for row in a[:n]], args.repeat) / n
    child = subprocess.run(
        [sys.executable, __file__, "--rows", str(n), "--repeat", str(args.repeat), "--batch-only"],
        env={**os.environ, "RAYON_NUM_THREADS": "1"}, capture_output=True, text=True, check=True)
    rust = float(child.stdout)
    print(f"single call: {1e6 * single:.2f} µs; Rust solve (one thread, in a batch): "
          f"{1e6 * rust:.2f} µs; call overhead {1e6 * (single - rust):.2f} µs")


if __name__ == "__main__":
    main()
