"""Shared fixtures of the Python binding's tests: the repository, the `hyst` CLI built from
the same sources (for bit-for-bit comparisons) and the bundled piezo record."""

import csv
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
PIEZO = ROOT / "data" / "piezo-sine" / "piezo_sine_1hz.csv"


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def hyst_bin() -> Path:
    """The CLI of this checkout: $HYST_BIN, else target/release/hyst (scripts/test-python
    builds it). A missing binary is an error, not a skip."""
    path = Path(os.environ.get("HYST_BIN", ROOT / "target" / "release" / "hyst"))
    if not path.exists():
        pytest.fail(f"{path}: the hyst CLI is missing; run `cargo build --release -p hyst-cli`")
    return path


@pytest.fixture(scope="session")
def cli(hyst_bin):
    """Runs the CLI and returns its completed process (check=True)."""

    def run(*args, **kwargs):
        return subprocess.run(
            [str(hyst_bin), *map(str, args)], check=True, capture_output=True, text=True, **kwargs
        )

    return run


@pytest.fixture(scope="session")
def piezo():
    """(u, y) of the bundled piezo record, parsed from the CSV text as the CLI parses it."""
    with open(PIEZO, newline="") as f:
        rows = list(csv.DictReader(f))
    u = np.array([float(r["u_actuator_V"]) for r in rows])
    y = np.array([float(r["y_capsensor_um"]) for r in rows])
    return u, y


@pytest.fixture(scope="session")
def piezo_path() -> Path:
    return PIEZO


def read_csv(path):
    """A CSV written by `hyst run` as {column: array}."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names = rows[0]
    data = np.array([[float(v) for v in r] for r in rows[1:]])
    return {n: data[:, i] for i, n in enumerate(names)}


def computed(path, k=1):
    """The k-th last column of a CSV written by `hyst run`: its computed columns come after
    every column of its input (docs/formats.md), the last one first."""
    table = read_csv(path)
    return table[list(table)[-k]]


def interrupted(call):
    """Runs `call()` (a run of a second or less that checks for signals between chunks) while
    SIGINT arrives, and checks that it raises KeyboardInterrupt.

    The signal is sent from 20 ms in and again every 20 ms until the call returns, so that a
    loaded machine that wakes the sending thread late, or a fast one that runs ahead, still
    interrupts the run; Python's handler raises KeyboardInterrupt for the first signal only (as
    Ctrl-C's does), and the ones sent after it are ignored until the usual handler is back."""
    import signal
    import threading

    raised = threading.Event()

    def once(signum, frame):
        if not raised.is_set():
            raised.set()
            raise KeyboardInterrupt

    done = threading.Event()

    def send():
        while not done.wait(0.02):
            os.kill(os.getpid(), signal.SIGINT)

    usual = signal.signal(signal.SIGINT, once)
    sender = threading.Thread(target=send, daemon=True)
    sender.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            call()
    finally:
        done.set()
        sender.join()
        signal.signal(signal.SIGINT, usual)
