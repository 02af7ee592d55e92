"""Whatever is passed, the interpreter never aborts and no Rust panic reaches Python: bad
arguments raise ValueError / TypeError / OSError (IndexError for a channel outside a Bank)
with a message."""

import numpy as np
import pytest

import hyst


def no_panic(fn, *args, **kwargs):
    """Calls fn; returns its result or the exception, failing on a Rust panic."""
    try:
        return fn(*args, **kwargs)
    except BaseException as e:  # noqa: BLE001 - a PanicException derives from BaseException
        assert type(e).__name__ != "PanicException", f"panic crossed into Python: {e}"
        assert isinstance(e, (ValueError, TypeError, OSError, OverflowError, IndexError)), repr(e)
        assert str(e), "an exception without a message"
        return e


ODD = [
    None, "text", b"bytes", 1 + 2j, [1, "a"], [[1, 2], [3]], np.array([1 + 1j, 2]),
    np.array(["x", "y"]), np.array([1.0, np.inf]), np.array([np.nan]), np.zeros((0, 3)),
    np.float64(3.0), 7, object(), np.array([1e308, -1e308, 1e308]), np.array([5e-324, -5e-324]),
    np.arange(10, dtype=np.int8), np.array([True, False, True]), np.ones(5, dtype=np.float16),
]


@pytest.mark.parametrize("x", ODD, ids=range(len(ODD)))
def test_operators_survive_odd_input(x):
    for op in (hyst.Hysteresis(0.2, 8.0), hyst.InverseHysteresis(0.2, 8.0),
               hyst.Hysteresis(0.2, 8.0, dtype="float32"), hyst.Hysteresis(1e-300, 1e300)):
        no_panic(op.process, x)
        no_panic(op.process, x, derivatives=x)
        no_panic(op.step, x)
        no_panic(setattr, op, "memory", x)
        f = hyst.Family(0.2, 0.1, 8.0, 1.0)
        no_panic(f.envelope, x)
        no_panic(hyst.Compensator(op, 1.0, [0.1]).process, x, 1e-3)


@pytest.mark.parametrize("x", ODD, ids=range(len(ODD)))
def test_banks_survive_odd_input(x):
    for bank in (hyst.Bank([0.2, 0.1, 0.3], [8.0, 1.0, 3.0]),
                 hyst.Bank([0.2, 0.1, 0.3], [8.0, 1.0, 3.0], inverse=True, dtype="float32"),
                 hyst.Bank([1e-300, 4e307, 1.0], [1e300, 1e-300, 1.0], inverse=True)):  # extremes the core takes
        no_panic(bank.step, x)
        no_panic(bank.step, np.zeros(3), out=x)
        no_panic(bank.process, x)
        no_panic(bank.process, np.zeros((4, 3)), out=x)
        no_panic(bank.process, np.array([[1e308, -1e308, 5e-324]] * 3))
        no_panic(bank.memory, x)
        no_panic(bank.set_memory, 0, x)
        no_panic(bank.__setstate__, x)
        no_panic(hyst.Bank, x, x)
        no_panic(hyst.Bank, x, [1.0, 2.0, 3.0], dtype=x)
    aliased = np.zeros((4, 3))
    no_panic(bank.process, aliased, out=aliased)
    no_panic(bank.process, aliased, out=aliased[::-1])


@pytest.mark.parametrize(
    "args",
    [(np.nan, 1), (1, np.nan), (1e308, 1e308), (5e-324, 1.0), (1.0, 5e-324), ("a", 1), (None, 1), (-0.0, 1)],
)
def test_constructors_survive_odd_parameters(args):
    for cls in (hyst.Hysteresis, hyst.InverseHysteresis):
        no_panic(cls, *args)
        no_panic(cls, *args, dtype="float32")
    no_panic(hyst.Family, *args, *args)
    no_panic(hyst.Memory, *args)


