"""hyst.load_model / hyst.Model: the CLI's model file, bit-identical to `hyst run --model`."""

import pickle

import numpy as np
import pytest

import hyst
from conftest import read_csv


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
    ref = read_csv(out)["y"]
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
    ref = read_csv(tmp_path / "o.csv")
    y, dy = hyst.load_model(models["smooth"]).process(x, derivatives=d1)
    assert np.array_equal(y, ref["y"]) and np.array_equal(dy, ref["y_d1"])


def test_properties_save_and_pickle(models, piezo, tmp_path):
    u, _ = piezo
    m = hyst.load_model(models["smooth"])
    assert m.kind == "smooth" and not m.is_inverse
    assert set(m.params) >= {"k1", "k2", "k2.slope", "out.gain"}
    assert set(m.stderr) == set(m.params) and set(m.units) == set(m.params)
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
    # output of the data's range (issue 28: -120, -100, -80 were all clamped to -180210.9).
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
    ref = read_csv(tmp_path / "o.csv")["y"]
    inverse = m.inverse(saturate=True)
    assert inverse.saturate and inverse.clamped == 0 and not m.saturate
    assert not hasattr(inverse, "saturates")
    assert np.array_equal(inverse.process(desired), ref)
    assert inverse.clamped == int(np.sum((desired < clo) | (desired > chi)))
    # Pickled, it still clamps; reset() clears the count.
    again = pickle.loads(pickle.dumps(inverse))
    assert again.saturate and "saturate" in repr(again)
    assert np.array_equal(again.process(desired), ref)
    inverse.reset()
    assert inverse.clamped == 0
    # Without saturate, the first value beyond the range is refused, naming its index.
    with pytest.raises(ValueError, match=r"x\[\d+\]"):
        m.inverse().process(desired)
    # A model whose output is unbounded has nothing to clamp.
    affine = hyst.load_model(models["pi"])
    assert affine.saturation is None
    with pytest.raises(ValueError, match="unbounded"):
        affine.inverse(saturate=True)
