"""Models with dynamics or a rate term from Python: ``hyst.fit(x, y, time=...,
dynamics=N, rate_term="viscous")``, ``Model.process(x, time=...)`` and Lemma 5.1's compensator
``Model.compensate(...)``, bit for bit as ``hyst run --model M [--inverse]`` on the same CSV
file, and the refusals of every entry point that would run such a model without time."""

import copy
import pickle

import numpy as np
import pytest

import hyst
from conftest import computed

H = 1e-3  # sample period (s)
N = 4000  # samples
TAU = 0.05  # the truth's plant: TAU v' + v = x (s)
C = 0.05  # the truth's rate term c·v' (output units · s / input unit)


def _command(t):
    """A multisine command about 0.2 whose envelope rises over 0.3 s (the plant starts at rest)."""
    freqs = np.array([0.4, 1.1, 2.3, 4.7])
    phases = np.arange(1, 5)
    ramp = np.minimum(t / 0.3, 1.0)
    return 0.2 + 0.5 * ramp * np.sin(2 * np.pi * np.multiply.outer(t, freqs) + phases).sum(-1)


def _plant(t):
    """The command x(t) and the plant output v of TAU v' + v = x, sampled at t from rest at x(0):
    RK4 with 20 steps per sample on the continuous command (not the model's discretisation)."""
    steps = 20
    dt = H / steps
    fine = np.arange((N - 1) * steps + 1) * dt
    at, mid = _command(fine), _command(fine[:-1] + dt / 2)
    x = float(at[0])
    v = np.empty(N)
    v[0] = x
    for i in range(1, N):
        for k in range((i - 1) * steps, i * steps):
            a, m, b = at[k], mid[k], at[k + 1]
            k1 = (a - x) / TAU
            k2 = (m - x - dt / 2 * k1) / TAU
            k3 = (m - x - dt / 2 * k2) / TAU
            k4 = (b - x - dt * k3) / TAU
            x += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        v[i] = x
    return _command(t), v


@pytest.fixture(scope="module")
def record():
    """(t, x, y, y_rate): a first-order plant before y = 3 H(0.15, 6)[v] + 1 (the binding's own
    operator, started on the line), with 0.1 % noise; y_rate adds C·v' (backward difference)."""
    t = np.arange(N) * H
    x, v = _plant(t)
    z = hyst.Hysteresis(0.15, 6.0).process(v)
    noise = 1e-3 * np.random.default_rng(5).standard_normal(N)
    y = 3.0 * z + 1.0 + noise
    rate = np.r_[0.0, np.diff(v)] / H
    return t, x, y, y + C * rate


@pytest.fixture(scope="module")
def fitted(record):
    t, x, y, _ = record
    # The truth's command is continuous: linear between samples is its hold.
    return hyst.fit(x, y, time=t, dynamics=1, initial_state="line", hold="foh")


def write_csv(path, columns):
    """A CSV file of `columns` ({name: array}) in the shortest round-trip decimals, which the
    CLI parses to the same float64 values."""
    lines = [",".join(columns)]
    lines += [",".join(repr(float(v)) for v in row) for row in zip(*columns.values())]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_fit_recovers_the_plant(fitted, record):
    t, x, y, _ = record
    m = fitted.model
    a1 = m.dynamics["a"][0]
    assert abs(a1 / TAU - 1) < 0.02, a1
    assert m.dynamics["b"] == 1.0 and m.dynamics["identified"] == [True]
    assert fitted.params["dynamics.a1"] == a1 and fitted.std_errors["dynamics.a1"] > 0
    assert m.rate is None
    # At the noise level (0.1 % of 3 against a span of about 6); the static fit is far off.
    assert fitted.rms_percent < 0.03
    assert hyst.fit(x, y, initial_state="line").rms_percent > 50 * fitted.rms_percent
    assert "version = 4" in m.to_toml() and "[dynamics]" in m.to_toml()
    # A static model has neither.
    static = hyst.fit(x, y)
    assert static.model.dynamics is None and static.model.rate is None


