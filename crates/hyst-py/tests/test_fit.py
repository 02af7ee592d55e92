"""hyst.fit: the identification of `hyst fit` on arrays, with the same numbers and words."""

import json
import pickle

import numpy as np
import pytest

import hyst


def test_same_model_as_the_cli(cli, piezo, piezo_path, tmp_path):
    u, y = piezo
    out = tmp_path / "cli.toml"
    report = json.loads(
        cli("fit", piezo_path, "--input", "u_actuator_V", "--output", "y_capsensor_um",
            "-o", out, "--output-shaping", "poly2", "--json").stdout
    )
    r = hyst.fit(u, y, output_shaping="poly2", input_name="u_actuator_V", output_name="y_capsensor_um")
    cli_params = {p["name"]: p["value"] for p in report["model"]["parameters"]}
    assert r.params == cli_params
    assert r.std_errors == {p["name"]: p["std_error"] for p in report["model"]["parameters"]}
    assert r.rms == report["model"]["metrics"]["training"]["rms"]
    assert r.rms_percent == report["model"]["metrics"]["training"]["rms_pct_span"]
    assert r.delta_a == report["model"]["family"]["delta_a"]
    # The JSON report has the keys of `hyst fit --json`.
    mine = json.loads(r.to_json())
    assert set(mine) == set(report) and set(mine["model"]) == set(report["model"])
    # The model runs as the CLI's model file does.
    assert np.array_equal(r.model.process(u), hyst.load_model(out).process(u))
    text = r.report()
    assert "k1" in text and "Δa" in text and "training (8027 samples)" in text


def test_options_mirror_the_cli(piezo):
    u, y = piezo
    u, y = u[:3000], y[:3000]
    pi = hyst.fit(u, y, model_kind="prandtl-ishlinskii", plays=8, pi_output="poly2")
    assert pi.model.kind == "prandtl-ishlinskii" and pi.delta_a is None and pi.family is None
    both = hyst.fit(u, y, compare=True)
    assert [c["kind"] for c in both.comparison] == ["smooth", "prandtl-ishlinskii"]
    seg = hyst.fit(u, y, segment=1000, initial_state="line", validate=[2])
    assert seg.validation is not None and seg.validation["samples"] == 1000
    # Segments of one record are one history: cutting it changes nothing without validation.
    whole = hyst.fit(u, y, initial_state="line")
    assert hyst.fit(u, y, segment=1000, initial_state="line").params == whole.params
    # Independent records each start afresh (from the start rule), so they fit differently.
    rec = np.repeat([0, 1, 2], 1000)
    by_record = hyst.fit(u, y, record=rec, initial_state="line", validate_every=3)
    assert by_record.validation["samples"] == 1000 and by_record.params != seg.params
    w = np.ones_like(u)
    w[::2] = 0.0
    weighted = hyst.fit(u, y, weight=w)
    assert weighted.model.metrics["training"]["samples"] == 1500
    # Scaling every weight by one constant changes nothing.
    assert hyst.fit(u, y, weight=np.full(u.size, 1e-100)).params == hyst.fit(u, y).params
    assert hyst.fit(u, y, weight=w * 1e-100).params == weighted.params
    aff = hyst.fit(u, y, k2="affine", input_unit="V", output_unit="um")
    assert "k2.slope" in aff.params and aff.model.columns["output_unit"] == "um"


def test_unreached_family_gives_none():
    rng = np.random.default_rng(3)
    u = np.sin(np.linspace(0, 40, 4000))
    y = hyst.Hysteresis(0.2, 6.0).process(u) + 0.002 * rng.standard_normal(u.size)
    y[rng.choice(u.size, 200, replace=False)] += 5.0  # 5 % far outliers: 99 % cannot be covered
    r = hyst.fit(x=u, y=y, coverage=0.99)
    assert r.family is None and r.delta_a is None and r.output_bound is None
    # A model's input is x, its output y: the default column names of the model file.
    assert (r.model.columns["input"], r.model.columns["output"]) == ("x", "y")
    with pytest.raises(TypeError):
        hyst.fit(u=u, y=y)
    assert "NOT reachable" in r.report()


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"output_shaping": "cubic"}, r"output_shaping = \"cubic\": invalid value; possible values: affine, poly2"),
        ({"k2": "linear"}, "possible values: constant, affine"),
        ({"model_kind": "preisach"}, "possible values: smooth, prandtl-ishlinskii"),
        ({"starts": 0}, "starts = 0"),
        ({"coverage": 1.5}, "coverage"),
        ({"segment": 1}, "segment"),
        ({"validate": [99]}, "no record 99"),
        ({"model_kind": "prandtl-ishlinskii", "plays": 0}, "plays"),
        ({"segment": 100, "segments": 200}, "segment"),
    ],
)
def test_bad_options(piezo, kwargs, words):
    u, y = piezo
    with pytest.raises(ValueError, match=words):
        hyst.fit(u[:2000], y[:2000], **kwargs)


