"""examples/python/fleet_fit.py when records fail: a file without the named column, with a value
that is not a number, or a fit that raises, is reported in summary.csv with its error, the other
records are fitted, and the script exits with status 1."""

import csv
import importlib.util
import subprocess
import sys

import pytest

from conftest import ROOT

SCRIPT = ROOT / "examples" / "python" / "fleet_fit.py"
INPUT, OUTPUT = "u_actuator_V", "y_capsensor_um"


def load_example():
    spec = importlib.util.spec_from_file_location("fleet_fit", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture()
def records(tmp_path, piezo_path):
    """Two good records, one without the output column, one with a value that is not a number."""
    text = piezo_path.read_text()
    d = tmp_path / "records"
    d.mkdir()
    (d / "a-good.csv").write_text(text)
    (d / "b-no-column.csv").write_text(text.replace(OUTPUT, "y_other", 1))
    lines = text.splitlines(keepends=True)
    header = lines[0].rstrip("\n").split(",")
    row = lines[10].rstrip("\n").split(",")
    row[header.index(INPUT)] = "oops"
    lines[10] = ",".join(row) + "\n"
    (d / "c-not-a-number.csv").write_text("".join(lines))
    (d / "d-good.csv").write_text(text)
    return sorted(d.glob("*.csv"))


def summary(path):
    with open(path / "summary.csv", newline="") as f:
        return {r["record"]: r for r in csv.DictReader(f)}


def test_read_record_names_the_file_and_column(records):
    fleet = load_example()
    x, y = fleet.read_record(records[0], INPUT, OUTPUT)
    assert len(x) == len(y) == 8027
    with pytest.raises(ValueError, match=r"b-no-column\.csv: no column 'y_capsensor_um' \(columns: .*y_other"):
        fleet.read_record(records[1], INPUT, OUTPUT)
    with pytest.raises(ValueError, match=r"c-not-a-number\.csv: could not convert string to float: 'oops'"):
        fleet.read_record(records[2], INPUT, OUTPUT)


def test_fit_one_reports_its_own_error_without_dask(records):
    """The per-record function on its own (no Dask): a fit error and a bad option are rows."""
    fleet = load_example()
    x, y = fleet.read_record(records[0], INPUT, OUTPUT)
    row, toml = fleet.fit_one("a", x, y, {})
    assert toml is not None and "k1" in row and "error" not in row
    row, toml = fleet.fit_one("flat", x, 0.0 * x + 1.0, {})
    assert toml is None and row["record"] == "flat" and "hysteresis" in row["error"]
    row, toml = fleet.fit_one("a", x, y, {"no_such_option": 1})
    assert toml is None and row["error"].startswith("TypeError: ") and "no_such_option" in row["error"]


def test_gather_turns_a_failed_task_into_its_row():
    fleet = load_example()

    class Lost:
        def result(self):
            raise RuntimeError("worker lost")

    class Done:
        def result(self):
            return {"record": "ok", "k1": 0.1}, "toml"

    made = ({"record": "unread", "error": "no file"}, None)
    rows = fleet.gather([Done(), Lost(), made], ["ok", "lost", "unread"])
    assert rows[0] == ({"record": "ok", "k1": 0.1}, "toml")
    assert rows[1] == ({"record": "lost", "error": "RuntimeError: worker lost"}, None)
    assert rows[2] is made


def test_failing_files_are_reported_and_the_batch_completes(records, tmp_path):
    pytest.importorskip("dask.distributed")
    out = tmp_path / "models"
    p = subprocess.run(
        [sys.executable, str(SCRIPT), *map(str, records), "--input", INPUT, "--output", OUTPUT,
         "--workers", "1", "--out", str(out)],
        capture_output=True, text=True, timeout=600,
    )
    assert p.returncode == 1, p.stdout + p.stderr
    assert "CancelledError" not in p.stderr
    rows = summary(out)
    assert list(rows) == ["a-good", "b-no-column", "c-not-a-number", "d-good"]  # the files' order
    for good in ("a-good", "d-good"):
        assert rows[good]["error"] == "" and float(rows[good]["k1"]) > 0
        assert (out / f"{good}.toml").exists()
    assert "no column 'y_capsensor_um'" in rows["b-no-column"]["error"]
    assert "could not convert string to float: 'oops'" in rows["c-not-a-number"]["error"]
    assert not (out / "b-no-column.toml").exists() and not (out / "c-not-a-number.toml").exists()
    assert "fitted 2 of 4 records" in p.stdout
    assert "b-no-column: " in p.stderr and "c-not-a-number: " in p.stderr


def test_a_fit_error_of_every_record_is_reported(records, tmp_path):
    """An option hyst.fit refuses fails each task on its worker, and each is reported."""
    pytest.importorskip("dask.distributed")
    out = tmp_path / "models"
    p = subprocess.run(
        [sys.executable, str(SCRIPT), str(records[0]), str(records[3]), "--input", INPUT, "--output",
         OUTPUT, "--workers", "1", "--out", str(out), "--", "--output_shaping", "cubic"],
        capture_output=True, text=True, timeout=600,
    )
    assert p.returncode == 1, p.stdout + p.stderr
    rows = summary(out)
    assert len(rows) == 2 and all("output_shaping" in r["error"] for r in rows.values())
