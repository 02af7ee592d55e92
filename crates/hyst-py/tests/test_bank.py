"""hyst.Bank: N operators stepped together. Each channel agrees with the scalar operator of its
k1, k2 within the bank's stated tolerance (|dy| <= 1e-13 max(|y|, k1) in float64, 1e-5 in
float32); step and process give the same outputs; both array orders; errors name the tick,
channel and value and leave every memory as it was; memories per channel; pickling; Ctrl-C."""

import pickle

import numpy as np
import pytest
from conftest import interrupted

import hyst

K1 = np.linspace(0.05, 0.3, 23)
K2 = np.linspace(2.0, 12.0, 23)


def signals(ticks=3000, channels=23, seed=3):
    rng = np.random.default_rng(seed)
    t = np.arange(ticks)[:, None] * 0.01
    phase = rng.uniform(0, 6, channels)
    return (0.2 + 0.02 * np.arange(channels)) * np.sin(t * (1 + 0.1 * np.arange(channels)) + phase) \
        + 0.05 * rng.standard_normal((ticks, channels)).cumsum(axis=0) / 30


def scalar(inverse, dtype=None):
    cls = hyst.InverseHysteresis if inverse else hyst.Hysteresis
    return [cls(a, b, dtype=dtype) for a, b in zip(K1, K2)]


def close(bank, ref, k1, tol):
    return np.abs(bank - ref) <= tol * np.maximum(np.abs(ref), k1)


@pytest.mark.parametrize("inverse", [False, True])
def test_channels_agree_with_the_scalar_operators(inverse):
    x = signals()
    y = hyst.Bank(K1, K2, inverse=inverse).process(x)
    assert y.shape == x.shape and y.dtype == np.float64
    ref = np.stack([op.process(x[:, c]) for c, op in enumerate(scalar(inverse))], axis=1)
    assert close(y, ref, K1, 1e-13).all(), np.max(np.abs(y - ref))
    assert np.mean(y != x) > 0.5  # the outputs move off the line y = x


def test_float32_channels_agree_with_the_float32_operators():
    x = signals().astype(np.float32)
    b = hyst.Bank(K1, K2, inverse=True, dtype="float32")
    assert b.dtype == "float32"
    y = b.process(x)
    assert y.dtype == np.float32
    ref = np.stack([op.process(x[:, c]) for c, op in enumerate(scalar(True, "float32"))], axis=1)
    assert close(y.astype(np.float64), ref, K1, 1e-5).all()


def test_step_process_and_array_orders_agree():
    x = signals(800)
    whole = hyst.Bank(K1, K2).process(x)
    b = hyst.Bank(K1, K2)
    out = np.empty(len(K1))
    steps = np.array([b.step(row).copy() for row in x[:400]]
                     + [b.step(row, out=out).copy() for row in x[400:]])
    assert np.array_equal(steps, whole)
    for layout in (np.asfortranarray(x), x[:, ::-1][:, ::-1], np.repeat(x, 2, axis=0)[::2]):
        assert np.array_equal(hyst.Bank(K1, K2).process(layout), whole)
    # In blocks, continuing the memories; into out=, C or Fortran ordered.
    b = hyst.Bank(K1, K2)
    buf = np.empty_like(x)
    assert b.process(x[:300], out=buf[:300]) is not None
    b.process(x[300:], out=buf[300:])
    assert np.array_equal(buf, whole)
    f = np.asfortranarray(np.empty_like(x))
    assert hyst.Bank(K1, K2).process(x, out=f) is f and np.array_equal(f, whole)
    # Lists are array-likes.
    assert np.array_equal(hyst.Bank(K1, K2).process(x.tolist()), whole)


