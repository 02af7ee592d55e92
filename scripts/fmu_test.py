#!/usr/bin/env python3
"""The FMUs that `hyst fmu` makes, run through FMPy and compared with `hyst run`.

Run by scripts/test-fmu with the Python of its virtual environment (FMPy installed):

    fmu_test.py --hyst target/release/hyst --dir TMP --k1 0.2 --k2 8 \
        --operator op.fmu --inverse inv.fmu --model piezo.toml \
        --model-direct piezo.fmu --model-inverse piezo-inverse.fmu

For every FMU: FMPy's validate_fmu finds no problem; FMU2Slave stepped sample by sample (set x,
get y, doStep) over a signal with many reversals gives y equal to `hyst run` on the same signal
within 1e-12 relative (and says whether it is bit-identical), and y read again after doStep is
the same output; get/set FMU state and
serialise/deserialise round trips reproduce the outputs; two instances at once stay independent;
fmi2Reset starts over; a non-finite x is refused and logged; simulate_fmu runs it with a
structured-array input. For the operator FMUs: k1, k2 set before initialisation change the result
as `hyst run --k1 .. --k2 ..` predicts, and are refused (logged) when invalid or set too late.

Prints one line per check and a final `fmu: N passed, M failed`; exits 1 on any failure.
"""

import argparse
import csv
import math
import os
import random
import subprocess
import sys
import traceback
from ctypes import byref

import numpy as np
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    defaultCallbacks,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)
from fmpy.logging import addLoggerProxy
from fmpy.validation import validate_fmu

RELATIVE_TOLERANCE = 1e-12
VR_X, VR_Y, VR_K1, VR_K2 = 0, 1, 2, 3

passed = 0
failed = 0


def check(name, ok, detail=""):
    """Counts and prints one check."""
    global passed, failed
    if ok:
        passed += 1
    else:
        failed += 1
    print(f"   {'ok  ' if ok else 'FAIL'} {name}{': ' + detail if detail else ''}", flush=True)
    return ok


def compare(name, got, want):
    """Checks two output sequences agree within RELATIVE_TOLERANCE; reports the largest relative
    difference and whether they are bit-identical."""
    got = np.asarray(got, dtype=np.float64)
    want = np.asarray(want, dtype=np.float64)
    if got.shape != want.shape:
        return check(name, False, f"{got.size} outputs, expected {want.size}")
    identical = np.array_equal(got.view(np.uint64), want.view(np.uint64))
    scale = np.maximum(np.maximum(np.abs(got), np.abs(want)), np.finfo(np.float64).tiny)
    diff = np.abs(got - want)
    rel = np.where(diff == 0.0, 0.0, diff / scale)
    worst = float(rel.max()) if rel.size else 0.0
    ok = bool(np.all(np.isfinite(got))) and worst <= RELATIVE_TOLERANCE
    how = "bit-identical" if identical else f"max relative difference {worst:.3g}"
    return check(name, ok, f"{got.size} samples, {how}")


def rust(v):
    """A number as Rust's `{}` (and so the core's error messages) prints it: -1, 0.5, inf."""
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    if v == int(v) and abs(v) < 1e16:
        return str(int(v))
    return repr(v)


def raises(function, *args):
    """True if the FMI call fails (FMPy raises FMICallException for fmi2Error and worse)."""
    try:
        function(*args)
    except FMICallException:
        return True
    return False


# ---------------------------------------------------------------------------------------------
# Signals and the reference (`hyst run`)


def reversals(n, lo, hi, seed):
    """A signal in [lo, hi] with many reversals: a sine under a slowly varying envelope, with
    jitter (minor loops), held samples and exact repeats."""
    rng = random.Random(seed)
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    xs = []
    for k in range(n):
        envelope = 0.25 + 0.7 * abs(math.sin(2 * math.pi * k / 1700))
        x = envelope * math.sin(2 * math.pi * k / 211) + rng.uniform(-0.04, 0.04)
        if xs and rng.random() < 0.05:
            xs.append(xs[-1])  # a held sample
            continue
        xs.append(mid + half * max(-1.0, min(1.0, x)))
    return xs


def count_reversals(xs):
    d = np.sign(np.diff(xs))
    d = d[d != 0]
    return int(np.sum(d[1:] != d[:-1]))


