"""hyst.Hysteresis / hyst.InverseHysteresis / hyst.Memory: eqs. (2) and (4) with the memory of
Definition 2.1, on numpy arrays."""

import copy
import pickle

import numpy as np
import pytest

import hyst
from conftest import read_csv


def signal(n=2000, seed=1):
    """A wandering input with many reversals of every size."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 20.0, n)
    return 1.5 * np.sin(t) * np.cos(0.37 * t) + 0.3 * np.sin(7.1 * t) + 0.05 * rng.standard_normal(n)


def test_process_equals_step_and_keeps_dtype():
    x = signal()
    h1, h2 = hyst.Hysteresis(0.2, 8.0), hyst.Hysteresis(0.2, 8.0)
    y = h1.process(x)
    assert isinstance(y, np.ndarray) and y.dtype == np.float64 and y.shape == x.shape
    assert np.array_equal(y, np.array([h2.step(v) for v in x]))
    y32 = hyst.Hysteresis(0.2, 8.0).process(x.astype(np.float32))
    assert y32.dtype == np.float32
    # float64 arithmetic on float32 samples: the float64 result rounded once.
    ref = hyst.Hysteresis(0.2, 8.0).process(x.astype(np.float32).astype(np.float64))
    assert np.array_equal(y32, ref.astype(np.float32))


def test_array_likes_and_views():
    x = signal(500)
    ref = hyst.Hysteresis(0.14, 5.0).process(x)
    assert np.array_equal(hyst.Hysteresis(0.14, 5.0).process(list(x)), ref)
    assert np.array_equal(hyst.Hysteresis(0.14, 5.0).process(tuple(x)), ref)
    # A strided view is read in place, with the same results as a contiguous copy.
    wide = np.zeros(2 * x.size)
    wide[::2] = x
    assert np.array_equal(hyst.Hysteresis(0.14, 5.0).process(wide[::2]), ref)
    # Integers become float64.
    ints = np.arange(-5, 6)
    out = hyst.Hysteresis(0.5, 2.0).process(ints)
    assert out.dtype == np.float64
    assert np.array_equal(out, hyst.Hysteresis(0.5, 2.0).process(ints.astype(float)))
    # The input is not modified, the output is a new array.
    before = x.copy()
    y = hyst.Hysteresis(0.14, 5.0).process(x)
    assert np.array_equal(x, before) and not np.shares_memory(x, y)
    assert hyst.Hysteresis(0.2, 8.0).process(np.array([])).shape == (0,)


def test_float32_arithmetic():
    x = signal(3000).astype(np.float32)
    y32 = hyst.Hysteresis(0.2, 8.0, dtype=np.float32).process(x)
    y64 = hyst.Hysteresis(0.2, 8.0).process(x.astype(np.float64))
    assert y32.dtype == np.float32
    assert np.max(np.abs(y32 - y64)) < 1e-5
    assert hyst.Hysteresis(0.2, 8.0, dtype="float32").dtype == "float32"
    with pytest.raises(ValueError, match="dtype"):
        hyst.Hysteresis(0.2, 8.0, dtype="int32")
    with pytest.raises(ValueError, match="float32"):
        hyst.Hysteresis(1e-50, 8.0, dtype=np.float32)


def test_inverse_identity_and_mirrored_memory():
    x = signal(4000)
    for k1, k2 in [(0.2, 8.0), (0.05, 0.5), (1.0, 200.0)]:
        v = hyst.InverseHysteresis(k1, k2).process(x)
        back = hyst.Hysteresis(k1, k2).process(v)
        assert np.max(np.abs(back - x)) < 1e-12 * (1 + np.max(np.abs(x)))
    # inverse() mirrors the memory: from here on H(H^-1(u)) = u.
    h = hyst.Hysteresis(0.2, 8.0)
    h.process(x[:1234])
    inv = h.inverse()
    assert isinstance(inv, hyst.InverseHysteresis)
    desired = x[1234:]
    assert np.max(np.abs(h.process(inv.process(desired)) - desired)) < 1e-12
    assert isinstance(inv.direct(), hyst.Hysteresis)


def test_memory_save_restore_and_pickle():
    x = signal(3000)
    h = hyst.Hysteresis(0.2, 8.0)
    assert h.memory is None
    h.process(x[:1500])
    saved = h.memory
    assert isinstance(saved, hyst.Memory) and saved.direction in ("rising", "falling")
    rest = h.process(x[1500:])
    g = hyst.Hysteresis(0.2, 8.0)
    g.memory = pickle.loads(pickle.dumps(saved))
    assert np.array_equal(g.process(x[1500:]), rest)
    # The whole operator pickles and copies with its memory.
    h.memory = saved
    for clone in (pickle.loads(pickle.dumps(h)), copy.deepcopy(h)):
        assert np.array_equal(clone.process(x[1500:]), rest)
    # A memory outside the band |output - input| <= k1 is refused and nothing changes.
    with pytest.raises(ValueError, match="band|k1"):
        g.memory = hyst.Memory(0.0, 0.5)
    assert g.memory == h.memory or g.memory is not None
    h.reset()
    assert h.memory is None
    m = hyst.Memory(0.1, 0.0, "falling")
    assert m.to_dict()["direction"] == "falling" and m.last_input == 0.1
    with pytest.raises(ValueError, match="direction"):
        hyst.Memory(0.0, 0.0, "up")


def test_refused_sample_names_index_and_keeps_memory():
    h = hyst.Hysteresis(0.2, 8.0)
    h.process([0.0, 0.5, 1.0])
    saved = h.memory
    with pytest.raises(ValueError, match=r"x\[2\] = (NaN|nan)"):
        h.process([0.7, 0.3, np.nan, 0.1])
    assert h.memory == saved
    with pytest.raises(ValueError, match="inf"):
        h.step(np.inf)
    assert h.memory == saved


@pytest.mark.parametrize("bad", [(0.0, 8.0), (-1.0, 8.0), (0.2, 0.0), (np.nan, 1.0), (0.2, np.inf)])
def test_bad_parameters(bad):
    with pytest.raises(ValueError, match="k1|k2"):
        hyst.Hysteresis(*bad)
    with pytest.raises(ValueError, match="k1|k2"):
        hyst.InverseHysteresis(*bad)


def test_bad_arrays():
    h = hyst.Hysteresis(0.2, 8.0)
    with pytest.raises(ValueError, match=r"1-D.*\(2, 2\)"):
        h.process(np.ones((2, 2)))
    with pytest.raises(ValueError, match="x"):
        h.process(["a", "b"])
    with pytest.raises(ValueError, match="derivatives"):
        h.process(np.ones(4), derivatives=np.ones((3, 1)))
    with pytest.raises(ValueError, match="derivatives"):
        h.process(np.ones(4), derivatives=np.ones((4, 9)))
    # hyst.MAX_ORDER columns at most, and the message says so.
    y, dy = h.process(np.ones(4), derivatives=np.zeros((4, hyst.MAX_ORDER)))
    assert dy.shape == (4, hyst.MAX_ORDER)
    too_many = hyst.MAX_ORDER + 1
    with pytest.raises(ValueError, match=f"{too_many} columns; give 1 to hyst.MAX_ORDER = {hyst.MAX_ORDER} time"):
        h.process(np.ones(4), derivatives=np.zeros((4, too_many)))


def test_derivatives_match_finite_differences():
    dt = 1e-4
    t = np.arange(0.0, 3.0, dt)
    x = np.sin(2.0 * t) + 0.5 * np.sin(5.0 * t)
    dx = 2.0 * np.cos(2.0 * t) + 2.5 * np.cos(5.0 * t)
    ddx = -4.0 * np.sin(2.0 * t) - 12.5 * np.sin(5.0 * t)
    for cls in (hyst.Hysteresis, hyst.InverseHysteresis):
        y, dy = cls(0.2, 8.0).process(x, derivatives=np.column_stack([dx, ddx]))
        assert dy.shape == (x.size, 2)
        assert np.array_equal(y, cls(0.2, 8.0).process(x))
        fd = np.gradient(y, dt)
        inner = slice(10, -10)
        # Away from reversals (where the second derivative jumps), the jet agrees with the
        # central difference.
        smooth = np.ones(x.size, dtype=bool)
        for i in np.flatnonzero(np.diff(np.sign(dx)) != 0):
            smooth[max(i - 5, 0) : i + 6] = False
        err = np.abs(fd[inner] - dy[inner, 0]) / (1.0 + np.abs(dy[inner, 0]))
        assert np.max(err[smooth[inner]]) < 1e-3
        y1, d1 = cls(0.2, 8.0).process(x, derivatives=dx)
        assert d1.shape == x.shape and np.allclose(d1, dy[:, 0], rtol=1e-12, atol=1e-12)


def test_bit_identical_to_cli_with_derivatives(cli, tmp_path):
    t = np.linspace(0, 10, 3001)
    x = 1.2 * np.sin(t) + 0.4 * np.cos(2.7 * t)
    d1 = 1.2 * np.cos(t) - 1.08 * np.sin(2.7 * t)
    d2 = -1.2 * np.sin(t) - 2.916 * np.cos(2.7 * t)
    path = tmp_path / "sig.csv"
    with open(path, "w") as f:
        f.write("x,x_d1,x_d2\n")
        for row in zip(x, d1, d2):
            f.write(",".join(repr(float(v)) for v in row) + "\n")
    for inverse in (False, True):
        out = tmp_path / f"out{inverse}.csv"
        flags = ["--inverse"] if inverse else []
        cli("run", "--k1", 0.14, "--k2", 5, *flags, "--derivatives", 2, path, "-o", out)
        ref = read_csv(out)
        op = hyst.InverseHysteresis(0.14, 5.0) if inverse else hyst.Hysteresis(0.14, 5.0)
        y, dy = op.process(x, derivatives=np.column_stack([d1, d2]))
        assert np.array_equal(y, ref["y"])
        assert np.array_equal(dy[:, 0], ref["y_d1"]) and np.array_equal(dy[:, 1], ref["y_d2"])


def test_repr():
    assert repr(hyst.Hysteresis(0.2, 8.0)) == "Hysteresis(k1=0.2, k2=8.0)"
    assert "InverseHysteresis" in repr(hyst.InverseHysteresis(0.2, 8.0))


def test_ctrl_c_stops_a_long_run():
    """SIGINT during a long process() raises KeyboardInterrupt at the next chunk of 2^20 samples
    and leaves the memory as it was (a finished run would have moved it)."""
    from conftest import interrupted

    x = np.sin(np.linspace(0.0, 2e4, 20_000_000))
    h = hyst.Hysteresis(0.2, 8.0)
    h.process([0.0, 0.3])
    saved = h.memory
    interrupted(lambda: h.process(x))
    assert h.memory == saved


def test_out_array():
    x = signal(1000)
    ref = hyst.Hysteresis(0.2, 8.0).process(x)
    buf = np.empty_like(x)
    h = hyst.Hysteresis(0.2, 8.0)
    got = h.process(x, out=buf)
    assert got is buf and np.array_equal(buf, ref)
    b32 = np.empty(1000, dtype=np.float32)
    hyst.Hysteresis(0.2, 8.0).process(x.astype(np.float32), out=b32)
    assert np.array_equal(b32, hyst.Hysteresis(0.2, 8.0).process(x.astype(np.float32)))
    with pytest.raises(ValueError, match="float64"):
        h.process(x, out=np.empty(1000, dtype=np.float32))
    with pytest.raises(ValueError, match="999 elements"):
        h.process(x, out=np.empty(999))
    with pytest.raises(ValueError, match="derivatives"):
        h.process(x, derivatives=x, out=buf)
    ro = np.empty_like(x)
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="written"):
        h.process(x, out=ro)
    saved = h.memory
    with pytest.raises(ValueError, match=r"x\[1\]"):
        h.process([0.1, np.nan], out=np.empty(2))
    assert h.memory == saved
