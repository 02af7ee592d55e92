"""hyst.Adaptive: the same estimator as `hyst adapt` (bit for bit on the bundled piezo record),
the compensator loop with a drifting actuator, bad samples counted or, with strict=True,
refused, and the adapted model usable as any model."""

import numpy as np
import pytest

import hyst


@pytest.fixture(scope="module")
def piezo_model(tmp_path_factory, cli, piezo_path):
    path = tmp_path_factory.mktemp("adapt") / "piezo.toml"
    cli("fit", piezo_path, "--input", "u_actuator_V", "--output", "y_capsensor_um", "-o", path)
    return path


def test_process_equals_the_cli_bit_for_bit(piezo_model, piezo, piezo_path, cli, tmp_path):
    u, y = piezo
    out = tmp_path / "out.csv"
    cli("adapt", "--model", piezo_model, piezo_path, "--input", "u_actuator_V",
        "--output", "y_capsensor_um", "-o", out)
    table = np.genfromtxt(out, delimiter=",", names=True)
    a = hyst.Adaptive(hyst.load_model(piezo_model))
    y_pred, params = a.process(u, y)
    assert a.parameters == ["k1", "k2", "gain", "offset"]
    assert params.shape == (len(u), 4)
    np.testing.assert_array_equal(y_pred, table["y_pred"])
    np.testing.assert_array_equal(params[:, 0], table["k1"])
    np.testing.assert_array_equal(params[:, 2], table["gain"])
    assert a.counts["updated"] > 7000
    assert set(a.values) == {"k1", "k2", "gain", "offset"}
    assert all(s > 0 for s in a.std_errors.values())


def drifting(k, n):
    """Output gain of the truth at sample k of n: down 30 % over the first 60 %."""
    return 1.0 - 0.3 * min(1.0, k / (0.6 * n))


def test_the_compensator_follows_a_drifting_actuator():
    model = _model(0.15, 10.0, 2.0)
    a = hyst.Adaptive(model, noise=2e-3)
    fixed = _model(0.15, 10.0, 2.0).inverse()
    truth_a, truth_f = hyst.Hysteresis(0.15, 10.0), hyst.Hysteresis(0.15, 10.0)
    n = 60_000
    t = np.arange(n) * 1e-3
    desired = 1.6 * np.sin(1.7 * t) * (0.6 + 0.3 * np.sin(0.13 * t)) + 0.1
    err_a, err_f = [], []
    for k in range(n):
        g = 2.0 * drifting(k, n)
        x = a.step(desired[k])
        y = g * truth_a.step(x) + 0.1
        a.measure(y)
        yf = g * truth_f.step(fixed.process(np.array([desired[k]]))[0]) + 0.1
        if k > n // 2:
            err_a.append(y - desired[k])
            err_f.append(yf - desired[k])
    rms_a, rms_f = np.sqrt(np.mean(np.square(err_a))), np.sqrt(np.mean(np.square(err_f)))
    assert rms_a < rms_f / 10, (rms_a, rms_f)
    assert abs(a.values["gain"] / 1.4 - 1) < 0.02


def _model(k1, k2, gain):
    toml = f"""format = "hyst-model"
version = 1
kind = "smooth"
parameters = []
[columns]
input = "x"
output = "y"
[units]
input = ""
output = ""
[metrics]
parameters = 0
fit_seconds = 0.0
ns_per_sample = 0.0
[metrics.training]
samples = 0
rms = 0.0
max_abs = 0.0
rms_pct_span = 0.0
max_pct_span = 0.0
[smooth]
k1 = {k1}
initial_state = "line"
[smooth.k2]
law = "constant"
value = {k2}
[smooth.input_shaping]
pre_gain = 1.0
pre_offset = 0.0
shape = "identity"
post_gain = 1.0
post_offset = 0.0
[smooth.output_shaping]
pre_gain = 1.0
pre_offset = 0.0
shape = "identity"
post_gain = {gain}
post_offset = 0.1
[provenance]
file = "none"
bytes = 0
fnv1a64 = "0"
rows = 0
records = 0
command = "hand-written"
hyst_version = "0.1.0"
created_unix = 0
"""
    return hyst._hyst._model_from_toml(toml, source="<test>")


def test_bad_samples_are_counted_or_with_strict_refused():
    model = _model(0.15, 10.0, 2.0)
    x = np.sin(np.linspace(0, 20, 500))
    y = 2.0 * hyst.Hysteresis(0.15, 10.0).process(x) + 0.1
    y[100] = np.nan
    x2 = x.copy()
    x2[200] = np.inf
    a = hyst.Adaptive(model, noise=1e-3)
    y_pred, _ = a.process(x2, y)
    assert a.counts["bad_output"] == 1 and a.counts["bad_input"] == 1
    assert np.isnan(y_pred[200]) and np.isfinite(y_pred[100])
    strict = hyst.Adaptive(model, noise=1e-3, strict=True)
    with pytest.raises(ValueError, match="sample 100: .*the measurement is not finite"):
        strict.process(x, y)
    with pytest.raises(ValueError, match="gian"):
        hyst.Adaptive(model, noise=1e-3, parameters=["k1", "gian"])
    with pytest.raises(ValueError, match="noise is needed"):
        hyst.Adaptive(model)
    with pytest.raises(ValueError, match="drift"):
        hyst.Adaptive(model, noise=1e-3, drift=-1.0)
    with pytest.raises(ValueError, match="same length|one measurement per command"):
        a.process(x[:10], y[:11])
    assert a.measure(1.0) is None


def test_the_adapted_model_is_a_model():
    model = _model(0.15, 10.0, 2.0)
    x = np.sin(np.linspace(0, 200, 20_000))
    y = 1.7 * hyst.Hysteresis(0.15, 10.0).process(x) + 0.1
    a = hyst.Adaptive(model, noise=1e-3, parameters=["gain"])
    a.process(x, y)
    m = a.model()
    assert abs(a.values["gain"] - 1.7) < 1e-3
    out = m.process(x)
    assert np.sqrt(np.mean((out[-5000:] - y[-5000:]) ** 2)) < 1e-3
    assert "adapted from: hand-written" in m.to_toml()
    a.reset()
    assert a.values["gain"] == 2.0


def test_the_adapted_models_params_are_the_values_it_computes_with(piezo_model, piezo):
    """Model.params of an adapted model: k1, k2, out.gain and out.offset are the adapted
    numbers (the model file's [smooth] values), not the fit's; the standard errors stay the
    fit's."""
    u, y = piezo
    fitted = hyst.load_model(piezo_model)
    a = hyst.Adaptive(fitted)
    a.process(u, 1.1 * y + 0.5)  # the actuator's gain and offset have moved
    m = a.model()
    for name, adapted in (("k1", "k1"), ("k2", "k2"), ("out.gain", "gain"), ("out.offset", "offset")):
        assert m.params[name] == a.values[adapted], name
        assert m.params[name] != fitted.params[name], name
    assert m.std_errors == fitted.std_errors
    # The values are those of the model file's model section, read back.
    text = m.to_toml()
    assert f"k1 = {m.params['k1']!r}" in text.split("[smooth]")[1]
    assert hyst._hyst._model_from_toml(text).params == m.params
