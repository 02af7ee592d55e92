#!/usr/bin/env python3
"""A PI loop around a piezo actuator with hysteresis, closed in python-control, with and without
hyst's compensator (the exact inverse of the actuator's hysteresis model).

    python examples/python/pi_loop.py                      # writes pi_loop.png here
    python examples/python/pi_loop.py --out /tmp/loop.png

The actuator is the model fitted to the bundled piezo record (data/piezo-sine: volts in,
micrometres out), followed by a first-order lag of TAU seconds (its mechanics and sensor). The
loop runs at 1 kHz, with the reference fed forward and a PI controller on the error:

    u_d = r + PI(r - y);   u_d --compensator--> x --hysteresis--> lag --> y

u_d is the actuator output asked for (µm). The compensator turns it into the command x (V):
hyst's exact inverse of the fitted model (``hyst.control.iosys(model.inverse(), dt)``) or, for
comparison, the straight line fitted to the same data (what a linear design would use). All
blocks are python-control systems, closed by ``control.interconnect`` and run by
``control.input_output_response``. The reference is a two-tone trajectory; the loop starts on
its first value (the lag's output there, the PI's integral at 0). The script prints the RMS
tracking error of both loops after the start-up (t >= SETTLE s) and plots the outputs, the
errors and the commands.

Needs python-control and matplotlib (``pip install "./crates/hyst-py[control,plot]"``).
"""

import argparse
import csv
import sys
from pathlib import Path
from typing import Any, List, Optional, Tuple

import numpy as np

import hyst
import hyst.control

ROOT = Path(__file__).resolve().parents[2]
PIEZO = ROOT / "data" / "piezo-sine" / "piezo_sine_1hz.csv"

DT = 1e-3  # sample time of the loop (s)
TAU = 0.01  # time constant of the actuator's lag (s)
KP, KI = 0.3, 60.0  # PI gains (µm/µm, µm/(µm·s))
SETTLE = 0.25  # start-up left out of the RMS errors (s)


def piezo() -> Tuple[np.ndarray, np.ndarray]:
    """(volts, micrometres) of the bundled record."""
    with open(PIEZO, newline="") as f:
        rows = list(csv.DictReader(f))
    return (
        np.array([float(r["u_actuator_V"]) for r in rows]),
        np.array([float(r["y_capsensor_um"]) for r in rows]),
    )


def closed_loop(ct: Any, compensator: Any, actuator: Any) -> Any:
    """r -> (y, x, u_d): u_d = r + PI(r - y), then `compensator` (u_d -> x), the actuator."""
    error = ct.summing_junction(inputs=["r", "-y"], output="e", name="error")
    pi = ct.ss([[1.0]], [[DT]], [[KI]], [[KP]], DT, inputs="e", outputs="c", states="integral", name="pi")
    feedforward = ct.summing_junction(inputs=["r", "c"], output="ud", name="feedforward")
    a = float(np.exp(-DT / TAU))
    lag = ct.ss([[a]], [[1.0 - a]], [[1.0]], [[0.0]], DT, inputs="h", outputs="y", states="position", name="lag")
    return ct.interconnect(
        [error, pi, feedforward, compensator, actuator, lag], inputs="r", outputs=["y", "x", "ud"], name="loop"
    )


def at_rest(ct: Any, loop: Any, r0: float) -> np.ndarray:
    """The initial state on r0: the lag's output at r0, the PI's integral at 0, the hysteresis
    systems without history (their start rules)."""
    x0 = np.zeros(loop.nstates)
    labels: List[str] = list(loop.state_labels)
    sep = ct.config.defaults["iosys.state_name_delim"]  # "lag_position" by default
    x0[labels.index(f"lag{sep}position")] = r0
    return x0


def main(argv: Optional[List[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=Path("pi_loop.png"), help="PNG file to write (default: ./pi_loop.png)")
    p.add_argument("--seconds", type=float, default=2.0, help="length of the run (s)")
    args = p.parse_args(argv)

    import control as ct

    volts, um = piezo()
    model = hyst.fit(volts, um, output_shaping="poly2", input_unit="V", output_unit="um").model
    slope, offset = np.polyfit(volts, um, 1)  # the linear design's actuator model

    actuator = hyst.control.iosys(model, DT, inputs="x", outputs="h", name="hysteresis")
    with_hyst = closed_loop(ct, hyst.control.iosys(model.inverse(), DT, inputs="ud", outputs="x", name="inverse"), actuator)
    linear = ct.NonlinearIOSystem(
        None, lambda t, x, u, params: (u - offset) / slope, inputs="ud", outputs="x", dt=DT, name="linear"
    )
    with_line = closed_loop(ct, linear, actuator)

    t = np.arange(int(round(args.seconds / DT)) + 1) * DT
    lo, hi = np.percentile(um, [5, 95])
    r = 0.5 * (lo + hi) + 0.4 * (hi - lo) * (0.8 * np.sin(2 * np.pi * 1.0 * t) + 0.2 * np.sin(2 * np.pi * 3.7 * t))

    runs = {}
    for label, loop in [("hyst compensator", with_hyst), ("linear inverse", with_line)]:
        resp = ct.input_output_response(loop, t, r, X0=at_rest(ct, loop, float(r[0])))
        y, x = resp.outputs[0], resp.outputs[1]
        after = t >= SETTLE
        runs[label] = (y, x, float(np.sqrt(np.mean((y - r)[after] ** 2))))

    rms_h, rms_l = runs["hyst compensator"][2], runs["linear inverse"][2]
    print(
        f"RMS tracking error (t >= {SETTLE:g} s): {rms_h:.3g} um with the hyst compensator, "
        f"{rms_l:.3g} um with a linear inverse"
    )
    print(f"(reference span {np.ptp(r):.3g} um; PI kp = {KP}, ki = {KI}/s; actuator lag {TAU * 1e3:g} ms; loop at {1 / DT:g} Hz)")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(3, 1, figsize=(10, 9), sharex=True)
    ax[0].plot(t, r, color="k", lw=2, label="reference")
    for (label, (y, x, rms)), color in zip(runs.items(), ["C0", "C3"]):
        ax[0].plot(t, y, "--" if color == "C0" else "-", color=color, lw=1, label=f"{label} (RMS error {rms:.3g} um after {SETTLE:g} s)")
        ax[1].plot(t, y - r, color=color, lw=1, label=label)
        ax[2].plot(t, x, color=color, lw=1, label=label)
    ax[0].set(ylabel="y (um)", title="PI loop around a piezo actuator with hysteresis (python-control)")
    ax[1].set(ylabel="y - r (um)")
    ax[2].set(xlabel="t (s)", ylabel="command x (V)")
    for a in ax:
        a.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")
    return 0 if rms_h < rms_l else 1


if __name__ == "__main__":
    sys.exit(main())
