#!/usr/bin/env python3
"""Speed of the Python binding against the Rust core, measured in one run (ratios, not
seconds, are what to compare on a shared machine).

    python examples/python/bench.py [--samples 1000000] [--repeats 7] [--json]

For each operator: `.process` on a numpy array of 1e6 samples (best of `--repeats`), the same
into a reused array (`out=`), the core's own loop (`Operator::process` on Rust vectors into a
reused buffer, `hyst._hyst._bench_core`) over the same samples, their ratios (goal <= 1.15), and
the cost of one `.step(x)` call from Python. A new result array costs its page faults (8 MB
per 1e6 float64 samples), which the core loop and `out=` do not pay.
"""

import argparse
import json
import sys
import time

from typing import Any, Dict, List, Optional

import numpy as np

import hyst
from hyst import _hyst


def best(fn: Any, repeats: int) -> float:
    t = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        t = min(t, time.perf_counter() - start)
    return t


def main(argv: Optional[List[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--samples", type=int, default=1_000_000)
    p.add_argument("--repeats", type=int, default=7)
    p.add_argument("--json", action="store_true")
    args = p.parse_args(argv)
    n = args.samples
    t = np.linspace(0.0, 200.0, n)
    x = 1.5 * np.sin(t) * np.cos(0.37 * t) + 0.3 * np.sin(7.1 * t)
    results: Dict[str, Dict[str, float]] = {}
    for name, cls, inverse, dtype in [
        ("inverse", hyst.InverseHysteresis, True, "float64"),
        ("direct", hyst.Hysteresis, False, "float64"),
        ("inverse_f32", hyst.InverseHysteresis, True, "float32"),
    ]:
        xs = x.astype(dtype)
        op = cls(0.2, 8.0, dtype=dtype)

        def run() -> None:
            op.reset()
            op.process(xs)

        python_ns = best(run, args.repeats) * 1e9 / n
        buf = np.empty_like(xs)

        def run_out() -> None:
            op.reset()
            op.process(xs, out=buf)

        out_ns = best(run_out, args.repeats) * 1e9 / n
        core_ns = _hyst._bench_core(0.2, 8.0, xs, inverse=inverse, dtype=dtype, repeats=args.repeats)
        step_samples = xs[: min(n, 200_000)].tolist()
        step = op.step

        def steps() -> None:
            for v in step_samples:
                step(v)

        step_ns = best(steps, 3) * 1e9 / len(step_samples)
        results[name] = {
            "process_ns": python_ns,
            "core_ns": core_ns,
            "ratio": python_ns / core_ns,
            "process_out_ns": out_ns,
            "ratio_out": out_ns / core_ns,
            "step_call_ns": step_ns,
        }
    if args.json:
        print(json.dumps(results, indent=2))
    else:
        print(f"{'operator':<12} {'process':>8} {'out=':>8} {'core':>8} {'ratio':>6} {'out=':>6} {'step() ns/call':>15}")
        for name, r in results.items():
            print(
                f"{name:<12} {r['process_ns']:>8.2f} {r['process_out_ns']:>8.2f} {r['core_ns']:>8.2f} "
                f"{r['ratio']:>6.3f} {r['ratio_out']:>6.3f} {r['step_call_ns']:>15.1f}"
            )
        print("(ns per sample; process: a new result array; out=: into a reused array)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