def test_errors_name_tick_channel_and_value_and_keep_the_memories():
    b = hyst.Bank(K1, K2, inverse=True)
    b.process(signals(50))
    saved = [b.memory(c) for c in range(b.channels)]
    x = signals(100)
    x[70, 13] = np.nan
    with pytest.raises(ValueError, match=r"x\[70, 13\] = NaN \(channel 13\)"):
        b.process(x)
    assert [b.memory(c) for c in range(b.channels)] == saved
    row = np.zeros(len(K1))
    row[4] = np.inf
    with pytest.raises(ValueError, match=r"x\[4\] = inf \(channel 4\)"):
        b.step(row)
    assert [b.memory(c) for c in range(b.channels)] == saved
    with pytest.raises(ValueError, match=r"k1\[2\] = -1.0, k2\[2\] = 3.0 \(channel 2\): invalid parameter k1 = -1"):
        hyst.Bank([0.1, 0.2, -1.0], [1, 2, 3])
    with pytest.raises(ValueError, match=r"k2\[1\] = 1e-50 \(as float32\)"):
        hyst.Bank([0.1, 0.2], [1, 1e-50], dtype="float32")
    with pytest.raises(ValueError, match="3 values and k2 2"):
        hyst.Bank([0.1, 0.2, 0.3], [1, 2])
    with pytest.raises(ValueError, match="no channels"):
        hyst.Bank([], [])
    with pytest.raises(ValueError, match=r"expected \(ticks, 23\)"):
        b.process(np.zeros((5, 22)))
    with pytest.raises(ValueError, match="2-D"):
        b.process(np.zeros(23))
    with pytest.raises(ValueError, match="22 samples for a bank of 23"):
        b.step(np.zeros(22))
    with pytest.raises(ValueError, match=r"x\[0, 1\] = 1e39: beyond the float32 range"):
        hyst.Bank([0.1, 0.2], [1, 2], dtype="float32").process([[0.0, 1e39]])
    with pytest.raises(ValueError, match="out: expected a float64 array of shape"):
        b.process(np.zeros((5, 23)), out=np.zeros((5, 23), dtype=np.float32))
    with pytest.raises(IndexError, match="channel 23"):
        b.memory(23)
    with pytest.raises(IndexError, match="channel -1"):
        b.set_memory(-1, None)
    # Overflow: an output beyond the float range is refused, the memories kept.
    big = hyst.Bank([0.2, 4e307], [8.0, 8.0], inverse=True)  # the core takes k1 up to max/4
    big.step([0.0, 0.0])
    kept = [big.memory(0), big.memory(1)]
    with pytest.raises(ValueError, match=r"x\[1, 1\] = 1.5e308 \(channel 1\)"):
        big.process([[0.1, 0.1], [0.2, 1.5e308]])
    assert [big.memory(0), big.memory(1)] == kept


def test_memories_per_channel_move_between_bank_and_operator():
    x = signals(600)
    b = hyst.Bank(K1, K2, inverse=True)
    b.process(x[:300])
    ops = scalar(True)
    for c, op in enumerate(ops):
        op.memory = b.memory(c)
    y = b.process(x[300:])
    for c, op in enumerate(ops):
        assert close(y[:, c], op.process(x[300:, c]), K1[c], 1e-13).all()
    # Channel 5's memory into channel 6 of another bank with the same k1.
    m = b.memory(5)
    other = hyst.Bank(np.full(23, K1[5]), np.full(23, K2[5]), inverse=True)
    other.set_memory(6, m)
    assert other.memory(6) == m and other.memory(5) is None
    with pytest.raises(ValueError, match="memory of channel 0"):
        other.set_memory(0, hyst.Memory(0.0, 10.0))
    other.set_memory(6, None)
    assert other.memory(6) is None
    b.reset()
    assert all(b.memory(c) is None for c in range(b.channels))


def test_pickle_and_properties():
    x = signals(200)
    b = hyst.Bank(K1, K2, inverse=True, dtype=np.float32)
    b.process(x[:100])
    c = pickle.loads(pickle.dumps(b))
    assert (c.channels, c.inverse, c.dtype) == (23, True, "float32")
    assert np.array_equal(c.k1, K1.astype(np.float32)) and np.array_equal(c.k2, K2.astype(np.float32))
    assert np.array_equal(c.process(x[100:]), b.process(x[100:]))
    assert repr(b) == "Bank(channels=23, inverse=True, dtype='float32')"


def test_ctrl_c_stops_a_long_run_and_keeps_the_memories():
    x = np.sin(np.linspace(0.0, 2e3, 200_000))[:, None] * np.linspace(0.5, 1.5, 100)
    b = hyst.Bank(np.full(100, 0.2), np.full(100, 8.0))
    b.process(x[:2])
    saved = [b.memory(c) for c in range(b.channels)]
    interrupted(lambda: b.process(x))
    assert [b.memory(c) for c in range(b.channels)] == saved
