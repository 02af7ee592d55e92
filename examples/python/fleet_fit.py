#!/usr/bin/env python3
"""Fit many actuator records in parallel on Dask: one model file per record and a summary CSV.

    # measured records, one CSV per actuator:
    python examples/python/fleet_fit.py records/*.csv --input x --output y --out models/
    # synthetic actuators with known parameters (a check of the whole chain):
    python examples/python/fleet_fit.py --synthetic 64 --out models/
    # on a running cluster instead of a LocalCluster on this machine:
    python examples/python/fleet_fit.py records/*.csv --input x --output y --scheduler tcp://host:8786

Each task runs `hyst.fit` on one record on a worker (the fit releases the GIL; one thread per
worker process is right). Records travel to the workers as arrays and models come back as
model-file text, so the workers need no shared file system. Any extra `--option value` pairs
after `--` are passed to `hyst.fit` (e.g. `-- --output_shaping poly2 --k2 affine`).

A record that fails (a file that cannot be read, a missing column, a value that is not a number,
an error of its fit, a task lost with its worker) does not stop the others: its row of
summary.csv holds the error message, the message goes to standard error too, and the script
exits with status 1 once every record has been tried.

Synthetic actuators: y = gain * H(k1, k2)[x] + offset + noise, the input x spanning [-1, 1]
exactly (so the fit's normalised input units are the truth's units) and starting without history (the fit's
`initial_state="line"`). The summary then holds each true value and its z-score
(estimate - truth) / standard error.
"""

import argparse
import asyncio
import csv
import json
import sys
from pathlib import Path

from typing import Any, Dict, List, Optional, Tuple

import numpy as np

PARAMS = ["k1", "k2", "out.gain", "out.offset"]


def synthetic_truth(seed: int) -> Dict[str, float]:
    """The known parameters of synthetic actuator `seed`."""
    rng = np.random.default_rng(seed)
    return {
        "k1": float(rng.uniform(0.05, 0.3)),
        "k2": float(rng.uniform(3.0, 12.0)),
        "out.gain": float(rng.uniform(5.0, 20.0)),
        "out.offset": float(rng.uniform(-5.0, 5.0)),
    }


def synthetic_record(seed: int, samples: int, noise: float) -> Tuple[Any, Any, Dict[str, float]]:
    """(x, y, truth) of synthetic actuator `seed`: a decaying sine with minor loops through the
    truth operator, plus white noise of `noise` output units."""
    import hyst

    truth = synthetic_truth(seed)
    rng = np.random.default_rng(seed + 1_000_003)
    t = np.linspace(0.0, 1.0, samples)
    x = np.sin(2 * np.pi * 3 * t) * (1.0 - 0.7 * t) + 0.25 * np.sin(2 * np.pi * 17 * t + seed)
    x = 2.0 * (x - x.min()) / (x.max() - x.min()) - 1.0
    h = hyst.Hysteresis(truth["k1"], truth["k2"])
    y = truth["out.gain"] * h.process(x) + truth["out.offset"] + noise * rng.standard_normal(samples)
    return x, y, truth


def read_record(path: Path, input_column: str, output_column: str) -> Tuple[Any, Any]:
    """(x, y) of one CSV record. Raises OSError for a file that cannot be read and ValueError
    naming the file for a missing column or a value that is not a number."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{path}: no data rows")
    for col in (input_column, output_column):
        if col not in rows[0]:
            raise ValueError(f"{path}: no column {col!r} (columns: {', '.join(rows[0])})")
    try:
        x = np.array([float(r[input_column]) for r in rows])
        y = np.array([float(r[output_column]) for r in rows])
    except (TypeError, ValueError) as e:
        raise ValueError(f"{path}: {e}") from e
    return x, y


def error_row(name: str, error: BaseException) -> Tuple[Dict[str, Any], Optional[str]]:
    """The summary row of a record that could not be fitted (no model file)."""
    message = str(error) or type(error).__name__
    if not isinstance(error, ValueError):  # say what kind of failure it was
        message = f"{type(error).__name__}: {message}"
    return {"record": name, "error": message}, None


def fit_one(name: str, x: Any, y: Any, options: Dict[str, Any]) -> Tuple[Dict[str, Any], Optional[str]]:
    """Runs on a worker: fits one record, returns the summary row and the model file text. Any
    error of this record (the model cannot represent it, a bad option) is its row's `error`,
    not the batch's."""
    import hyst

    try:
        r = hyst.fit(x, y, **options)
    except Exception as e:  # reported in the summary, not fatal to the other records
        return error_row(name, e)
    row: Dict[str, Any] = {"record": name, "rms": r.rms, "rms_percent": r.rms_percent, "delta_a": r.delta_a}
    for p, v in r.params.items():
        row[p] = v
        row[p + ".std_error"] = r.std_errors[p]
    return row, r.model.to_toml()


