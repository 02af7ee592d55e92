"""The Python examples run as a user runs them: piezo compensation to a PNG, the fleet fit on
a Dask LocalCluster (2 worker processes) with parameters recovered within their standard
errors, and the benchmark (for its output, not its timings)."""

import csv
import json
import subprocess
import sys

import numpy as np

from conftest import ROOT

EXAMPLES = ROOT / "examples" / "python"


def run(script, *args, timeout=600):
    return subprocess.run(
        [sys.executable, str(EXAMPLES / script), *map(str, args)],
        capture_output=True, text=True, timeout=timeout,
    )


def test_piezo_compensation(tmp_path):
    p = run("piezo_compensation.py", "--out", tmp_path)
    assert p.returncode == 0, p.stderr
    png = tmp_path / "piezo_compensation.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
    assert (tmp_path / "piezo.toml").exists()
    assert "compensated" in p.stdout and "linear inverse" in p.stdout


def test_fleet_fit_recovers_known_parameters(tmp_path):
    p = run("fleet_fit.py", "--synthetic", 16, "--workers", 2, "--out", tmp_path)
    assert p.returncode == 0, p.stderr + p.stdout
    with open(tmp_path / "summary.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 16
    assert len(list(tmp_path.glob("synthetic-*.toml"))) == 16
    params = ["k1", "k2", "out.gain", "out.offset"]
    z = np.array([[float(r[f"{q}.z"]) for q in params] for r in rows])
    # Every estimate within a few standard errors of its truth, and the standard errors
    # calibrated: the z-scores of 64 estimates have an RMS near 1 and most lie within +-1.
    assert np.all(np.abs(z) < 4.5), z
    assert 0.5 < np.sqrt(np.mean(z**2)) < 1.6
    assert np.mean(np.abs(z) <= 1.0) >= 0.5
    # A model file per actuator, usable from Python.
    import hyst

    m = hyst.load_model(tmp_path / "synthetic-0003.toml")
    assert m.params["k1"] == float(rows[3]["k1"])


def test_fleet_fit_on_csv_records(tmp_path, piezo_path):
    p = run("fleet_fit.py", piezo_path, piezo_path, "--input", "u_actuator_V", "--output",
            "y_capsensor_um", "--workers", 1, "--out", tmp_path, "--", "--output_shaping", "poly2")
    assert p.returncode == 0, p.stderr + p.stdout
    rows = list(csv.DictReader(open(tmp_path / "summary.csv")))
    assert rows[0]["k1"] == rows[1]["k1"] and "out.q2" in rows[0]


def test_bench_runs():
    p = run("bench.py", "--samples", 20000, "--repeats", 2, "--json")
    assert p.returncode == 0, p.stderr
    r = json.loads(p.stdout)
    assert set(r) == {"inverse", "direct", "inverse_f32"}
    assert all(v["ratio"] > 0 and v["ratio_out"] > 0 and v["step_call_ns"] > 0 for v in r.values())


def test_docs_first_example_runs():
    """The first Python block of docs/python.md, run as written."""
    text = (ROOT / "docs" / "python.md").read_text()
    block = text.split("```python\n", 1)[1].split("```", 1)[0]
    exec(compile(block, "docs/python.md", "exec"), {})


def test_docs_bank_example_runs():
    """The Python block under "## A bank of operators" in docs/python.md, run as written."""
    text = (ROOT / "docs" / "python.md").read_text()
    section = text.split("## A bank of operators\n", 1)[1]
    block = section.split("```python\n", 1)[1].split("```", 1)[0]
    exec(compile(block, "docs/python.md", "exec"), {})
