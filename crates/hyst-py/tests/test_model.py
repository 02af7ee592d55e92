"""hyst.load_model / hyst.Model: the CLI's model file, bit-identical to `hyst run --model`."""

import copy
import pickle

import numpy as np
import pytest

import hyst
from conftest import computed


@pytest.fixture(scope="module")
def models(cli, piezo_path, tmp_path_factory):
    """Model files fitted by the CLI: smooth (tanh output, affine k2) and PI with poly3."""
    d = tmp_path_factory.mktemp("models")
    files = {}
    common = [piezo_path, "--input", "u_actuator_V", "--output", "y_capsensor_um"]
    files["smooth"] = d / "smooth.toml"
    cli("fit", *common, "-o", files["smooth"], "--output-shaping", "poly3", "--k2", "affine")
    files["pi"] = d / "pi.toml"
    cli("fit", *common, "-o", files["pi"], "--model-kind", "pi", "--pi-output", "poly3")
    return files


@pytest.mark.parametrize("kind", ["smooth", "pi"])
@pytest.mark.parametrize("inverse", [False, True])
def test_bit_identical_to_hyst_run(cli, models, piezo, piezo_path, tmp_path, kind, inverse):
    u, y = piezo
    out = tmp_path / "out.csv"
    flags = ["--inverse"] if inverse else []
    cli("run", "--model", models[kind], *flags, piezo_path, "-o", out)
    ref = computed(out)
    m = hyst.load_model(models[kind])
    if inverse:
        m = m.inverse()
    got = m.process(y if inverse else u)
    assert np.array_equal(got, ref)
    # In blocks, the model continues where it stopped: the same numbers.
    m.reset()
    x = y if inverse else u
    blocks = np.concatenate([m.process(b) for b in np.array_split(x, 7)])
    assert np.array_equal(blocks, ref)
    m.reset()
    assert np.array_equal(np.array([m.step(v) for v in x[:300]]), ref[:300])


def test_derivatives_bit_identical(cli, models, tmp_path):
    t = np.linspace(0, 4, 2001)
    x = 4.0 + 3.0 * np.sin(2 * t)
    d1 = 6.0 * np.cos(2 * t)
    path = tmp_path / "in.csv"
    with open(path, "w") as f:
        f.write("x,x_d1\n")
        for a, b in zip(x, d1):
            f.write(f"{float(a)!r},{float(b)!r}\n")
    cli("run", "--model", models["smooth"], "--column", "x", "--derivatives", 1, path, "-o", tmp_path / "o.csv")
    y, dy = hyst.load_model(models["smooth"]).process(x, derivatives=d1)
    out = tmp_path / "o.csv"
    assert np.array_equal(y, computed(out, 2)) and np.array_equal(dy, computed(out))


def test_properties_save_and_pickle(models, piezo, tmp_path):
    u, _ = piezo
    m = hyst.load_model(models["smooth"])
    assert m.kind == "smooth" and not m.is_inverse
    assert set(m.params) >= {"k1", "k2", "k2.slope", "out.gain"}
    assert set(m.std_errors) == set(m.params) and set(m.units) == set(m.params)
    assert m.columns["input"] == "u_actuator_V"
    assert m.metrics["training"]["samples"] == u.size
    if m.family is not None:
        assert m.delta_a == m.family["delta_a"]
    saved = tmp_path / "copy.toml"
    m.save(saved)
    again = hyst.load_model(saved)
    assert again.params == m.params and again.to_toml() == m.to_toml()
    clone = pickle.loads(pickle.dumps(m.inverse()))
    assert clone.is_inverse
    assert np.array_equal(pickle.loads(pickle.dumps(m)).process(u), m.process(u))
    pi = hyst.load_model(models["pi"])
    assert pi.kind == "prandtl-ishlinskii" and pi.delta_a is None and pi.family is None


def test_file_errors(tmp_path, models):
    missing = tmp_path / "nope.toml"
    with pytest.raises(FileNotFoundError, match="nope.toml"):
        hyst.load_model(missing)
    with pytest.raises(OSError, match=str(tmp_path)):
        hyst.load_model(tmp_path)
    bad = tmp_path / "bad.toml"
    bad.write_text("format = 'hyst-model'\nversion = 1\n")
    with pytest.raises(ValueError, match="bad.toml"):
        hyst.load_model(bad)
    m = hyst.load_model(models["smooth"])
    with pytest.raises(OSError, match="no-such-dir"):
        m.save(tmp_path / "no-such-dir" / "m.toml")
    assert not (tmp_path / "no-such-dir").exists()


def test_refused_sample_leaves_model_unchanged(models, piezo):
    u, _ = piezo
    m = hyst.load_model(models["smooth"])
    first = m.process(u[:100])
    with pytest.raises(ValueError, match=r"x\[3\]"):
        m.process(np.array([u[100], u[101], u[102], np.nan]))
    rest = m.process(u[100:200])
    m.reset()
    assert np.array_equal(m.process(u[:200]), np.concatenate([first, rest]))


