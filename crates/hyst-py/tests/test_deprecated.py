"""Old names still work, each with a DeprecationWarning that names the new one (docs/formats.md,
"Deprecated names"), and give what the new names give."""

import numpy as np
import pytest

import hyst


@pytest.fixture(scope="module")
def data():
    x = 0.8 * np.sin(np.linspace(0.0, 12.0 * np.pi, 1200))
    y = hyst.Hysteresis(0.2, 8.0).process(x)
    return x, y


def test_old_keywords_and_values_of_fit(data):
    x, y = data
    seg = hyst.fit(x, y, segment=400, initial_state="line")
    with pytest.warns(DeprecationWarning, match="segments is deprecated: use segment"):
        old = hyst.fit(x, y, segments=400, initial_state="line")
    assert old.params == seg.params
    with pytest.warns(DeprecationWarning, match=r'model_kind = "pi" is deprecated: use model_kind = "prandtl-ishlinskii"'):
        pi = hyst.fit(x, y, model_kind="pi", plays=8)
    assert pi.params == hyst.fit(x, y, model_kind="prandtl-ishlinskii", plays=8).params


def test_old_attribute_names(data):
    x, y = data
    r = hyst.fit(x, y, initial_state="line")
    with pytest.warns(DeprecationWarning, match=r"FitResult.stderr is deprecated: use FitResult.std_errors"):
        assert r.stderr == r.std_errors
    with pytest.warns(DeprecationWarning, match=r"Model.stderr is deprecated: use Model.std_errors"):
        assert r.model.stderr == r.model.std_errors
    inverse = r.model.inverse(saturate=False)
    with pytest.warns(DeprecationWarning, match=r"Model.clamped is deprecated: use Model.saturated"):
        assert inverse.clamped == inverse.saturated == 0
    a = hyst.Adaptive(r.model, noise=0.01)
    a.process(x, y)
    with pytest.warns(DeprecationWarning, match=r"Adaptive.sigmas is deprecated: use Adaptive.std_errors"):
        assert a.sigmas == a.std_errors


def test_t_is_the_old_name_of_time():
    m = hyst.fit(
        *_timed(), time=np.arange(2000) * 1e-3, dynamics=1, initial_state="line", hold="foh"
    ).model
    x = np.sin(np.linspace(0.0, 4.0 * np.pi, 500))
    t = np.arange(500) * 1e-3
    with pytest.warns(DeprecationWarning, match="t is deprecated: use time"):
        old = m.process(x, t=t)
    assert np.array_equal(old, m.process(x, time=t))
    with pytest.raises(ValueError, match="time and t are given"):
        m.process(x, time=t, t=t)


def _timed():
    x = 0.8 * np.sin(np.linspace(0.0, 8.0 * np.pi, 2000))
    y = hyst.Hysteresis(0.2, 8.0).process(x)
    return x, y
