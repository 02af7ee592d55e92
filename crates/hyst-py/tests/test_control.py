"""hyst.control.iosys against the real python-control: input_output_response gives
what ``.process`` gives on the same samples, bit for bit, for every supported object; series and closed loops
with python-control's discrete linear systems give what a loop written by hand gives; the state
is the operator's memory; what cannot be represented is refused; and the example
examples/python/pi_loop.py runs."""

import copy
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import control as ct  # pinned in requirements-test.txt: missing, the tests fail, not skip
import hyst
import hyst.control
from conftest import ROOT

DT = 1e-3
N = 1500
T = np.arange(N) * DT
STATIC = ROOT / "crates" / "hyst-model" / "testdata" / "static-model.toml"


def signal(lo=-1.5, hi=1.5):
    """A two-tone input with minor loops, spanning about [lo, hi]."""
    s = 0.8 * np.sin(2 * np.pi * 1.3 * T) + 0.25 * np.sin(2 * np.pi * 9.0 * T + 0.4)
    return 0.5 * (lo + hi) + 0.5 * (hi - lo) * s / 1.05


def response(obj, u, **kwargs):
    return ct.input_output_response(hyst.control.iosys(obj, DT), T[: len(u)], u, **kwargs)


@pytest.fixture(scope="module")
def models(piezo):
    """Fitted models of the piezo record with different shapings (input/output)."""
    x, y = piezo
    return {
        "affine": hyst.fit(x, y).model,
        "poly3/poly3": hyst.fit(x, y, input_shaping="poly3", output_shaping="poly3").model,
        "affine/tanh": hyst.fit(x, y, output_shaping="tanh").model,
        "affine/langevin": hyst.fit(x, y, output_shaping="langevin", initial_state="falling").model,
        "line/poly2": hyst.fit(x, y, output_shaping="poly2", initial_state="line").model,
        "affine-k2": hyst.fit(x, y, output_shaping="poly3", k2="affine").model,
        "pi": hyst.fit(x, y, model_kind="prandtl-ishlinskii").model,
        "pi/poly3": hyst.fit(x, y, model_kind="prandtl-ishlinskii", pi_output="poly3").model,
    }


MODELS = ["affine", "poly3/poly3", "affine/tanh", "affine/langevin", "line/poly2", "affine-k2", "pi", "pi/poly3"]


@pytest.mark.parametrize(
    "make",
    [
        lambda: hyst.Hysteresis(0.2, 8.0),
        lambda: hyst.InverseHysteresis(0.2, 8.0),
        lambda: hyst.Hysteresis(0.2, 8.0, dtype="float32"),
        lambda: hyst.InverseHysteresis(0.05, 30.0),
    ],
    ids=["direct", "inverse", "direct-float32", "inverse-narrow"],
)
def test_operator_response_is_process(make):
    u = signal()
    r = response(make(), u)
    assert r.outputs.shape == (N,)
    assert np.array_equal(r.outputs, make().process(u))


def test_bank_response_is_process():
    k1, k2 = np.array([0.1, 0.2, 0.3]), np.array([4.0, 8.0, 2.0])
    u = np.column_stack([signal(), 0.5 * signal(), signal(-3, 1)])
    for inverse in (False, True):
        sys_ = hyst.control.iosys(hyst.Bank(k1, k2, inverse=inverse), DT)
        assert (sys_.ninputs, sys_.noutputs, sys_.nstates) == (3, 3, 18)
        r = ct.input_output_response(sys_, T, u.T)
        assert np.array_equal(r.outputs.T, hyst.Bank(k1, k2, inverse=inverse).process(u))


@pytest.mark.parametrize("name", MODELS)
def test_model_response_is_process(models, piezo, name):
    """A fitted model and its exact inverse (Model.inverse()), started by the model's rule: the
    model's own steps, so process's samples bit for bit."""
    model = models[name]
    x = signal(float(piezo[0].min()), float(piezo[0].max()))
    y = model.direct().process(x)
    r = response(model, x)
    assert np.array_equal(r.outputs, y)
    back = response(model.inverse(), y)
    assert np.array_equal(back.outputs, model.inverse().process(y))