def test_process_is_hyst_run(fitted, record, cli, tmp_path):
    t, x, _, _ = record
    path = tmp_path / "m.toml"
    fitted.model.save(path)
    data = write_csv(tmp_path / "x.csv", {"t": t, "x": x})
    out = tmp_path / "y.csv"
    cli("run", "--model", path, data, "-o", out)
    expected = computed(out)
    y = fitted.model.process(x, time=t)
    assert y.dtype == np.float64 and np.array_equal(y, expected)
    # The period itself gives the same; so do the loaded and the unpickled model; each call is
    # one record from rest, so a second call repeats the first.
    period = (t[-1] - t[0]) / (N - 1)
    loaded = hyst.load_model(path)
    assert np.array_equal(loaded.process(x, period=period), expected)
    again = pickle.loads(pickle.dumps(fitted.model))
    assert again.dynamics == fitted.model.dynamics
    assert np.array_equal(again.process(x, time=t), expected)
    assert np.array_equal(again.process(x, time=t), expected)
    # float32 stays float32.
    y32 = loaded.process(x.astype(np.float32), time=t)
    assert y32.dtype == np.float32 and np.max(np.abs(y32 - expected)) < 1e-4 * np.ptp(expected)
    assert loaded.process(np.empty(0), time=np.empty(0)).size == 0


def test_compensate_is_hyst_run_inverse(fitted, record, cli, tmp_path):
    t, _, y, _ = record
    path = tmp_path / "m.toml"
    fitted.model.save(path)
    m = hyst.load_model(path)
    # A desired output from rest, with its exact derivative.
    f = 1.3
    desired = 1.0 + 3.0 * np.sin(np.pi * f * t) ** 2
    d1 = 3.0 * np.pi * f * np.sin(2 * np.pi * f * t)

    given = write_csv(tmp_path / "d.csv", {"t": t, "y": desired, "y_d1": d1})
    out = tmp_path / "u.csv"
    cli("run", "--model", path, "--inverse", given, "-o", out)
    command = m.compensate(desired, time=t, derivatives=d1)
    assert np.array_equal(command, computed(out))
    assert np.array_equal(m.compensate(desired, time=t, derivatives=d1[:, None]), command)
    # The command makes the model give the desired output, to the discretisation's accuracy.
    assert np.max(np.abs(m.process(command, time=t) - desired)) < 2e-4 * np.ptp(desired)

    plain = write_csv(tmp_path / "r.csv", {"t": t, "y": desired})
    out = tmp_path / "uf.csv"
    cli("run", "--model", path, "--inverse", "--prefilter-hz", "20", plain, "-o", out)
    # With the prefilter: the commands and the prefiltered reference they track, the CLI's
    # last two columns (the command, then y_filtered).
    filtered, y_filtered = m.compensate(desired, time=t, prefilter_hz=20.0)
    assert np.array_equal(filtered, computed(out, 2))
    assert np.array_equal(y_filtered, computed(out, 1))
    assert filtered.shape == y_filtered.shape == desired.shape
    assert 0 < np.max(np.abs(y_filtered - desired)) < 0.1 * np.ptp(desired)
    again, y_again = m.compensate(desired, period=1e-3, prefilter_hz=20.0)
    assert np.array_equal(again, filtered) and np.array_equal(y_again, y_filtered)
    f32, y32 = m.compensate(desired.astype(np.float32), time=t, prefilter_hz=20.0)
    assert f32.dtype == y32.dtype == np.float32


def test_rate_term(record, cli, tmp_path):
    t, x, _, y_rate = record
    r = hyst.fit(x, y_rate, time=t, dynamics=1, rate_term="viscous", initial_state="line", hold="foh")
    m = r.model
    assert abs(m.rate["c"] / C - 1) < 0.02 and m.rate["c_std_error"] > 0
    assert r.params["rate.c"] == m.rate["c"]
    assert abs(m.dynamics["a"][0] / TAU - 1) < 0.02
    path = tmp_path / "m.toml"
    m.save(path)
    out = tmp_path / "y.csv"
    cli("run", "--model", path, write_csv(tmp_path / "x.csv", {"t": t, "x": x}), "-o", out)
    assert np.array_equal(m.process(x, time=t), computed(out))
    # Its output depends on the rate of the command: no compensator.
    with pytest.raises(ValueError, match="rate term has no inverse"):
        m.compensate(y_rate, time=t, prefilter_hz=5.0)
    with pytest.raises(ValueError, match="a rate term: it runs on timed records only"):
        m.inverse()