def test_saturating_inverse_clamps_as_hyst_run_saturate(cli, models, piezo_path, tmp_path):
    common = [piezo_path, "--input", "u_actuator_V", "--output", "y_capsensor_um"]
    tanh = tmp_path / "tanh.toml"
    cli("fit", *common, "-o", tanh, "--output-shaping", "tanh")
    m = hyst.load_model(tanh)
    s = m.saturation
    assert s["shaping"] == "tanh"
    (lo, hi), (clo, chi) = s["range"], s["limits"]
    assert lo < clo < chi < hi
    # The fit puts the data in the last 0.1 % of the tanh's range: the limits still clamp no
    # output of the data's range.
    within = np.array([-120.0, -100.0, -80.0])
    assert np.array_equal(m.inverse(saturate=True).process(within), m.inverse().process(within))
    # Desired outputs that leave the range now and then.
    t = np.linspace(0.0, 6.0, 900)
    desired = 0.5 * (lo + hi) + 0.6 * (hi - lo) * np.sin(t)
    assert np.any(desired > hi) and np.any(desired < lo)
    path = tmp_path / "desired.csv"
    with open(path, "w") as f:
        f.write("y\n" + "".join(f"{float(v)!r}\n" for v in desired))
    cli("run", "--model", tanh, "--inverse", "--saturate", "--column", "y", path, "-o", tmp_path / "o.csv")
    ref = computed(tmp_path / "o.csv", 2)  # then y_saturated
    inverse = m.inverse(saturate=True)
    assert inverse.saturate and inverse.saturated == 0 and not m.saturate
    assert not hasattr(inverse, "saturates")
    assert np.array_equal(inverse.process(desired), ref)
    assert inverse.saturated == int(np.sum((desired < clo) | (desired > chi)))
    # Pickled, it still clamps; reset() clears the count.
    again = pickle.loads(pickle.dumps(inverse))
    assert again.saturate and "saturate" in repr(again)
    assert np.array_equal(again.process(desired), ref)
    inverse.reset()
    assert inverse.saturated == 0
    # Without saturate, the first value beyond the range is refused, naming its index.
    with pytest.raises(ValueError, match=r"x\[\d+\]"):
        m.inverse().process(desired)
    # A model whose output is unbounded has nothing to clamp.
    affine = hyst.load_model(models["pi"])
    assert affine.saturation is None
    with pytest.raises(ValueError, match="unbounded"):
        affine.inverse(saturate=True)


@pytest.mark.parametrize("input_shaping", ["tanh", "langevin"])
def test_saturate_with_a_saturating_input_shaping_keeps_the_training_range(cli, piezo_path, tmp_path, input_shaping):
    """The limits come from the input range the model was fitted on (0 to 3.6 V), whatever ψ_in:
    desired outputs of the training range are not clamped and get the plain inverse's commands."""
    common = [piezo_path, "--input", "u_actuator_V", "--output", "y_capsensor_um"]
    path = tmp_path / f"{input_shaping}.toml"
    cli("fit", *common, "-o", path, "--input-shaping", input_shaping, "--output-shaping", "tanh")
    m = hyst.load_model(path)
    within = np.array([-120.0, -100.0, -80.0])
    inverse = m.inverse(saturate=True)
    commands = inverse.process(within)
    assert inverse.saturated == 0
    assert np.array_equal(commands, m.inverse().process(within))
    assert np.allclose(commands, [1.33, 2.30, 3.34], atol=0.01), commands
    lo, hi = m.saturation["limits"]
    assert lo < -130.0 and hi > -75.0, (lo, hi)


@pytest.mark.parametrize("kind", ["smooth", "pi"])
@pytest.mark.parametrize("inverse", [False, True])
def test_memory_round_trip(models, piezo, kind, inverse):
    """Model.memory after N samples, assigned to a fresh copy: the copy goes on exactly as the
    model that had it; None before the first sample and after reset()."""
    u, y = piezo
    m = hyst.load_model(models[kind])
    if inverse:
        m = m.inverse()
    x = y if inverse else u
    assert m.memory is None
    whole = m.process(x)
    m.reset()
    assert m.memory is None
    k = 1234
    first = m.process(x[:k])
    saved = m.memory
    if kind == "smooth":
        assert isinstance(saved, hyst.Memory)
    else:
        plays, last = saved
        assert isinstance(plays, tuple) and len(plays) > 1 and isinstance(last, float)
        assert all(isinstance(p, float) for p in plays)
    fresh = copy.copy(m)  # the model without its history
    assert fresh.memory is None and fresh.is_inverse == inverse
    fresh.memory = saved
    assert fresh.memory == saved
    assert np.array_equal(np.concatenate([first, fresh.process(x[k:])]), whole)
    # Onto a model that has run elsewhere, and after pickling the memory: the same.
    other = copy.copy(m)
    other.process(x[::-1][:50])
    other.memory = pickle.loads(pickle.dumps(saved))
    assert np.array_equal(np.array([other.step(v) for v in x[k : k + 300]]), whole[k : k + 300])
    # None forgets the history, as reset() does: the start rule again.
    other.memory = None
    assert other.memory is None
    assert np.array_equal(other.process(x), whole)
    # The model itself was not touched by its copies.
    assert m.memory == saved