@pytest.mark.parametrize("name", ["poly3/poly3", "affine-k2", "pi/poly3"])
def test_model_state_is_its_memory_and_resumes_it(models, piezo, name):
    """state(model) continues where the model stopped; memory(x) gives Model.memory back."""
    for model in (models[name].direct(), models[name].inverse()):
        u = signal(float(piezo[0].min()), float(piezo[0].max()))
        if model.is_inverse:
            u = model.direct().process(u)
        whole = copy.copy(model).process(u)
        first = model.process(u[:700])
        x0 = hyst.control.state(model)
        sys_ = hyst.control.iosys(model, DT)
        assert sys_.nstates == x0.size and x0[0] == 1.0
        assert hyst.control.memory(x0, model=model) == model.memory
        r = response(model, u[700:], X0=x0)
        assert np.array_equal(np.r_[first, r.outputs], whole)
        model.process(u[700:])
        last = sys_.dynamics(T[-1], r.states[:, -1], [u[-1]])
        assert hyst.control.memory(last, model=model) == model.memory
        model.reset()
        assert np.array_equal(hyst.control.state(model), np.zeros(sys_.nstates))
    if name.startswith("pi"):
        assert sys_.state_labels[:3] == ["has_history", "last_output", "play[0]"]


def test_saturating_inverse_clamps_as_process(models):
    model = models["affine/tanh"]
    lo, hi = model.saturation["limits"]
    desired = np.linspace(lo - 0.2 * (hi - lo), hi + 0.2 * (hi - lo), N)
    inverse = model.inverse(saturate=True)
    r = response(inverse, desired)
    assert np.array_equal(r.outputs, inverse.process(desired))
    with pytest.raises(ValueError, match=r"at t = .*outside the range"):
        response(model.inverse(), desired)  # without saturate, as Model.process refuses


def test_stop_form_model(root):
    """A friction model (stop form, with its linear term) from the damper record."""
    import csv

    with open(root / "data" / "friction-damper" / "friction_damper_sines.csv", newline="") as f:
        rows = [r for _, r in zip(range(6000), csv.DictReader(f))]
    x = np.array([float(r["x_mm"]) for r in rows])
    force = np.array([float(r["force_kN"]) for r in rows])
    model = hyst.fit(x, force).model
    assert "form = \"stop\"" in model.to_toml()
    r = response(model, x[:N])
    assert np.array_equal(r.outputs, model.process(x[:N]))


def test_state_is_the_memory_and_resumes_it():
    h = hyst.Hysteresis(0.2, 8.0)
    u = signal()
    first = h.process(u[:700])
    x0 = hyst.control.state(h)
    m = h.memory
    assert list(x0) == [1.0, m.reversal_input, m.reversal_output, 1.0 if m.direction == "rising" else -1.0,
                        m.last_input, m.last_output]
    r = response(h, u[700:], X0=x0)  # goes on where h stopped
    assert np.array_equal(np.r_[first, r.outputs], hyst.Hysteresis(0.2, 8.0).process(u))
    h.process(u[700:])
    assert r.states.shape == (6, N - 700)
    # The state after the last sample (one update past the last stored state) is h's memory.
    sys_ = hyst.control.iosys(h, DT)
    last = sys_.dynamics(T[-1], r.states[:, -1], [u[-1]])
    assert hyst.control.memory(last) == h.memory
    assert hyst.control.memory(np.zeros(6)) is None
    assert np.array_equal(hyst.control.state(hyst.InverseHysteresis(0.1, 3.0)), np.zeros(6))
    bank = hyst.Bank([0.1, 0.2], [3.0, 4.0])
    bank.process(np.column_stack([u, u])[:100])
    assert np.array_equal(hyst.control.state(bank)[6:], hyst.control.state(_channel(bank, 1)))


def _channel(bank, c):
    h = hyst.Hysteresis(bank.k1[c], bank.k2[c])
    h.memory = bank.memory(c)
    return h


def test_output_has_direct_feedthrough_and_keeps_the_state():
    """y[k] = H(memory[k-1], u[k]): outfcn depends on u now and changes nothing."""
    sys_ = hyst.control.iosys(hyst.Hysteresis(0.2, 8.0), DT)
    h = hyst.Hysteresis(0.2, 8.0)
    h.process([0.0, 0.5, 0.2])
    x = hyst.control.state(h)
    before = x.copy()
    y1 = sys_.output(0.0, x, [0.7])
    y2 = sys_.output(0.0, x, [-0.3])
    assert np.array_equal(x, before)
    assert y1[0] == hyst.Hysteresis(0.2, 8.0).process([0.0, 0.5, 0.2, 0.7])[-1]
    assert y2[0] == hyst.Hysteresis(0.2, 8.0).process([0.0, 0.5, 0.2, -0.3])[-1]
    assert np.array_equal(sys_.output(0.0, x, [0.7]), y1)
    nxt = sys_.dynamics(0.0, x, [0.7])
    h.step(0.7)
    assert hyst.control.memory(nxt) == h.memory


