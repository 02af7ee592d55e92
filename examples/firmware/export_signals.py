#!/usr/bin/env python3
"""The test signals of the exported models (scripts/test-firmware, docs/c.md).

    export_signals.py HYST OUT MODEL.toml...

For each model NAME.toml: an input x spanning the model's input range (a Prandtl-Ishlinskii
model, which has no normalisation, takes that of a smooth model of the same input column) (a sine whose amplitude
grows from 0 to 95 % of the range, with minor loops), written to OUT/NAME.x.csv; `HYST run
--model` of it gives the outputs OUT/NAME.dir.csv, which become the desired outputs of the inverse
(OUT/NAME.y.csv; `HYST run --model --inverse --saturate` gives OUT/NAME.inv.csv, except for the
stop form, which has no inverse). OUT/export_signals.h holds the smooth models' x and desired
outputs as C arrays of doubles, each written as the shortest decimal that reads back to the same
double (the C firmware API has no Prandtl-Ishlinskii model).

A model with dynamics (a model file's [dynamics], order n) runs on timed records of period
PERIOD (2^-10 s: the mean step of their time stamps is this number exactly, the period its
exports take with --period): x with a time column gives OUT/NAME.dir.csv (the model with its
plant), and a smooth desired output within the direct outputs' range, with its first n time
derivatives in the columns y_d1 ... y_dn (OUT/NAME.desired.csv, from rest), gives `HYST run
--model --inverse`'s commands OUT/NAME.inv.csv (Lemma 5.1's compensator). export_signals.h
holds NAME_desired[EXP_SAMPLES][n + 1]."""
import csv
import math
import pathlib
import subprocess
import sys
import tomllib

SAMPLES = 400
PERIOD = 2.0 ** -10


def input_range(model, ranges):
    """The input interval that hyst fit's normalisation maps to [-1, 1] (psi_in's pre-scaling)."""
    if "smooth" not in model:
        return ranges[model["columns"]["input"]]
    psi = model["smooth"]["input_shaping"]
    gain, offset = psi["pre_gain"], psi["pre_offset"]
    return sorted(((-1.0 - offset) / gain, (1.0 - offset) / gain))


def signal(lo, hi):
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    x = []
    for i in range(SAMPLES):
        t = i / SAMPLES
        amplitude = 0.95 * min(1.0, 1.6 * t)
        x.append(mid + half * amplitude * (0.85 * math.sin(6 * math.pi * t)
                                           + 0.15 * math.sin(31 * math.pi * t)))
    return x


def saturation_range(model):
    """The open output range of a saturating psi_out (tanh, Langevin: post_offset +- |post_gain
    gain|), or None."""
    psi = model.get("smooth", {}).get("output_shaping", {})
    shape = psi.get("shape")
    if not isinstance(shape, dict):
        return None
    for kind in ("tanh", "langevin"):
        if kind in shape:
            half = abs(psi["post_gain"] * shape[kind]["gain"])
            return psi["post_offset"] - half, psi["post_offset"] + half
    return None


def desired(lo, hi, order):
    """A desired output in [lo, hi] from rest and its first `order` time derivatives: two
    cosines, 5 Hz and 15 Hz (reversals and minor loops), rows of order + 1 values."""
    span, w = hi - lo, 2 * math.pi * 5.0
    parts = [(0.25 * span, w), (0.05 * span, 3 * w)]  # amplitude a: a (1 - cos(w t))
    rows = []
    for i in range(SAMPLES):
        t = i * PERIOD
        row = [lo + 0.2 * span + sum(a * (1 - math.cos(f * t)) for a, f in parts)]
        for k in range(1, order + 1):
            # d^k/dt^k (1 - cos(f t)) = f^k (sin, cos, -sin, -cos)(f t) for k = 1, 2, 3, 4 (mod 4)
            wave = [lambda v: -math.cos(v), math.sin, math.cos, lambda v: -math.sin(v)][k % 4]
            row.append(sum(a * f ** k * wave(f * t) for a, f in parts))
        rows.append(row)
    return rows