def test_memory_of_a_saturating_inverse_keeps_clamping(piezo):
    u, y = piezo
    m = hyst.fit(u, y, output_shaping="tanh").model
    lo, hi = m.saturation["range"]
    desired = 0.5 * (lo + hi) + 0.6 * (hi - lo) * np.sin(np.linspace(0.0, 6.0, 900))
    inverse = m.inverse(saturate=True)
    whole = inverse.process(desired)
    inverse.reset()
    first = inverse.process(desired[:400])
    fresh = copy.copy(inverse)
    fresh.memory = inverse.memory
    assert np.array_equal(np.concatenate([first, fresh.process(desired[400:])]), whole)
    assert fresh.saturated + inverse.saturated == int(np.sum((desired < m.saturation["limits"][0]) | (desired > m.saturation["limits"][1])))


def test_bad_memory_is_refused(models, piezo):
    """A memory the model cannot be in raises ValueError naming it; a memory of the other kind
    of model, TypeError; the model is then unchanged."""
    u, _ = piezo
    m = hyst.load_model(models["smooth"])
    m.process(u[:100])
    kept = m.memory
    k1 = m.params["k1"]
    for bad in (hyst.Memory(0.0, 10.0 * k1), hyst.Memory(1e300, 1e300, "rising", last_input=0.4, last_output=0.3)):
        with pytest.raises(ValueError, match=r"memory = Memory\(reversal_input="):
            m.memory = bad
        assert m.memory == kept
    with pytest.raises(TypeError, match=r"memory = \(\(0\.1,\), 0\.2\): a smooth model's memory is a hyst\.Memory"):
        m.memory = ((0.1,), 0.2)
    for odd in ("text", 1.0, object(), [1.0, 2.0]):
        with pytest.raises(TypeError, match="memory = "):
            m.memory = odd
    assert m.memory == kept
    fresh = copy.copy(m)
    with pytest.raises(ValueError, match="memory = Memory"):
        fresh.memory = hyst.Memory(0.0, 10.0 * k1)
    assert fresh.memory is None  # a model that had not started has still not

    pi = hyst.load_model(models["pi"])
    pi.process(u[:100])
    plays, last = kept_pi = pi.memory
    n = len(plays)
    with pytest.raises(ValueError, match=rf"memory = .*: {n + 1} play outputs for a model of {n} plays"):
        pi.memory = ((0.0,) * (n + 1), 0.0)
    with pytest.raises(ValueError, match=r"memory = .*: invalid parameter play output = NaN"):
        pi.memory = ((float("nan"),) + plays[1:], last)
    with pytest.raises(ValueError, match=r"memory = .*: invalid parameter last output = inf"):
        pi.memory = (plays, float("inf"))
    with pytest.raises(TypeError, match=r"Prandtl-Ishlinskii model's memory is \(plays, last_output\)"):
        pi.memory = kept
    assert pi.memory == kept_pi
    pi.memory = (np.array(plays), last)  # any sequence of floats
    assert pi.memory == kept_pi
    # Odd objects: TypeError or ValueError, never a panic, and nothing changes.
    odd = [None, "text", b"bytes", 1 + 2j, (plays, None), (plays, "x"), ([None] * n, 0.0), ((), 0.0),
           (np.array(["a"] * n), 0.0), ((1e308,) * n, -1e308), ((5e-324,) * n, 0.0), (plays, last, 0.0),
           hyst.Memory(1e308, -1e308), np.zeros(n + 1)]
    for model in (m, pi, copy.copy(m), copy.copy(pi), m.inverse(), pi.inverse()):
        for x in odd:
            before = model.memory
            try:
                model.memory = x
            except (TypeError, ValueError) as e:
                assert str(e) and model.memory == before


def test_a_timed_model_keeps_no_memory(root):
    text = (root / "crates" / "hyst-model" / "testdata" / "static-model.toml").read_text()
    timed = text.replace("version = 1", "version = 4").replace("[provenance]", "[dynamics]\nb = 1.0\na = [0.05]\n\n[provenance]")
    m = hyst._hyst._model_from_toml(timed)
    m.process(np.linspace(0.0, 1.0, 50), period=1e-3)
    assert m.memory is None
    with pytest.raises(ValueError, match=r"dynamics of order 1.*Model\.memory"):
        m.memory = hyst.Memory(0.0, 0.0)
    m.memory = None