def test_series_with_a_discrete_lag_is_the_hand_loop():
    """H followed by a discrete first-order lag (control.ss), as one interconnection."""
    a = float(np.exp(-DT / 0.02))
    lag = ct.ss([[a]], [[1 - a]], [[1.0]], [[0.0]], DT, inputs="h", outputs="y", name="lag")
    plant = ct.interconnect(
        [hyst.control.iosys(hyst.Hysteresis(0.2, 8.0), DT, inputs="v", outputs="h", name="H"), lag],
        inputs="v", outputs="y",
    )
    assert plant.dt == DT
    u = signal()
    r = ct.input_output_response(plant, T, u)
    h, z, expected = hyst.Hysteresis(0.2, 8.0), 0.0, []
    for v in u:
        expected.append(z)  # the lag has no direct term
        z = a * z + (1 - a) * h.step(v)
    assert np.allclose(r.outputs, expected, rtol=1e-13, atol=1e-13)
    # control.series gives the same system.
    r2 = ct.input_output_response(ct.series(hyst.control.iosys(hyst.Hysteresis(0.2, 8.0), DT), lag), T, u)
    assert np.allclose(r2.outputs, expected, rtol=1e-13, atol=1e-13)


def test_closed_loop_pi_compensator_plant_is_the_hand_loop():
    """r -> PI -> H^-1 -> H -> lag -> y, fed back: the loop closed by python-control gives the
    samples of the loop written by hand; and as H(H^-1(.)) is the identity, it is the linear
    loop of the PI and the lag alone."""
    k1, k2, kp, ki = 0.2, 8.0, 0.4, 40.0
    a = float(np.exp(-DT / 0.01))
    pi = ct.ss([[1.0]], [[DT]], [[ki]], [[kp]], DT, inputs="e", outputs="ud", name="pi")
    lag = ct.ss([[a]], [[1 - a]], [[1.0]], [[0.0]], DT, inputs="h", outputs="y", name="lag")
    err = ct.summing_junction(inputs=["r", "-y"], output="e", name="err")
    comp = hyst.control.iosys(hyst.InverseHysteresis(k1, k2), DT, inputs="ud", outputs="v", name="comp")
    plant = hyst.control.iosys(hyst.Hysteresis(k1, k2), DT, inputs="v", outputs="h", name="H")
    loop = ct.interconnect([err, pi, comp, plant, lag], inputs="r", outputs=["y", "v"])
    r = signal()
    out = ct.input_output_response(loop, T, r)

    hinv, h = hyst.InverseHysteresis(k1, k2), hyst.Hysteresis(k1, k2)
    integral, z, ys, vs = 0.0, 0.0, [], []
    for rk in r:
        e = rk - z
        ud = ki * integral + kp * e
        v = hinv.step(ud)
        ys.append(z)
        vs.append(v)
        integral += DT * e
        z = a * z + (1 - a) * h.step(v)
    assert np.allclose(out.outputs[0], ys, rtol=1e-12, atol=1e-12)
    assert np.allclose(out.outputs[1], vs, rtol=1e-12, atol=1e-12)

    linear = ct.feedback(lag * pi, 1)
    lin = ct.input_output_response(linear, T, r)
    assert np.allclose(out.outputs[0], lin.outputs, rtol=1e-9, atol=1e-9)
    assert np.sqrt(np.mean((out.outputs[0] - r)[200:] ** 2)) < 0.1 * np.ptp(r)  # it tracks


def test_feedback_around_a_model_and_its_inverse(models):
    """control.feedback and series with a fitted Model and its inverse in the loop."""
    model = models["poly3/poly3"]
    a = float(np.exp(-DT / 0.01))
    lag = ct.ss([[a]], [[1 - a]], [[1.0]], [[0.0]], DT)
    pi = ct.ss([[1.0]], [[DT]], [[50.0]], [[0.3]], DT)
    forward = ct.series(pi, hyst.control.iosys(model.inverse(), DT), hyst.control.iosys(model, DT), lag)
    loop = ct.feedback(forward, 1)
    y0 = float(model.direct().process([1.8])[0])
    t = T[:600]
    r = y0 + 5.0 * np.sin(2 * np.pi * 2.0 * t)
    out = ct.input_output_response(loop, t, r)
    lin = ct.input_output_response(ct.feedback(ct.series(pi, lag), 1), t, r)
    assert np.allclose(out.outputs, lin.outputs, rtol=1e-9, atol=1e-9 * np.ptp(r))