def timed(hyst, out, name, path, model, x):
    """The timed runs of a model with dynamics (see the module's documentation); the arrays of
    export_signals.h."""
    order = len(model["dynamics"]["a"])
    with open(out / f"{name}.x.csv", "w", newline="") as f:
        f.write("t,x\n")
        for i, v in enumerate(x):
            f.write(f"{i * PERIOD!r},{v!r}\n")
    run(hyst, ["--model", path, "--column", "x"], out / f"{name}.x.csv", out / f"{name}.dir.csv")
    y = column(out / f"{name}.dir.csv", "y")
    rows = desired(min(y), max(y), order)
    with open(out / f"{name}.desired.csv", "w", newline="") as f:
        f.write(",".join(["t", "y"] + [f"y_d{k}" for k in range(1, order + 1)]) + "\n")
        for i, row in enumerate(rows):
            f.write(",".join(repr(v) for v in [i * PERIOD] + row) + "\n")
    run(hyst, ["--model", path, "--inverse", "--column", "y"], out / f"{name}.desired.csv",
        out / f"{name}.inv.csv")
    return [(f"{name}_x", x)], [(f"{name}_desired", rows)]


def run(hyst, args, src, dst, **kw):
    """`hyst run ARGS SRC`, keeping in DST (header `y`) the column it computes: the first after
    SRC's own columns, which hyst run passes through first (docs/formats.md)."""
    full = dst.with_suffix(".run.csv")
    subprocess.run([hyst, "run", *args, str(src), "-o", str(full)], check=True, **kw)
    with open(src, newline="") as f:
        width = len(next(csv.reader(f)))
    with open(full, newline="") as f, open(dst, "w", newline="") as g:
        g.write("y\n")
        for row in list(csv.reader(f))[1:]:
            g.write(row[width] + "\n")


def column(path, name):
    with open(path, newline="") as f:
        return [float(row[name]) for row in csv.DictReader(f)]


def write_csv(path, name, values):
    with open(path, "w", newline="") as f:
        f.write(name + "\n")
        for v in values:
            f.write(repr(v) + "\n")


def main():
    hyst, out, models = sys.argv[1], pathlib.Path(sys.argv[2]), sys.argv[3:]
    out.mkdir(parents=True, exist_ok=True)
    arrays = []
    tables = []
    ranges = {}
    loaded = [(path, tomllib.loads(pathlib.Path(path).read_text())) for path in models]
    # Smooth models first: they give a Prandtl-Ishlinskii model of the same input its range.
    loaded.sort(key=lambda pm: "smooth" not in pm[1])
    for path, model in loaded:
        name = pathlib.Path(path).stem
        x_range = input_range(model, ranges)
        ranges.setdefault(model["columns"]["input"], x_range)
        x = signal(*x_range)
        if "dynamics" in model:
            plain, rows = timed(hyst, out, name, path, model, x)
            arrays += plain
            tables += rows
            continue
        write_csv(out / f"{name}.x.csv", "x", x)
        run(hyst, ["--model", path, "--column", "x"], out / f"{name}.x.csv",
            out / f"{name}.dir.csv")
        y = column(out / f"{name}.dir.csv", "y")
        smooth = "smooth" in model
        if smooth:
            arrays.append((f"{name}_x", x))
        if not smooth or model["smooth"].get("form", "operator") == "operator":
            # A saturating model's inverse clamps: its last ten desired outputs go beyond the
            # range, alternately above and below.
            limits = saturation_range(model)
            if limits is not None:
                lo, hi = limits
                y = y[:-10] + [hi + 0.1 * (hi - lo) if k % 2 else lo - 0.1 * (hi - lo)
                               for k in range(10)]
            write_csv(out / f"{name}.y.csv", "y", y)
            run(hyst, ["--model", path, "--inverse", "--saturate", "--column", "y"],
                out / f"{name}.y.csv", out / f"{name}.inv.csv", stderr=subprocess.DEVNULL)
            if smooth:
                arrays.append((f"{name}_y", y))
    lines = ["/* Generated by examples/firmware/export_signals.py: the exported models' test "
             "signals. */",
             "#ifndef EXPORT_SIGNALS_H", "#define EXPORT_SIGNALS_H", "",
             f"#define EXP_SAMPLES {SAMPLES}", ""]
    for name, values in arrays:
        lines.append(f"static const double {name}[EXP_SAMPLES] = {{")
        lines += [f"    {v!r}," for v in values]
        lines += ["};", ""]
    for name, rows in tables:
        lines.append(f"static const double {name}[EXP_SAMPLES][{len(rows[0])}] = {{")
        lines += ["    {" + ", ".join(repr(v) for v in row) + "}," for row in rows]
        lines += ["};", ""]
    lines.append("#endif")
    (out / "export_signals.h").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
