#!/usr/bin/env python3
"""Fit the bundled piezo record, compute the command that makes the actuator follow a desired
trajectory, and plot data, model and command to a PNG.

    python examples/python/piezo_compensation.py [--data CSV] [--out DIR]

The model maps its input x (the actuator voltage) to its output y (the displacement):
y = psi_out(H(k1, k2)[psi_in(x)]) (eq. 2 inside affine shaping). The command is its exact
inverse (eq. 4 inside the shaping) applied to the desired output, so the model driven by the
command reproduces the desired output to rounding. The family bound delta_a
says how far the real actuator may still be from it (Propositions 3.2, 3.3).
"""

import argparse
import csv
import sys
from pathlib import Path

from typing import List, Optional

import numpy as np

import hyst

ROOT = Path(__file__).resolve().parents[2]


def main(argv: Optional[List[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--data", type=Path, default=ROOT / "data" / "piezo-sine" / "piezo_sine_1hz.csv")
    p.add_argument("--input", default="u_actuator_V", help="input column (V)")
    p.add_argument("--output", default="y_capsensor_um", help="output column (um)")
    p.add_argument("--out", type=Path, default=Path("."), help="directory for the PNG and model")
    args = p.parse_args(argv)

    with open(args.data, newline="") as f:
        rows = list(csv.DictReader(f))
    x = np.array([float(r[args.input]) for r in rows])
    y = np.array([float(r[args.output]) for r in rows])

    fit = hyst.fit(x, y, input_name=args.input, output_name=args.output, input_unit="V", output_unit="um")
    print(fit.report())

    # A desired trajectory inside the measured range: two tones, 2 s at the record's rate.
    lo, hi = np.percentile(y, [5, 95])
    t = np.linspace(0.0, 2.0, 2000)
    desired = 0.5 * (lo + hi) + 0.45 * (hi - lo) * (0.8 * np.sin(2 * np.pi * 1.0 * t) + 0.2 * np.sin(2 * np.pi * 3.7 * t))

    command = fit.model.inverse().process(desired)        # the exact inverse (eq. 4)
    achieved = fit.model.process(command)                   # the model driven by it
    gain, offset = np.polyfit(x, y, 1)                      # what a linear inverse would send
    linear_command = (desired - offset) / gain
    linear_achieved = fit.model.process(linear_command)

    err_comp = np.max(np.abs(achieved - desired))
    err_lin = np.max(np.abs(linear_achieved - desired))
    print(f"model tracking error: compensated {err_comp:.3g} um, linear inverse {err_lin:.3g} um")
    if fit.output_bound is not None:
        print(f"guaranteed for a device in the fitted family: within {fit.output_bound:.3g} um")

    args.out.mkdir(parents=True, exist_ok=True)
    fit.model.save(args.out / "piezo.toml")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    ax[0].plot(x, y, ".", ms=1.5, color="0.6", label="measured")
    ax[0].plot(x, fit.model.process(x), lw=0.8, color="C0", label="model")
    ax[0].set(xlabel="x (V)", ylabel="y (um)", title=f"fit: RMS {fit.rms_percent:.2f} % of span")
    ax[0].legend()
    ax[1].plot(t, desired, color="k", lw=2, label="desired")
    ax[1].plot(t, achieved, "--", color="C0", label="with hyst compensation")
    ax[1].plot(t, linear_achieved, color="C3", lw=0.8, label="linear inverse")
    ax[1].set(xlabel="t (s)", ylabel="y (um)", title="model output")
    ax[1].legend()
    ax[2].plot(t, command, color="C0", label="hyst command")
    ax[2].plot(t, linear_command, color="C3", lw=0.8, label="linear command")
    ax[2].set(xlabel="t (s)", ylabel="x (V)", title="command")
    ax[2].legend()
    fig.tight_layout()
    png = args.out / "piezo_compensation.png"
    fig.savefig(png, dpi=110)
    print(f"wrote {png} and {args.out / 'piezo.toml'}")
    return 0 if err_comp < 1e-6 * (hi - lo) else 1


if __name__ == "__main__":
    sys.exit(main())