def test_names_are_passed_through():
    sys_ = hyst.control.iosys(hyst.Hysteresis(0.2, 8.0), 0.01, inputs="v", outputs="u", name="H")
    assert sys_.name == "H" and sys_.input_labels == ["v"] and sys_.output_labels == ["u"]
    assert sys_.state_labels == list(hyst.control.STATE_NAMES) and sys_.dt == 0.01
    named = hyst.control.iosys(hyst.Hysteresis(0.2, 8.0), True, states=[f"m{i}" for i in range(6)])
    assert named.state_labels == [f"m{i}" for i in range(6)] and named.dt is True


def test_refusals(root):
    h = hyst.Hysteresis(0.2, 8.0)
    supported = r"supported: hyst\.Hysteresis, hyst\.InverseHysteresis, hyst\.Bank, a hyst\.Model"
    with pytest.raises(ValueError, match=r"^dt = True: a hyst\.Compensator integrates"):
        hyst.control.iosys(hyst.Compensator(h, 1.0, [0.02]), True)
    with pytest.raises(TypeError, match=r"expected hyst\.Hysteresis.*got float"):
        hyst.control.iosys(0.5, DT)
    text = STATIC.read_text()
    timed = text.replace("version = 1", "version = 4").replace("[provenance]", "[dynamics]\nb = 1.0\na = [0.05]\n\n[provenance]")
    with pytest.raises(TypeError, match=r"dynamics or a rate term.*its hysteresis part is model\.hysteresis.*" + supported):
        hyst.control.iosys(hyst._hyst._model_from_toml(timed), DT)
    # Its hysteresis part and its compensator are taken.
    part = hyst._hyst._model_from_toml(timed).hysteresis
    assert np.array_equal(response(part, signal()).outputs, part.process(signal()))
    assert hyst.control.iosys(hyst.Compensator(hyst._hyst._model_from_toml(timed)), DT).nstates == 1 + 6
    with pytest.raises(TypeError, match=r"hyst\.control\.state: .*dynamics or a rate term"):
        hyst.control.state(hyst._hyst._model_from_toml(timed))
    rate = text.replace("version = 1", "version = 4").replace("[provenance]", "[rate]\nc = 0.05\n\n[provenance]")
    with pytest.raises(TypeError, match=r"dynamics or a rate term"):
        hyst.control.iosys(hyst._hyst._model_from_toml(rate), DT)
    for dt in (0, -1e-3, float("nan"), None, False):
        with pytest.raises(ValueError, match=r"dt = .*sample time"):
            hyst.control.iosys(h, dt)
    with pytest.raises(TypeError, match=r"hyst\.control\.state: expected .*got float"):
        hyst.control.state(0.5)
    with pytest.raises(ValueError, match=r"6 state values"):
        hyst.control.memory([1.0, 2.0])


def test_a_refused_sample_names_the_time():
    u = signal()
    u[300] = np.nan
    with pytest.raises(ValueError, match=r"Hysteresis at t = 0\.3 s: x = NaN"):
        response(hyst.Hysteresis(0.2, 8.0), u)


def test_the_hand_written_model_file(root):
    """The static test model of the core (k1 0.2, k2 6, ψ_in = 0.5 x - 1, ψ_out = 3 u + 1), and
    the same with an affine k2 law."""
    text = STATIC.read_text()
    affine_k2 = text.replace('law = "constant"\nvalue = 6.0', 'law = "affine"\nat_zero = 6.0\nslope = 0.5\nmin = 1.0\nmax = 10.0')
    assert affine_k2 != text
    for model in (hyst.load_model(STATIC), hyst._hyst._model_from_toml(affine_k2)):
        x = signal(-1.0, 5.0)
        assert np.array_equal(response(model, x).outputs, model.process(x))
        y = model.direct().process(x)
        assert np.array_equal(response(model.inverse(), y).outputs, model.inverse().process(y))
        assert hyst.control.memory(hyst.control.state(model)) == model.memory


def test_a_model_system_leaves_the_model_alone(models):
    """iosys works on a copy: the model's memory and clamp count are as before."""
    model = models["affine/tanh"].inverse(saturate=True)
    lo, hi = model.saturation["limits"]
    model.process([lo - 1.0, 0.5 * (lo + hi)])
    before, clamped = model.memory, model.saturated
    response(model, np.linspace(lo - 1.0, hi + 1.0, 200))
    assert model.memory == before and model.saturated == clamped == 1