class Hyst:
    """The release `hyst` CLI: the reference the FMUs are compared with."""

    def __init__(self, exe, workdir):
        self.exe = exe
        self.dir = workdir
        self.runs = 0

    def run(self, args, xs):
        """`hyst run ARGS --column x IN -o OUT` on xs; returns the column it computes (the last:
        hyst run passes the input's x through first)."""
        self.runs += 1
        src = os.path.join(self.dir, f"run{self.runs}-in.csv")
        dst = os.path.join(self.dir, f"run{self.runs}-out.csv")
        with open(src, "w") as f:
            f.write("x\n")
            f.writelines(f"{float(x)!r}\n" for x in xs)
        subprocess.run([self.exe, "run", *args, "--column", "x", src, "-o", dst], check=True)
        with open(dst, newline="") as f:
            rows = list(csv.reader(f))[1:]
        xs_back = [float(r[0]) for r in rows]
        if xs_back != [float(x) for x in xs]:
            raise RuntimeError("hyst run did not read back the signal exactly")
        return [float(r[-1]) for r in rows]


# ---------------------------------------------------------------------------------------------
# FMU instances


class Fmu:
    """An extracted FMU; makes instances that log into a list."""

    def __init__(self, path, name):
        self.path = path
        self.name = name
        self.md = read_model_description(path)
        self.dir = extract(path)
        self.count = 0

    def instance(self, params=None, params_in_init=None):
        """An initialised FMU2Slave; `params` (dict vr -> value) are set in the state
        Instantiated, `params_in_init` in InitializationMode."""
        s = self.instantiate()
        s.setupExperiment(startTime=0.0)
        if params:
            s.setReal(list(params), list(params.values()))
        s.enterInitializationMode()
        if params_in_init:
            s.setReal(list(params_in_init), list(params_in_init.values()))
        s.exitInitializationMode()
        return s

    def instantiate(self):
        self.count += 1
        s = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self.dir,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=f"{self.name}-{self.count}",
        )
        s.log = []

        def logger(_env, _instance, status, category, message):
            s.log.append((status, (category or b"").decode(), (message or b"").decode()))

        callbacks = fmi2CallbackFunctions()
        callbacks.logger = fmi2CallbackLoggerTYPE(logger)
        callbacks.allocateMemory = defaultCallbacks.allocateMemory
        callbacks.freeMemory = defaultCallbacks.freeMemory
        # FMPy's native proxy formats printf-style messages before they reach Python.
        addLoggerProxy(byref(callbacks))
        s.keep_alive = (logger, callbacks)
        s.instantiate(callbacks=callbacks, loggingOn=True)
        return s


def step(s, xs, t=0.0, sizes=None):
    """Per sample: setReal(x), getReal(y), doStep. Returns the ys (and the end time)."""
    ys = []
    for k, x in enumerate(xs):
        s.setReal([VR_X], [float(x)])
        ys.append(s.getReal([VR_Y])[0])
        h = 1.0 if sizes is None else sizes[k % len(sizes)]
        s.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        t += h
    return ys


def close(s):
    s.terminate()
    s.freeInstance()


# ---------------------------------------------------------------------------------------------
# The checks