def test_fit_errors_name_the_option_and_the_sample(record):
    t, x, y, _ = record
    with pytest.raises(ValueError, match=r"^time: a fit with dynamics or rate_term needs"):
        hyst.fit(x, y, dynamics=1)
    with pytest.raises(ValueError, match=r"^time: a fit with dynamics or rate_term needs"):
        hyst.fit(x, y, rate_term="viscous")
    with pytest.raises(ValueError, match=r"^time: time stamps apply to a fit with dynamics"):
        hyst.fit(x, y, time=t)
    with pytest.raises(ValueError, match=r"dynamics = 5: the plant order must be 1 to 4"):
        hyst.fit(x, y, time=t, dynamics=5)
    with pytest.raises(ValueError, match=r"dynamics = 0"):
        hyst.fit(x, y, time=t, dynamics=0)
    with pytest.raises(ValueError, match=r'rate_term = "coulomb": invalid value; possible values: viscous'):
        hyst.fit(x, y, time=t, rate_term="coulomb")
    with pytest.raises(ValueError, match="time has 3999 samples but x has 4000"):
        hyst.fit(x, y, time=t[:-1], dynamics=1)
    with pytest.raises(ValueError, match="fit_from_start=True and estimate_initial_states=True"):
        hyst.fit(x, y, time=t, dynamics=1, estimate_initial_states=True, fit_from_start=True)
    repeated = t.copy()
    repeated[100] = repeated[99]
    with pytest.raises(ValueError, match=r"^time\[100\] = 0\.099: time stamp 0\.099 repeats the one before"):
        hyst.fit(x, y, time=repeated, dynamics=1)
    # Unix-epoch seconds at 1 MHz: 64-bit floats cannot resolve the steps.
    epoch = 1.7e9 + np.arange(N) * 1e-6
    with pytest.raises(ValueError, match=r"^time\[0\] = .*: .* apart in 64-bit floats"):
        hyst.fit(x, y, time=epoch, dynamics=1)
    with pytest.raises(ValueError, match=r"hold: the hold is how the plant"):
        hyst.fit(x, y, time=t, rate_term="viscous", hold="zoh")
    with pytest.raises(ValueError, match=r"^time\[300\] = NaN: the time stamp is not a finite number"):
        hyst.fit(x, y, time=np.where(np.arange(N) == 300, np.nan, t), dynamics=1)
    # With records, the record is named too.
    with pytest.raises(ValueError, match=r"^time\[100\] = 0\.099 \(record 0\): time stamp"):
        hyst.fit(x, y, time=repeated, dynamics=1, record=np.repeat([0, 1], N // 2))


def test_timed_model_needs_time_and_static_model_refuses_it(fitted, record):
    t, x, y, _ = record
    m = fitted.model
    with pytest.raises(ValueError, match=r"has dynamics of order 1: it needs the record's time stamps time"):
        m.process(x)
    with pytest.raises(ValueError, match="time and period: give one"):
        m.process(x, time=t, period=H)
    with pytest.raises(ValueError, match="^period = -0.001: expected a finite, positive sample period"):
        m.process(x, period=-H)
    with pytest.raises(ValueError, match="time has 3999 samples but the record has 4000"):
        m.process(x, time=t[:-1])
    with pytest.raises(ValueError, match=r"^time\[2\] = 0\.001: time stamp 0\.001 repeats"):
        m.process(x[:4], time=np.array([0.0, 1e-3, 1e-3, 2e-3]))
    with pytest.raises(ValueError, match="^derivatives: the model <fit> has dynamics of order 1: it runs without derivatives"):
        m.process(x, t)  # the time stamps passed where derivatives go
    with pytest.raises(ValueError, match=r"^x\[3\] = NaN: input sample NaN is not finite"):
        m.process(np.where(np.arange(N) == 3, np.nan, x), time=t)

    static = hyst.fit(x, y).model
    before = static.process(x)
    for kwargs, name in [({"time": t}, "time"), ({"period": H}, "period")]:
        with pytest.raises(ValueError, match=f"^{name} applies to a model with dynamics or a rate term"):
            static.process(x, **kwargs)
    # Refused without effect: the static model runs on as before.
    static.reset()
    assert np.array_equal(static.process(x), before)
    with pytest.raises(ValueError, match="the model has no dynamics: its compensator is the exact inverse"):
        static.compensate(y, time=t, prefilter_hz=5.0)


def test_entry_points_without_time_refuse_a_timed_model(fitted, record):
    t, x, y, _ = record
    m = fitted.model
    refusals = [
        (m.inverse, "Model.inverse"),
        (lambda: m.inverse(saturate=True), "Model.inverse"),
        (lambda: m.step(0.2), "Model.step"),
        (lambda: hyst._hyst._model_from_toml(m.to_toml(), True), "Model.inverse"),
    ]
    for call, what in refusals:
        with pytest.raises(ValueError, match=rf"the model has dynamics of order 1: it runs on timed records only .*not for {what}"):
            call()
    # hyst.Compensator takes the model's own plant; another plant goes with its hysteresis part.
    with pytest.raises(ValueError, match=r"^b, a: the model has its own plant \(dynamics of order 1: b = 1, a = \[0\.0"):
        hyst.Compensator(m, 1.0, [TAU])
    assert hyst.Compensator(m.hysteresis, 1.0, [TAU]).a == [TAU]
    # The compensator's own checks and arguments.
    desired = y[:100]
    with pytest.raises(ValueError, match=r"needs the desired output's first 1 time derivatives: give derivatives"):
        m.compensate(desired, time=t[:100])
    with pytest.raises(ValueError, match="derivatives and prefilter_hz: give one"):
        m.compensate(desired, time=t[:100], derivatives=np.zeros(100), prefilter_hz=5.0)
    with pytest.raises(ValueError, match=r"derivatives: the plant has order 1: .* got shape \(100, 2\)"):
        m.compensate(desired, time=t[:100], derivatives=np.zeros((100, 2)))
    with pytest.raises(ValueError, match=r"^derivatives\[7\] = inf: not a finite number"):
        m.compensate(desired, time=t[:100], derivatives=np.where(np.arange(100) == 7, np.inf, 0.0))
    with pytest.raises(ValueError, match="^prefilter_hz = 0: the bandwidth must be"):
        m.compensate(desired, time=t[:100], prefilter_hz=0.0)
    for bad, shown in [(float("nan"), "NaN"), (-1.0, "-1"), (float("inf"), "inf")]:
        with pytest.raises(ValueError, match=f"^prefilter_hz = {shown}: the bandwidth must be"):
            m.compensate(desired, time=t[:100], prefilter_hz=bad)
    # At most 1/20 of the Nyquist frequency of the sample period (25 Hz at 1 kHz), as hyst run.
    assert np.all(np.isfinite(m.compensate(desired, time=t[:100], prefilter_hz=24.9)))
    for hz, shown in [(26.0, "26"), (1e12, "1e12")]:
        with pytest.raises(ValueError, match=rf"^prefilter_hz = {shown}: above 25 Hz, .* sample period of 0\.001 s"):
            m.compensate(desired, time=t[:100], prefilter_hz=hz)
        with pytest.raises(ValueError, match=rf"^prefilter_hz = {shown}: above 25 Hz"):
            m.compensate(desired, period=H, prefilter_hz=hz)
    with pytest.raises(ValueError, match="it needs the record's time stamps time"):
        m.compensate(desired, prefilter_hz=5.0)
    with pytest.raises(ValueError, match=r"^desired\[5\] = NaN: input sample NaN is not finite"):
        m.compensate(np.where(np.arange(100) == 5, np.nan, desired), time=t[:100], prefilter_hz=5.0)


ODD = [None, "abc", [1.0, None, 2.0], np.ones((3, 3)), np.array([1 + 2j, 3]), [], [np.nan, 1.0], 5,
       np.array([], dtype=np.float32), float("inf"), -0.0, object()]


def test_odd_arguments_raise_value_or_type_errors(fitted, record):
    """No panic and no other exception crosses into Python from the new arguments."""
    t, x, y, _ = record
    m = fitted.model
    calls = [
        lambda a, b: m.process(a, time=b),
        lambda a, b: m.process(a, period=b),
        lambda a, b: m.compensate(a, time=b, prefilter_hz=5.0),
        lambda a, b: m.compensate(a, period=H, derivatives=b),
        lambda a, b: m.compensate(y[:3], period=a, prefilter_hz=b),
        lambda a, b: hyst.fit(x[:50], y[:50], time=a, dynamics=b),
        lambda a, b: hyst.fit(x[:50], y[:50], time=t[:50], rate_term=a, dynamics=b),
    ]
    for call in calls:
        for a in ODD:
            for b in ODD:
                try:
                    call(a, b)
                except (ValueError, TypeError):
                    pass
    # An empty record runs to an empty result, but still needs its time.
    assert m.process(np.empty(0), period=H).size == 0
    with pytest.raises(ValueError, match="it needs the record's time stamps time"):
        m.process(np.empty(0))


def test_uneven_stamps_and_the_hold_are_hyst_run(fitted, record, cli, tmp_path):
    """Uneven steps (DAQ jitter, a Unix-epoch offset) run at their own lengths, bit for bit as
    `hyst run`, under the file's hold or `hold=` (`hyst run --hold`); a gap starts the rest
    afresh with a UserWarning."""
    _, x, _, _ = record
    steps = np.where(np.arange(N) % 7 == 3, 2.3e-3, 1e-3 + 2e-4 * (np.arange(N) % 3))
    t = 1.7e9 + np.r_[0.0, np.cumsum(steps[1:])]
    path = tmp_path / "m.toml"
    fitted.model.save(path)
    data = write_csv(tmp_path / "x.csv", {"t": t, "x": x})
    for hold in ["foh", "zoh"]:
        out = tmp_path / f"y-{hold}.csv"
        cli("run", "--model", path, "--hold", hold, data, "-o", out)
        y = fitted.model.process(x, time=t, hold=hold)
        assert np.array_equal(y, computed(out)), hold
    assert fitted.model.dynamics["hold"] == "foh"
    assert np.array_equal(fitted.model.process(x, time=t), fitted.model.process(x, time=t, hold="foh"))
    assert not np.array_equal(fitted.model.process(x, time=t), fitted.model.process(x, time=t, hold="zoh"))
    with pytest.raises(ValueError, match=r'hold = "x": invalid value'):
        fitted.model.process(x, time=t, hold="x")
    # A gap: the rest starts at rest, as a record of its own.
    gap = np.arange(N) * H
    gap[2000:] += 5.0
    with pytest.warns(UserWarning, match=r"time\[2000\]: a gap of 5\.00"):
        y = fitted.model.process(x, time=gap)
    assert np.array_equal(y[2000:], fitted.model.process(x[2000:], time=gap[2000:]))


def test_the_hysteresis_part_of_a_timed_model(fitted, record, tmp_path):
    """Model.hysteresis: the static model of the plant output, without the plant; what a user
    got before by deleting [dynamics] from the model file."""
    t, x, _, _ = record
    m = fitted.model
    h = m.hysteresis
    assert h.dynamics is None and h.rate is None and not h.is_inverse
    assert "dynamics.a1" in m.params and "dynamics.a1" not in h.params
    assert {k: v for k, v in m.params.items() if not k.startswith("dynamics.")} == h.params
    text = h.to_toml()
    assert "[dynamics]" not in text and "version = 1" in text
    # Held at a constant command, the plant rests at b·x, and the timed model gives the
    # hysteresis part's output at b·x.
    b = m.dynamics["b"]
    for level in (-0.2, 0.4):
        held = np.full(500, level)
        h.reset()  # a static model keeps its history between calls; each level starts afresh
        assert np.allclose(m.process(held, time=t[:500]), h.process(b * held), rtol=0, atol=1e-12)
    h.reset()
    # The timed model's refusal of inverse() names it.
    with pytest.raises(ValueError, match=r"hyst\.Compensator\(model\), and the inverse of its hysteresis part Model\.hysteresis\.inverse\(\)"):
        m.inverse()
    # It takes what a static model takes: inverse, step, memory, pickling.
    v = 0.2 + 0.4 * np.sin(np.linspace(0, 12, 600))
    y = h.process(v)
    assert np.max(np.abs(h.inverse().process(y) - v)) < 1e-9
    assert h.memory is not None and h.step(0.1) == h.step(0.1)
    assert pickle.loads(pickle.dumps(h)).params == h.params
    # A static model's part is a copy of it, without history.
    assert h.hysteresis.to_toml() == h.to_toml() and h.hysteresis.memory is None


def test_a_timed_models_compensator_in_python_control_is_compensate(fitted, record, cli, tmp_path):
    """hyst.Compensator(model) of a model with dynamics in python-control: the open loop
    (u_new -> commands) equals Model.compensate and `hyst run --inverse` bit for bit on the
    reference its integrators give; closed through the plant and the hysteresis part, the
    output follows the reference."""
    ct = pytest.importorskip("control")
    import hyst.control

    t, _, _, _ = record
    m = fitted.model
    path = tmp_path / "m.toml"
    m.save(path)
    comp = hyst.Compensator(m, state=[1.0])
    assert comp.b == m.dynamics["b"] and comp.a == m.dynamics["a"] and comp.order == 1
    f = 1.3
    u_new = 3.0 * np.pi * f * np.sin(2 * np.pi * f * t)  # v' of v = 1 + 3 sin²(π f t)
    sys = hyst.control.iosys(comp, H, inputs="u_new", outputs="u", name="comp")
    assert sys.state_labels == ["v", *hyst.control.STATE_NAMES]
    start = hyst.control.state(comp)
    resp = ct.input_output_response(sys, t, u_new, X0=start)
    commands, v = resp.outputs, resp.states[0]
    assert np.max(np.abs(v - (1.0 + 3.0 * np.sin(np.pi * f * t) ** 2))) < 1e-2
    # The library's compensate and the CLI on the same reference and derivative.
    assert np.array_equal(commands, m.compensate(v, period=H, derivatives=u_new))
    assert np.array_equal(commands, copy.copy(comp).process(u_new, H))  # the object, stepped
    data = write_csv(tmp_path / "d.csv", {"t": t, "y": v, "y_d1": u_new})
    out = tmp_path / "u.csv"
    cli("run", "--model", path, "--inverse", data, "-o", out)
    assert np.array_equal(commands, computed(out))

    # Closed: u_new -> compensator -> plant b/(a1 s + 1) under its hold -> hysteresis part.
    plant = ct.sample_system(ct.tf([m.dynamics["b"]], [m.dynamics["a"][0], 1.0]), H, method="foh")
    plant = ct.ss(plant, inputs="u", outputs="x1", name="plant")
    hyst_part = hyst.control.iosys(m.hysteresis, H, inputs="x1", outputs="y", name="H")
    loop = ct.interconnect([sys, plant, hyst_part], inputs="u_new", outputs="y")
    # The plant starts at rest at the first command, the hysteresis part with no history.
    rest = np.linalg.solve(np.eye(plant.nstates) - plant.A, plant.B[:, 0] * commands[0])
    y = ct.input_output_response(loop, t, u_new, X0=np.r_[start, rest, np.zeros(6)]).outputs
    # The loop is the timed model run on the commands (python-control's first-order-hold
    # discretisation against hyst's, to rounding), and its output follows the reference to the
    # accuracy of commands given as samples (docs/fitting.md, "Compensation").
    assert np.max(np.abs(y - m.process(commands, time=t))) < 1e-9 * np.ptp(v)
    err = np.abs(y - v)[100:]
    print(f"closed loop: max |y - v| = {err.max():.3g} (span {np.ptp(v):.3g})")
    assert err.max() < 2e-3 * np.ptp(v)


def test_compensate_warns_of_unresolved_corners_and_of_a_far_sample_period(fitted, record, tmp_path):
    """As `hyst run --inverse` says on standard error: a sample period that does not resolve the
    loop's corners (here k2 raised to 1e4), and a record sampled 1000 × slower than the fit's
    (a time axis in milliseconds), each give a UserWarning naming what to do; the fit's own
    record gives none."""
    import re
    import warnings

    t, _, _, _ = record
    f = 1.3
    desired = 1.0 + 3.0 * np.sin(np.pi * f * t) ** 2
    d1 = 3.0 * np.pi * f * np.sin(2 * np.pi * f * t)
    m = fitted.model
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m.compensate(desired, time=t, derivatives=d1)
    with pytest.warns(UserWarning, match=r"sample period 1\.000e0 s is 1000 × longer .* in seconds\?"):
        m.compensate(desired, time=t * 1e3, derivatives=d1 / 1e3)
    text = re.sub(r"(\[smooth\.k2\][^\[]*?value = )[^\n]+", r"\g<1>1e4", m.to_toml())
    path = tmp_path / "sharp.toml"
    path.write_text(text)
    sharp = hyst.load_model(path)
    with pytest.warns(UserWarning, match=r"desired\[\d+\]: .* corner .* sample at most every"):
        commands = sharp.compensate(desired, time=t, derivatives=d1)
    assert commands.shape == desired.shape
