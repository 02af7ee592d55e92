"""A model whose output is bounded by its input shaping alone: y = 10 * H(0.1, 8)[tanh(x)].

The operator input lies in (-1, 1), so the outputs lie in (-11, 11), and every state reaches
10 * [-0.899, 0.899] (k1 inside 99.9 % of tanh's range): the limits of saturate=True. A desired
output out of reach is refused in output units, as `hyst run --inverse` refuses it."""

import numpy as np
import pytest

import hyst
from conftest import ROOT

MODEL = (ROOT / "crates/hyst-model/testdata/tanh-input.toml").read_text()


@pytest.fixture
def model(tmp_path):
    path = tmp_path / "tanh-in.toml"
    path.write_text(MODEL)
    return hyst.load_model(path)


def test_limits_and_range_come_from_the_input_shaping(model):
    s = model.saturation
    assert s["shaping"] == "tanh"
    assert s["range"] == pytest.approx((-11.0, 11.0), abs=1e-12)
    assert s["limits"] == pytest.approx((-8.99, 8.99), abs=1e-12)


def test_out_of_reach_is_refused_in_output_units(model):
    desired = np.array([0.0, 5.0, 8.5, 9.5, 12.0, 3.0])
    with pytest.raises(ValueError) as e:
        model.inverse().process(desired)
    text = str(e.value)
    assert text.startswith(
        "x[3] = 9.5: desired output 9.5 is outside the range (-9.000002, 9.000000) of outputs "
        "the model can reach from its state"
    ), text
    assert 'Model.inverse(saturate=True) clamps desired outputs into Model.saturation["limits"]' in text
    with pytest.raises(ValueError, match=r"x\[0\] = 10.5: .*desired output 10.5 is outside the range \(-11.00000, 9.000000\)"):
        model.inverse().process(np.array([10.5]))


def test_saturate_clamps_into_the_limits(model):
    desired = np.array([0.0, 5.0, 8.5, 9.5, 12.0, 3.0])
    inverse = model.inverse(saturate=True)
    command = inverse.process(desired)
    assert inverse.saturated == 2
    assert command[3] == pytest.approx(np.arctanh(0.999), abs=1e-9)
    assert command[4] == command[3]
    clamped = np.clip(desired, -8.99, 8.99)
    assert np.allclose(model.process(command), clamped, atol=1e-9)