def check_fmu(fmu, hyst, run_args, xs, others):
    """Every check that applies to any FMU. `run_args`: `hyst run` arguments that compute the
    same thing; `xs`: its input signal; `others`: a second signal."""
    n = len(xs)
    want = hyst.run(run_args, xs)

    problems = validate_fmu(fmu.path)
    check(
        f"{fmu.name}: validate_fmu",
        problems == [],
        "no problems" if not problems else str(problems),
    )

    s = fmu.instance()
    compare(f"{fmu.name}: FMU2Slave == hyst run {' '.join(run_args)}", step(s, xs), want)
    close(s)

    # fmuCheck's stepping: set x, read y, doStep, read y again. Both reads are the output at
    # the communication point: the step commits the sample once and y keeps its output.
    s = fmu.instance()
    after = []
    for k, x in enumerate(xs):
        s.setReal([VR_X], [float(x)])
        s.getReal([VR_Y])
        s.doStep(currentCommunicationPoint=float(k), communicationStepSize=1.0)
        after.append(s.getReal([VR_Y])[0])
    compare(f"{fmu.name}: y read after doStep == y read before it (== hyst run)", after, want)
    close(s)

    # Rate independence: the communication step sizes do not matter (zero included).
    s = fmu.instance()
    got = step(s, xs, sizes=[1e-6, 0.5, 0.0, 3.0, 1e-3])
    compare(f"{fmu.name}: variable step sizes (0 included) give the same y", got, want)
    close(s)

    # y depends on x directly and does not move the memory until doStep: probing other values
    # before the real one changes nothing.
    s = fmu.instance()
    got = []
    for k, x in enumerate(xs):
        for probe in (others[k], others[(k * 7) % n]):
            s.setReal([VR_X], [probe])
            s.getReal([VR_Y])
        s.setReal([VR_X], [x])
        got.append(s.getReal([VR_Y])[0])
        s.doStep(currentCommunicationPoint=float(k), communicationStepSize=1.0)
    compare(f"{fmu.name}: getReal with other x before the step does not move the memory", got, want)
    close(s)

    # getFMUstate / setFMUstate: roll back to the middle and redo the second half.
    half = n // 2
    s = fmu.instance()
    first = step(s, xs[:half])
    state = s.getFMUstate()
    second = step(s, xs[half:], t=float(half))
    step(s, others[: n // 3], t=float(n))  # wander off
    s.setFMUstate(state)
    again = step(s, xs[half:], t=float(half))
    compare(f"{fmu.name}: get/setFMUstate round trip reproduces y", first + again, want)
    check(f"{fmu.name}: the rolled-back run is bit-identical to the first", again == second)
    s.freeFMUstate(state)

    # serialize / deSerialize: into the same instance and into a fresh one.
    s2 = fmu.instance()
    step(s2, xs[:half])
    state = s2.getFMUstate()
    blob = s2.serializeFMUstate(state)
    s2.freeFMUstate(state)
    step(s2, others[:500], t=float(half))
    restored = s2.deSerializeFMUstate(blob)
    s2.setFMUstate(restored)
    again = step(s2, xs[half:], t=float(half))
    s2.freeFMUstate(restored)
    compare(
        f"{fmu.name}: serialize/deSerializeFMUstate round trip ({len(blob)} bytes)", again, second
    )
    fresh = fmu.instance()
    restored = fresh.deSerializeFMUstate(blob)
    fresh.setFMUstate(restored)
    fresh.freeFMUstate(restored)
    compare(
        f"{fmu.name}: a serialised state restored into a fresh instance",
        step(fresh, xs[half:]),
        second,
    )
    close(fresh)

    # Garbage is refused, not accepted.
    bad = {
        "truncated": blob[: len(blob) // 2],
        "empty": b"",
        "one byte longer": blob + b"\0",
        "first byte changed": bytes([blob[0] ^ 0xFF]) + blob[1:],
        "non-finite values": blob[:-8] + np.float64(np.nan).tobytes(),
        "all bits flipped": bytes(b ^ 0xFF for b in blob),
    }
    refused = []
    for what, junk in bad.items():
        try:
            st = s2.deSerializeFMUstate(junk)
        except FMICallException:
            refused.append(what)
            continue
        # Accepted: it must at least be a state this FMU can run from.
        s2.setFMUstate(st)
        s2.freeFMUstate(st)
    check(
        f"{fmu.name}: deSerializeFMUstate refuses truncated, empty, over-long and altered bytes",
        {"truncated", "empty", "one byte longer", "first byte changed"} <= set(refused),
        f"refused: {', '.join(refused)}",
    )
    close(s2)

    # Two instances at once, interleaved sample by sample, on different signals.
    a, b = fmu.instance(), fmu.instance()
    ya, yb = [], []
    for k in range(n):
        a.setReal([VR_X], [xs[k]])
        b.setReal([VR_X], [others[k]])
        yb.append(b.getReal([VR_Y])[0])
        ya.append(a.getReal([VR_Y])[0])
        b.doStep(currentCommunicationPoint=float(k), communicationStepSize=1.0)
        a.doStep(currentCommunicationPoint=float(k), communicationStepSize=1.0)
    compare(f"{fmu.name}: two instances at once, first", ya, want)
    compare(f"{fmu.name}: two instances at once, second", yb, hyst.run(run_args, others))
    close(a)
    close(b)

    # fmi2Reset: back to the state after instantiation.
    s = fmu.instance()
    step(s, others[:700])
    s.reset()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    compare(f"{fmu.name}: after fmi2Reset the FMU starts over", step(s, xs), want)

    # A non-finite sample is refused (fmi2Error, logged) and changes nothing.
    s.reset()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    first = step(s, xs[:half])
    state = s.getFMUstate()
    s.log.clear()
    s.setReal([VR_X], [float("nan")])
    refused = raises(s.getReal, [VR_Y]) or raises(s.doStep, float(half), 1.0)
    check(f"{fmu.name}: x = NaN is refused with fmi2Error", refused)
    check(f"{fmu.name}: ... and logged", len(s.log) > 0, s.log[0][2] if s.log else "no log message")
    s.setFMUstate(state)  # allowed after fmi2Error
    s.freeFMUstate(state)
    compare(
        f"{fmu.name}: the run goes on after the refusal (state restored)",
        first + step(s, xs[half:], t=float(half)),
        want,
    )
    close(s)

    # FMPy's own master: simulate_fmu with the input as a structured array (time, x). It sets x
    # at t_k and records y after initialisation and after each step, at t_k+1: y(t_0) = y_0 and
    # y(t_k+1) = y_k (the output for x_0..x_k, which y keeps after the step).
    signal = np.array(
        list(zip(np.arange(n, dtype=np.float64), xs)),
        dtype=[("time", np.float64), ("x", np.float64)],
    )
    result = simulate_fmu(
        fmu.path,
        start_time=0.0,
        stop_time=float(n - 1),
        output_interval=1.0,
        input=signal,
        output=["x", "y"],
    )
    recorded_x = np.concatenate([xs[:1], xs[:-1]])
    check(f"{fmu.name}: simulate_fmu sets x as given", np.array_equal(result["x"], recorded_x))
    compare(
        f"{fmu.name}: simulate_fmu == hyst run", result["y"], np.concatenate([want[:1], want[:-1]])
    )
    return want


def check_parameters(fmu, hyst, inverse, k1, k2, xs):
    """k1, k2 of an operator FMU: start values, set before initialisation, refused later or when
    invalid."""
    direction = ["--inverse"] if inverse else []
    starts = {v.name: float(v.start) for v in fmu.md.modelVariables if v.name in ("k1", "k2")}
    check(
        f"{fmu.name}: k1, k2 start values are those given to hyst fmu",
        starts == {"k1": k1, "k2": k2},
        str(starts),
    )

    for nk1, nk2, where in [(0.5, 3.0, "instantiated"), (0.05, 40.0, "initialization mode")]:
        want = hyst.run(["--k1", repr(nk1), "--k2", repr(nk2), *direction], xs)
        params = {VR_K1: nk1, VR_K2: nk2}
        if where == "instantiated":
            s = fmu.instance(params=params)
        else:
            s = fmu.instance(params_in_init=params)
        check(
            f"{fmu.name}: getReal(k1, k2) after setting them ({where})",
            s.getReal([VR_K1, VR_K2]) == [nk1, nk2],
        )
        compare(
            f"{fmu.name}: k1 = {nk1}, k2 = {nk2} set in {where} == hyst run --k1 {nk1} --k2 {nk2}",
            step(s, xs),
            want,
        )
        # After initialisation the parameters are fixed.
        s.log.clear()
        late = raises(s.setReal, [VR_K1], [1.0])
        check(
            f"{fmu.name}: setting k1 after initialisation is fmi2Error",
            late,
            s.log[0][2] if s.log else "",
        )
        close(s)

    # Invalid values: refused at fmi2ExitInitializationMode (or when set), naming the parameter.
    for vr, name, value in [(VR_K1, "k1", -1.0), (VR_K2, "k2", 0.0), (VR_K1, "k1", float("inf"))]:
        s = fmu.instantiate()
        s.setupExperiment(startTime=0.0)
        refused = raises(s.setReal, [vr], [value])
        if not refused:
            s.enterInitializationMode()
            refused = raises(s.exitInitializationMode)
        message = " | ".join(m for _, _, m in s.log)
        check(
            f"{fmu.name}: {name} = {rust(value)} is refused and the log names it",
            refused and f"{name} = {rust(value)}" in message,
            message or "no log message",
        )
        s.freeInstance()

    # fmi2Reset restores the start values.
    s = fmu.instance(params={VR_K1: 0.5, VR_K2: 3.0})
    s.reset()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    check(
        f"{fmu.name}: fmi2Reset restores the parameters' start values",
        s.getReal([VR_K1, VR_K2]) == [k1, k2],
    )
    s.freeInstance()

    # simulate_fmu with start values for the parameters.
    n = len(xs)
    signal = np.array(
        list(zip(np.arange(n, dtype=np.float64), xs)),
        dtype=[("time", np.float64), ("x", np.float64)],
    )
    result = simulate_fmu(
        fmu.path,
        stop_time=float(n - 1),
        output_interval=1.0,
        input=signal,
        start_values={"k1": 0.5, "k2": 3.0},
        output=["y"],
    )
    want = hyst.run(["--k1", "0.5", "--k2", "3.0", *direction], xs)
    compare(
        f"{fmu.name}: simulate_fmu with start_values k1 = 0.5, k2 = 3", result["y"][1:], want[:-1]
    )


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--hyst", required=True)
    p.add_argument("--dir", required=True, help="a directory for the CSV files")
    p.add_argument("--k1", type=float, required=True, help="k1 the operator FMUs were made with")
    p.add_argument("--k2", type=float, required=True)
    p.add_argument("--operator", required=True, help="hyst fmu --k1 K1 --k2 K2")
    p.add_argument("--inverse", required=True, help="hyst fmu --k1 K1 --k2 K2 --inverse")
    p.add_argument("--model", required=True, help="the model file")
    p.add_argument("--model-direct", required=True, help="hyst fmu --model MODEL")
    p.add_argument("--model-inverse", required=True, help="hyst fmu --model MODEL --inverse")
    p.add_argument("--u-range", type=float, nargs=2, required=True, help="the model's input range")
    a = p.parse_args()
    hyst = Hyst(a.hyst, a.dir)
    n = 4000

    xs = reversals(n, -1.0, 1.0, seed=1)
    others = reversals(n, -0.7, 1.3, seed=2)
    print(f"   signal: {n} samples, {count_reversals(xs)} reversals", flush=True)
    cases = []
    try:
        op = Fmu(a.operator, "operator")
        check_fmu(op, hyst, ["--k1", repr(a.k1), "--k2", repr(a.k2)], xs, others)
        check_parameters(op, hyst, False, a.k1, a.k2, xs)
        cases.append("operator")
    except Exception:
        check("operator FMU: no exception", False, traceback.format_exc())
    try:
        inv = Fmu(a.inverse, "inverse")
        check_fmu(inv, hyst, ["--k1", repr(a.k1), "--k2", repr(a.k2), "--inverse"], xs, others)
        check_parameters(inv, hyst, True, a.k1, a.k2, xs)
        cases.append("inverse")
    except Exception:
        check("inverse FMU: no exception", False, traceback.format_exc())

    # The fitted model: a voltage signal over the data's range, and the model's own output on it
    # as the desired output for the inverse (reachable by construction).
    lo, hi = a.u_range
    us = reversals(n, lo, hi, seed=3)
    us_other = reversals(n, lo + 0.1 * (hi - lo), hi, seed=4)
    try:
        direct = Fmu(a.model_direct, "model")
        check_fmu(direct, hyst, ["--model", a.model], us, us_other)
        cases.append("model")
    except Exception:
        check("model FMU: no exception", False, traceback.format_exc())
    try:
        desired = hyst.run(["--model", a.model], us)
        desired_other = hyst.run(["--model", a.model], us_other)
        inverse = Fmu(a.model_inverse, "model-inverse")
        commands = check_fmu(inverse, hyst, ["--model", a.model, "--inverse"], desired, desired_other)
        # The exact inverse undoes the model: its commands reproduce the voltages.
        err = float(np.max(np.abs(np.asarray(commands) - np.asarray(us))))
        check(
            "model-inverse: the inverse's commands reproduce the model's input",
            err <= 1e-9 * (hi - lo),
            f"max |command - u| = {err:.3g} (span {hi - lo:.3g})",
        )
        cases.append("model-inverse")
    except Exception:
        check("model-inverse FMU: no exception", False, traceback.format_exc())

    print(f"fmu: {passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