def fit_synthetic(seed: int, samples: int, noise: float, options: Dict[str, Any]) -> Tuple[Dict[str, Any], Optional[str]]:
    """Runs on a worker: makes synthetic actuator `seed` there (nothing to ship) and fits it."""
    x, y, truth = synthetic_record(seed, samples, noise)
    row, toml = fit_one(f"synthetic-{seed:04d}", x, y, options)
    for p, v in truth.items():
        row[p + ".true"] = v
        if p in row and row.get(p + ".std_error"):
            row[p + ".z"] = (row[p] - v) / row[p + ".std_error"]
    return row, toml


def parse_extra(pairs: List[str]) -> Dict[str, Any]:
    """`--name value` pairs for hyst.fit; values read as JSON when they parse (numbers, true)."""
    options: Dict[str, Any] = {}
    it = iter(pairs)
    for key in it:
        if not key.startswith("--"):
            raise SystemExit(f"fleet_fit: expected --option value after --, got {key!r}")
        value = next(it, None)
        if value is None:
            raise SystemExit(f"fleet_fit: {key} needs a value")
        try:
            options[key[2:].replace("-", "_")] = json.loads(value)
        except json.JSONDecodeError:
            options[key[2:].replace("-", "_")] = value
    return options


def gather(tasks: List[Any], names: List[str]) -> List[Tuple[Dict[str, Any], Optional[str]]]:
    """The results in the order of the records: a task's result, or the error row already made
    for a record that was never sent. A task that failed on its worker (a lost worker, a
    cancelled task) becomes its record's error row instead of stopping the others."""
    results = []
    for name, task in zip(names, tasks):
        if isinstance(task, tuple):
            results.append(task)
            continue
        try:
            results.append(task.result())
        except (Exception, asyncio.CancelledError) as e:
            results.append(error_row(name, e))
    return results


def main(argv: Optional[List[str]] = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = []
    if "--" in argv:
        i = argv.index("--")
        argv, extra = argv[:i], argv[i + 1 :]
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("records", nargs="*", type=Path, help="CSV files, one record each")
    p.add_argument("--input", help="input column of the CSV files")
    p.add_argument("--output", help="output column of the CSV files")
    p.add_argument("--synthetic", type=int, metavar="N", help="fit N synthetic actuators instead")
    p.add_argument("--samples", type=int, default=4000, help="samples per synthetic record")
    p.add_argument("--noise", type=float, default=0.01, help="noise of synthetic records (output units)")
    p.add_argument("--out", type=Path, required=True, help="directory for the model files and summary.csv")
    p.add_argument("--scheduler", help="address of a Dask scheduler (default: a LocalCluster)")
    p.add_argument("--workers", type=int, default=2, help="LocalCluster worker processes")
    args = p.parse_args(argv)
    options = parse_extra(extra)
    if bool(args.records) == bool(args.synthetic):
        p.error("give CSV records or --synthetic N (one of them)")
    if args.records and not (args.input and args.output):
        p.error("CSV records need --input and --output")

    from dask.distributed import Client, LocalCluster

    cluster = None
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address=None)
        client = Client(cluster)
    try:
        if args.synthetic:
            options.setdefault("initial_state", "line")
            names = [f"synthetic-{seed:04d}" for seed in range(args.synthetic)]
            tasks: List[Any] = [
                client.submit(fit_synthetic, seed, args.samples, args.noise, options, pure=False)
                for seed in range(args.synthetic)
            ]
        else:
            names, tasks = [], []  # a task: a future, or the error row of a file not sent
            for path in args.records:
                names.append(path.stem)
                try:
                    x, y = read_record(path, args.input, args.output)
                except (OSError, ValueError) as e:  # this file's failure, not the batch's
                    tasks.append(error_row(path.stem, e))
                    continue
                tasks.append(client.submit(fit_one, path.stem, x, y, options, pure=False))
        results = gather(tasks, names)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()

    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for row, toml in results:
        if toml is not None:
            (args.out / f"{row['record']}.toml").write_text(toml)
        rows.append(row)
    columns = []
    for row in rows:
        columns += [c for c in row if c not in columns]
    summary = args.out / "summary.csv"
    with open(summary, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns)
        w.writeheader()
        w.writerows(rows)
    failed = [r for r in rows if "error" in r]
    print(f"fitted {len(rows) - len(failed)} of {len(rows)} records; wrote {summary}")
    for r in failed:
        print(f"  {r['record']}: {r['error']}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