def test_import_hyst_without_python_control():
    """`import hyst` works without python-control; iosys names the extra in its ImportError."""
    code = (
        "import sys; sys.modules['control'] = None\n"
        "import hyst, hyst.control\n"
        "try:\n"
        "    hyst.control.iosys(hyst.Hysteresis(0.2, 8.0), 1e-3)\n"
        "except ImportError as e:\n"
        "    print(e)\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert p.returncode == 0, p.stderr
    assert 'pip install "hyst[control]"' in p.stdout and "python-control" in p.stdout


def test_pi_loop_example_runs(tmp_path):
    png = tmp_path / "plots" / "loop.png"
    env = dict(os.environ, MPLBACKEND="Agg")
    p = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "python" / "pi_loop.py"), "--out", str(png)],
        capture_output=True, text=True, timeout=300, cwd=tmp_path, env=env,
    )
    assert p.returncode == 0, p.stdout + p.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
    m = re.search(r"RMS tracking error .*: ([0-9.e+-]+) um with the hyst compensator, ([0-9.e+-]+) um with a linear inverse", p.stdout)
    assert m, p.stdout
    with_hyst, linear = float(m.group(1)), float(m.group(2))
    assert with_hyst < 0.6 * linear
    assert not (tmp_path / "pi_loop.png").exists()  # only where --out says


def test_docs_python_control_block_runs(monkeypatch):
    """The Python block under "## python-control" in docs/python.md, run as written from the
    repository root."""
    text = (ROOT / "docs" / "python.md").read_text()
    section = text.split("## python-control\n", 1)[1]
    block = section.split("```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(ROOT)
    exec(compile(block, "docs/python.md", "exec"), {})


@pytest.mark.parametrize("a", [[], [0.02], [0.9, 1.0], [0.1, 0.03, 0.002]], ids=["n0", "n1", "n2", "n3"])
def test_compensator_response_is_process_and_its_state_resumes_it(a):
    """A Lemma 5.1 compensator in python-control: the commands are its process(u_new, dt)'s bit
    for bit (turning points of v between samples included, n >= 2); the state vector is its
    integrators and its inverse model's memory, which resume it exactly."""
    h = hyst.Hysteresis(0.2, 8.0)
    n = len(a)
    u_new = 0.6 * np.sin(2 * np.pi * 3.0 * T) + (0.3 if n == 0 else 0.0)
    comp = hyst.Compensator(h, 1.5, a)
    sys = hyst.control.iosys(comp, DT)
    assert sys.nstates == n + 6 and sys.state_labels[:n] == ["v", "v_d1", "v_d2"][:n]
    half = N // 2
    first = ct.input_output_response(sys, T[:half], u_new[:half], X0=hyst.control.state(comp))
    expected = copy.copy(comp).process(u_new, DT)
    assert np.array_equal(first.outputs, expected[:half])
    # The last state resumes it: in python-control, and assigned to a fresh compensator.
    end = first.states[:, -1]
    fresh = hyst.Compensator(h, 1.5, a)
    ref = copy.copy(comp)
    ref.process(u_new[: half - 1], DT)
    x_last = hyst.control.state(ref)
    # first.states[:, -1] is the state before the last sample of the first half.
    assert np.array_equal(end, x_last)
    ref.step(float(u_new[half - 1]), DT)
    fresh.state = list(hyst.control.state(ref)[:n])
    fresh.memory = hyst.control.memory(hyst.control.state(ref)[n:])
    assert np.array_equal(fresh.process(u_new[half:], DT), expected[half:])
    again = ct.input_output_response(sys, T[half:], u_new[half:], X0=hyst.control.state(ref))
    assert np.array_equal(again.outputs, expected[half:])
    assert comp.state == [0.0] * n  # the system steps a copy


def test_compensator_state_and_memory_are_checked():
    comp = hyst.Compensator(hyst.Hysteresis(0.2, 8.0), 1.0, [0.9, 1.0])
    comp.process(np.full(200, 3.0), 1e-2)
    state, memory = comp.state, comp.memory
    with pytest.raises(ValueError, match=r"state has 1 values: give n = len\(a\) = 2"):
        comp.state = [1.0]
    with pytest.raises(ValueError, match=r"^state = \[NaN, 0\.0\]: invalid parameter integrator state = NaN"):
        comp.state = [float("nan"), 0.0]
    with pytest.raises(ValueError, match=r"^memory: "):
        comp.memory = hyst.Memory(0.0, 5.0, "rising", 0.0, 5.0)  # outside the band (k1 = 0.2)
    with pytest.raises(TypeError):
        comp.memory = 1.0
    assert comp.state == state and comp.memory == memory
    comp.memory = None
    assert comp.memory is None
