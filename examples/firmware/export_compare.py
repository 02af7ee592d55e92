#!/usr/bin/env python3
"""Compares the exported models' outputs (exported.c's lines) with `hyst run --model`'s.

    export_compare.py SIGNALS RUN_OUTPUT [--identical]

SIGNALS is export_signals.py's folder (NAME.dir.csv, NAME.inv.csv: hyst run's outputs). For each
double series (`e NAME.dir|inv INDEX BITS`) it counts the values bit-identical to hyst run's and
the largest difference as a fraction of the series' output span; it fails when a difference
exceeds 1e-12 of the span, or, with --identical, when any value differs. The float series
(`...32`) are a gross check, within 1e-3 of the span: single precision resolves the operator's
input to about 6e-8 of its range, which is a larger share of a narrow loop (the header's comment
states it as a share of k1). Prints one line per series."""
import csv
import struct
import sys

TOLERANCE = 1e-12
TOLERANCE_F32 = 1e-3


def reference(folder, series):
    with open(f"{folder}/{series}.csv", newline="") as f:
        return [float(row["y"]) for row in csv.DictReader(f)]


def main():
    folder, run_output = sys.argv[1], sys.argv[2]
    identical_required = "--identical" in sys.argv[3:]
    series = {}
    with open(run_output) as f:
        for line in f:
            if line.startswith("e "):
                _, name, index, bits = line.split()
                if name.endswith("32"):
                    value = struct.unpack(">f", bytes.fromhex(bits))[0]
                else:
                    value = struct.unpack(">d", bytes.fromhex(bits))[0]
                if ".cmp" in name:
                    continue  # the compensator: hyst run has none for a static model
                series.setdefault(name, []).append((int(index), value))
    failed = False
    for name, values in series.items():
        f32 = name.endswith("32")
        ref = reference(folder, name[:-2] if f32 else name)
        if len(ref) != len(values):
            print(f"{name}: {len(values)} values, hyst run gave {len(ref)}: FAIL")
            failed = True
            continue
        span = max(ref) - min(ref) or 1.0
        same = sum(1 for (_, v), r in zip(values, ref) if v == r)
        worst = max(abs(v - r) for (_, v), r in zip(values, ref)) / span
        limit = TOLERANCE_F32 if f32 else TOLERANCE
        ok = worst <= limit and (f32 or not identical_required or same == len(ref))
        failed |= not ok
        print(f"{name}: {same} of {len(ref)} bit-identical to hyst run, largest difference "
              f"{worst:.3g} of the span (limit {limit:g}{', bit-identical' if identical_required and not f32 else ''}): "
              f"{'pass' if ok else 'FAIL'}")
    if not series:
        print("no values to compare: FAIL")
        failed = True
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