def test_bad_data():
    u = np.linspace(0, 1, 100)
    with pytest.raises(ValueError, match="y has 99 samples but x has 100"):
        hyst.fit(u, u[:99])
    with pytest.raises(ValueError, match="weight has 99 samples but x has 100"):
        hyst.fit(u, u, weight=np.ones(99))
    with pytest.raises(ValueError, match='"record" is taken by x or y'):
        hyst.fit(u, u, record=np.zeros(100), output_name="record")
    with pytest.raises(ValueError, match="not a finite number"):
        hyst.fit(u, np.where(u > 0.5, np.nan, u))
    with pytest.raises(ValueError, match="does not vary|constant"):
        hyst.fit(np.ones(100), u)
    with pytest.raises(ValueError, match="1-D"):
        hyst.fit(np.ones((10, 10)), np.ones((10, 10)))
    with pytest.raises(ValueError, match="negative"):
        hyst.fit(u, u, weight=-np.ones(100))


def test_pickle_fit_result(piezo):
    u, y = piezo
    r = hyst.fit(u[:2000], y[:2000])
    again = pickle.loads(pickle.dumps(r))
    assert again.params == r.params and again.report() == r.report()
    assert "FitResult(kind=\"smooth\"" in repr(r)


def _friction():
    """Force against position with a clockwise loop: 3 · (x − H[x]) plus noise, a stop form."""
    t = np.arange(6000) * 1e-3
    x = 4.0 * np.sin(2 * np.pi * 0.7 * t) + 1.5 * np.sin(2 * np.pi * 1.9 * t + 0.4)
    h = hyst.Hysteresis(k1=0.3, k2=12.0)
    force = 3.0 * (x - h.process(x)) + 0.05 * np.random.default_rng(7).standard_normal(x.size)
    return x, force


def test_friction_takes_the_stop_form_and_says_so():
    x, force = _friction()
    r = hyst.fit(x, force)
    assert r.orientation == "clockwise" and r.loop_gap > 0.1
    assert "out.level" in r.params and "out.linear" in r.params
    assert r.rms < 1.2 * 0.05 and not r.degenerate  # at the noise level
    assert "stop form" in r.report()
    back = pickle.loads(pickle.dumps(r))
    assert (back.orientation, back.loop_gap, back.notes) == (r.orientation, r.loop_gap, r.notes)
    # The stop form has no inverse.
    with pytest.raises(ValueError, match="no inverse"):
        r.model.inverse()


def test_a_fit_without_hysteresis_raises_unless_kept():
    x, force = _friction()
    with pytest.raises(ValueError, match="^no hysteresis found in"):
        hyst.fit(x, force, form="operator")
    kept = hyst.fit(x, force, form="operator", keep_degenerate=True)
    assert kept.degenerate and kept.notes[0].startswith("no hysteresis found")
    with pytest.raises(ValueError, match="form"):
        hyst.fit(x, force, form="clockwise")


def test_k1_k2_in_input_units_recover_a_model_stated_in_them(cli, tmp_path):
    """y = 2 H(5 V, 0.2 /V)[x] + 3 on an input of 5 to 95 V: the fit's k1, k2 are in normalised
    input units (the input range maps to [-1, 1], half-span 45 V); k1_input = k1 / s and
    k2_input = k2 · s (s = 1/45 per V) give back 5 V and 0.2 /V, in Python, the text report, the
    JSON report and `hyst fit --json`."""
    t = np.linspace(0.0, 6.0, 6000)
    x = 50.0 + 45.0 * np.sin(2 * np.pi * 0.5 * t) * (0.55 + 0.45 * np.cos(2 * np.pi * 0.17 * t))
    x = 50.0 + 45.0 * (x - 50.0) / np.max(np.abs(x - 50.0))  # exactly 5 … 95 V
    y = 2.0 * hyst.Hysteresis(5.0, 0.2).process(x) + 3.0
    r = hyst.fit(x, y, initial_state="line", input_name="x", output_name="y")
    k = r.model.in_input_units
    half_span = 0.5 * (x.max() - x.min())
    print(f"k1 = {r.params['k1']:.6g}, k2 = {r.params['k2']:.6g} (normalised); "
          f"k1_input = {k['k1_input']:.6g} V, k2_input = {k['k2_input']:.6g} /V")
    assert abs(k["input_slope"] * half_span - 1.0) < 1e-12
    assert abs(k["k1_input"] / 5.0 - 1.0) < 1e-4 and abs(k["k2_input"] / 0.2 - 1.0) < 1e-4
    assert abs(r.params["k1"] / (5.0 / half_span) - 1.0) < 1e-4  # normalised: 5 V / 45 V
    assert k["k1_input"] == r.params["k1"] / k["input_slope"]
    assert k["k2_input"] == r.params["k2"] * k["input_slope"]
    assert k["k1_input_std_error"] == r.std_errors["k1"] / k["input_slope"]
    # The text report, the JSON report and the CLI's.
    assert f"in input units: k1 = {k['k1_input']:.7g}"[:28] in r.report()
    mine = json.loads(r.to_json())
    assert {name: mine[name] for name in k} == k
    path = tmp_path / "d.csv"
    path.write_text("x,y\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(x, y)))
    report = json.loads(cli("fit", path, "--input", "x", "--output", "y", "--initial-state", "line", "-o", tmp_path / "m.toml", "--json").stdout)
    assert {name: report[name] for name in k} == k
    # A Prandtl-Ishlinskii model has no k1, k2.
    assert hyst.fit(x, y, model_kind="prandtl-ishlinskii").model.in_input_units is None