def test_fit_survives_odd_data():
    u = np.linspace(-1, 1, 50)
    for y in (np.zeros(50), u * 1e300, u * 1e-300, np.where(u > 0, 1e308, -1e308), -u):
        no_panic(hyst.fit, u, y)
    no_panic(hyst.fit, u, u, record=np.full(50, 0.5))
    no_panic(hyst.fit, u, u, segment=-1)
    no_panic(hyst.fit, u, u, starts=-3)
    no_panic(hyst.fit, [], [])
    no_panic(hyst.fit, u, u, input_name="y", output_name="y")
    no_panic(hyst.fit, u, u, input_name="", output_name="y")
    no_panic(hyst.load_model, "\0")
    no_panic(hyst.Compensator, hyst.Hysteresis(0.2, 8.0), np.nan, [1.0])
    no_panic(hyst.Compensator, hyst.Hysteresis(0.2, 8.0), 1.0, [np.inf])


def test_missing_values_are_named_not_reported_as_nan():
    """numpy reads None as NaN; the error names the missing value and where it is."""
    op = hyst.InverseHysteresis(0.2, 8.0)
    for x, where in (([0.0, 0.5, None, 1.0], "sample 2"),
                     (np.array([0.0, None], dtype=object), "sample 1"),
                     ((None,), "sample 0")):
        with pytest.raises(ValueError, match=f"{where} is None") as e:
            op.process(x)
        assert "NaN" not in str(e.value)
    with pytest.raises(ValueError, match="got None"):
        op.process(None)
    bank = hyst.Bank([0.2, 0.1], [8.0, 1.0])
    with pytest.raises(ValueError, match=r"element \(1, 0\) is None"):
        bank.process([[0.0, 0.1], [None, 0.2]])
    # A real NaN is still a NaN.
    with pytest.raises(ValueError, match="NaN|nan"):
        op.process(np.array([0.0, np.nan]))


def test_a_memory_off_its_branch_is_refused():
    """Rising with the reversal input 1e300 above the last input is a state no operator
    produces; assigning it raises ValueError and keeps the memory."""
    h = hyst.Hysteresis(0.2, 8.0)
    h.step(0.4)
    kept = h.memory
    with pytest.raises(ValueError, match="last_input"):
        h.memory = hyst.Memory(1e300, 1e300, "rising", last_input=0.4, last_output=0.3)
    assert h.memory == kept


def test_messages_blame_the_right_value_and_print_numbers_shortly():
    """A NaN derivative, a negative time step and an empty fit are named in their messages,
    and huge values print in exponent form."""
    model = hyst.Hysteresis(0.2, 8.0)
    x = np.array([0.0, 0.5, 1.0])
    d = np.array([0.1, np.nan, 0.2])
    with pytest.raises(ValueError, match=r"derivatives\[1\] = NaN: not a finite number"):
        model.process(x, derivatives=d)
    c = hyst.Compensator(hyst.Hysteresis(0.2, 8.0), b=1.0, a=[0.1])
    with pytest.raises(ValueError, match=r"dt = -1: the time step must be finite and >= 0"):
        c.step(1.0, dt=-1.0)
    with pytest.raises(ValueError, match="no samples"):
        hyst.fit(np.array([]), np.array([]))
    # Huge values print in exponent form, not as 300-digit integers.
    with pytest.raises(ValueError) as e:
        c.step(1e308, dt=1e300)
    assert len(str(e.value)) < 300 and "1e308" in str(e.value), str(e.value)


def test_out_that_aliases_x_or_is_strided_is_named():
    """out=x and a strided out say what is wrong with out."""
    h = hyst.Hysteresis(0.2, 8.0)
    x = np.linspace(0.0, 1.0, 10)
    with pytest.raises(ValueError, match=r"out|x: the array is being written"):
        h.process(x, out=x)
    with pytest.raises(ValueError, match=r"out: the array is not contiguous"):
        h.process(x[:5], out=np.empty(10)[::2])


def test_pure_noise_is_no_hysteresis(piezo):
    """An output that does not depend on the input is "no hysteresis found", not a model (and
    kept, it is marked degenerate)."""
    u, _ = piezo
    u = u[:3000]
    for seed in range(3):
        noise = np.random.default_rng(seed).random(u.size)
        with pytest.raises(ValueError) as refused:
            hyst.fit(u, noise)
        # Noise may also fold back along the input, or fall with it (refused before any fit).
        message = str(refused.value)
        assert any(
            said in message
            for said in ("no hysteresis found", "not monotone", "decreases when the input increases")
        ), message
        if "no hysteresis found" in message:
            assert hyst.fit(u, noise, keep_degenerate=True).degenerate
