"""hyst's operators and fitted models as python-control systems: ``iosys(obj, dt)``.

python-control (https://python-control.org) simulates and interconnects discrete-time systems
whose state is a vector of floats. ``iosys`` gives a hysteresis operator, the inverse of one, a
fitted static model (smooth or Prandtl–Ishlinskii) or its exact inverse (the compensator of a
static plant) such a system, so it can sit in a loop with controllers and linear plants built
by ``control.ss`` or ``control.tf``, and run in ``control.input_output_response``.

It needs the optional dependency python-control (``pip install "hyst[control]"``; from a clone,
``pip install "./crates/hyst-py[control]"``). ``import hyst`` and ``import hyst.control`` work
without it; ``iosys`` raises ImportError naming the extra when it is missing.

>>> import numpy as np, hyst, hyst.control                         # doctest: +SKIP
>>> sys = hyst.control.iosys(hyst.Hysteresis(0.2, 8.0), dt=1e-3)  # doctest: +SKIP
"""

from __future__ import annotations

import copy
import math
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union, cast, overload

import numpy as np

from ._hyst import Bank, Compensator, Hysteresis, InverseHysteresis, Memory, Model

__all__ = ["iosys", "state", "memory", "STATE_NAMES"]

#: The names of the six state variables of one operator (Definition 2.1's memory).
STATE_NAMES = (
    "has_history",
    "reversal_input",
    "reversal_output",
    "direction",
    "last_input",
    "last_output",
)
_N = len(STATE_NAMES)

_EXTRA = (
    'install the extra: pip install "hyst[control]" (from a clone: pip install '
    '"./crates/hyst-py[control]"), or pip install control'
)

_SUPPORTED = (
    "hyst.Hysteresis, hyst.InverseHysteresis, hyst.Bank, a hyst.Model without dynamics or a "
    "rate term (smooth or Prandtl-Ishlinskii; direct, or its inverse from Model.inverse()), and "
    "a hyst.Compensator"
)


def _control() -> Any:
    try:
        import control  # type: ignore[import-untyped]
    except ImportError as e:
        raise ImportError(f"hyst.control.iosys needs python-control, which is not installed: {_EXTRA}") from e
    return control


# ---------------------------------------------------------------------------------------------
# The state vector: Definition 2.1's memory as six floats; a Prandtl–Ishlinskii model's plays.

#: A Prandtl–Ishlinskii model's memory, as ``Model.memory`` gives it: (plays, last_output).
_Plays = Tuple[Tuple[float, ...], float]
_Vector = Union[Sequence[float], np.ndarray]


def _encode(m: Optional[Memory]) -> np.ndarray:
    if m is None:
        return np.zeros(_N)
    return np.array(
        [
            1.0,
            m.reversal_input,
            m.reversal_output,
            1.0 if m.direction == "rising" else -1.0,
            m.last_input,
            m.last_output,
        ]
    )


def _decode(x: _Vector) -> Optional[Memory]:
    if not x[0] > 0.5:
        return None
    return Memory(
        float(x[1]),
        float(x[2]),
        "rising" if x[3] >= 0.0 else "falling",
        float(x[4]),
        float(x[5]),
    )


def _encode_plays(m: Optional[_Plays], n: int) -> np.ndarray:
    if m is None:
        return np.zeros(2 + n)
    plays, last = m
    return np.array([1.0, last, *plays], dtype=float)


def _decode_plays(x: _Vector) -> Optional[_Plays]:
    if not x[0] > 0.5:
        return None
    return tuple(float(p) for p in x[2:]), float(x[1])


def _model_refusal(model: Model) -> Optional[str]:
    """Why iosys cannot represent ``model`` (None: it can)."""
    if model.dynamics is not None or model.rate is not None:
        return (
            f"hyst.control.iosys: {model!r} is a model with dynamics or a rate term (it runs on "
            "timed records and keeps no memory: Model.process(x, t=...) and Model.compensate); "
            "its hysteresis part is model.hysteresis (put the plant in the loop as a "
            "control.ss/control.tf system), its Lemma 5.1 compensator hyst.Compensator(model); "
            f"supported: {_SUPPORTED}"
        )
    return None


def _plays(model: Model) -> int:
    """The number of plays of a Prandtl–Ishlinskii model: from the memory of a scratch copy
    after one sample."""
    probe = copy.copy(model)
    probe.step(0.0)
    return len(cast(_Plays, probe.memory)[0])


def state(obj: Union[Hysteresis, InverseHysteresis, Bank, Model, Compensator]) -> np.ndarray:
    """The state vector of ``iosys(obj, dt)`` that continues from ``obj``'s memory now: the
    initial state to give ``control.input_output_response`` (``X0``) to resume where ``obj``
    stopped. A ``Bank`` gives its channels' six values one after the other; a ``Model`` the six
    values of its operator's memory (``Model.memory``), or for a Prandtl–Ishlinskii model
    ``has_history``, ``last_output`` and its play outputs; a ``Compensator`` its n integrators
    (``Compensator.state``) then the six values of its inverse model's memory
    (``Compensator.memory``). TypeError for anything else (and for a model with dynamics or a
    rate term, which keeps no memory)."""
    if isinstance(obj, (Hysteresis, InverseHysteresis)):
        return _encode(obj.memory)
    if isinstance(obj, Bank):
        return np.concatenate([_encode(obj.memory(c)) for c in range(obj.channels)])
    if isinstance(obj, Compensator):
        return np.concatenate([np.asarray(obj.state, dtype=float), _encode(obj.memory)])
    if isinstance(obj, Model):
        why = _model_refusal(obj)
        if why is not None:
            raise TypeError(why.replace("hyst.control.iosys", "hyst.control.state", 1))
        if obj.kind == "smooth":
            return _encode(cast(Optional[Memory], obj.memory))
        return _encode_plays(cast(Optional[_Plays], obj.memory), _plays(obj))
    raise TypeError(
        f"hyst.control.state: expected hyst.Hysteresis, hyst.InverseHysteresis, hyst.Bank or "
        f"hyst.Model, got {type(obj).__name__}"
    )


@overload
def memory(x: _Vector) -> Optional[Memory]: ...


@overload
def memory(x: _Vector, model: Optional[Model]) -> Union[Memory, _Plays, None]: ...


def memory(x: _Vector, model: Optional[Model] = None) -> Union[Memory, _Plays, None]:
    """The memory (None for no history) that the state values ``x`` of ``iosys`` encode: assign
    it to the object's ``memory`` to go on from the end of a simulation
    (``memory(response.states[:, -1])``).

    Without ``model`` (or with a smooth one) ``x`` is six values and the result a
    ``hyst.Memory``: an operator's, a ``Bank`` channel c's (``x[6 c : 6 c + 6]``) or a smooth
    model's operator H (H⁻¹ for the inverse), in operator units. With a Prandtl–Ishlinskii
    ``model``, ``x`` is its state (``has_history``, ``last_output``, the play outputs) and the
    result ``(plays, last_output)`` as ``Model.memory`` gives it."""
    a = np.asarray(x, dtype=float).reshape(-1)
    if model is not None and model.kind != "smooth":
        n = _plays(model)
        if a.shape != (2 + n,):
            raise ValueError(f"memory: expected the {2 + n} state values of a model of {n} plays, got {a.size}")
        return _decode_plays(a)
    if a.shape != (_N,):
        raise ValueError(f"memory: expected the {_N} state values of one operator, got {a.size}")
    return _decode(a)


# ---------------------------------------------------------------------------------------------
# What one sample does, from a state vector and an input vector, without side effects: a scratch
# copy of the object is given the memory the state encodes, steps, and its memory is read.


class _Operator:
    """Hysteresis or InverseHysteresis."""

    def __init__(self, op: Union[Hysteresis, InverseHysteresis]) -> None:
        self.op = copy.deepcopy(op)
        self.ninputs, self.noutputs, self.nstates = 1, 1, _N
        self.state_names: List[str] = list(STATE_NAMES)

    def step(self, x: np.ndarray, u: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        self.op.memory = _decode(x)
        y = self.op.step(float(u[0]))
        return np.array([y]), _encode(self.op.memory)


class _Bank:
    """N channels: six state values per channel, one input and one output per channel."""

    def __init__(self, bank: Bank) -> None:
        self.bank = copy.deepcopy(bank)
        n = bank.channels
        self.ninputs, self.noutputs, self.nstates = n, n, _N * n
        self.state_names = [f"{s}[{c}]" for c in range(n) for s in STATE_NAMES]

    def step(self, x: np.ndarray, u: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        n = self.ninputs
        for c in range(n):
            self.bank.set_memory(c, _decode(x[_N * c : _N * (c + 1)]))
        y = np.array(self.bank.step(np.asarray(u, dtype=float)), dtype=float)
        return y, np.concatenate([_encode(self.bank.memory(c)) for c in range(n)])


class _Model:
    """A fitted static model or its exact inverse (``Model.memory``): a smooth model's state is
    its operator's six values, a Prandtl–Ishlinskii model's ``has_history``, ``last_output``
    and its play outputs. The zero state is no history: the model's start rule."""

    def __init__(self, model: Model) -> None:
        why = _model_refusal(model)
        if why is not None:
            raise TypeError(why)
        self.model = copy.copy(model)  # the model file, direction and saturate; no history
        self.ninputs, self.noutputs = 1, 1
        self.encode: Callable[[Any], np.ndarray]
        self.decode: Callable[[np.ndarray], Any]
        if model.kind == "smooth":
            self.nstates, self.state_names = _N, list(STATE_NAMES)
            self.encode, self.decode = _encode, _decode
        else:
            n = _plays(model)
            self.nstates = 2 + n
            self.state_names = ["has_history", "last_output", *(f"play[{i}]" for i in range(n))]
            self.encode, self.decode = (lambda m: _encode_plays(m, n)), _decode_plays

    def step(self, x: np.ndarray, u: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        self.model.memory = self.decode(x)
        y = self.model.step(float(u[0]))
        return np.array([y]), self.encode(self.model.memory)


class _Compensator:
    """Lemma 5.1's compensator: input u_new = v⁽ⁿ⁾, output the command u (eq. 19); the state is
    its n integrators (v, v̇, …, v⁽ⁿ⁻¹⁾) then its inverse model's memory (six values). Each
    sample integrates u_new over the system's sample time ``dt``."""

    def __init__(self, comp: Compensator, dt: float) -> None:
        self.comp = copy.copy(comp)
        self.dt = dt
        n = comp.order
        self.n = n
        self.ninputs, self.noutputs, self.nstates = 1, 1, n + _N
        self.state_names = [*(["v"] if n else []), *(f"v_d{i}" for i in range(1, n)), *STATE_NAMES]

    def step(self, x: np.ndarray, u: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        self.comp.state = [float(v) for v in x[: self.n]]
        self.comp.memory = _decode(x[self.n :])
        command = self.comp.step(float(u[0]), self.dt)
        return np.array([command]), np.concatenate([np.asarray(self.comp.state, dtype=float), _encode(self.comp.memory)])


def _stepper(obj: Any, dt: Union[float, bool]) -> Any:
    if isinstance(obj, (Hysteresis, InverseHysteresis)):
        return _Operator(obj)
    if isinstance(obj, Bank):
        return _Bank(obj)
    if isinstance(obj, Model):
        return _Model(obj)
    if isinstance(obj, Compensator):
        if dt is True:
            raise ValueError(
                "dt = True: a hyst.Compensator integrates its new input u_new = v^(n) over the "
                "sample time, so it needs dt in seconds (> 0)"
            )
        return _Compensator(obj, float(dt))
    raise TypeError(f"hyst.control.iosys: expected {_SUPPORTED}; got {type(obj).__name__}")


def iosys(
    obj: Union[Hysteresis, InverseHysteresis, Bank, Model, Compensator],
    dt: Union[float, bool],
    *,
    inputs: Any = None,
    outputs: Any = None,
    states: Any = None,
    name: Optional[str] = None,
    **kwargs: Any,
) -> Any:
    """``obj`` as a discrete-time ``control.NonlinearIOSystem`` of sample time ``dt``.

    Parameters
    ----------
    obj : hyst.Hysteresis, hyst.InverseHysteresis, hyst.Bank, hyst.Model or hyst.Compensator
        The operator u = H(k1, k2)[v] (eq. 2) or its inverse v = H⁻¹[u_d] (eq. 4); a bank of N
        of them (N inputs, N outputs); a fitted model without dynamics or a rate term, smooth,
        x → y = ψ_out(H[ψ_in(x)]) (or its stop form), or Prandtl–Ishlinskii, or its exact
        inverse from ``Model.inverse()`` (desired output y_d → command x;
        ``inverse(saturate=True)`` clamps as it does); the hysteresis part of a model with
        dynamics (``Model.hysteresis``); a Lemma 5.1 ``Compensator`` (of a model with dynamics,
        ``Compensator(model)``): input the new input u_new = v⁽ⁿ⁾, output the command u of
        eq. (19), each sample integrating u_new over ``dt``. ``obj`` itself is not changed: the
        system steps a copy of it, given the state the state vector encodes.
    dt : float or True
        The sample time in seconds (> 0; ``True``: discrete time with an unspecified sample
        time, as python-control takes it). The operators are rate independent, so ``dt`` only
        sets the system's time base: systems in one interconnection share it. A
        ``Compensator`` integrates over it, so it needs a number (ValueError for ``True``).
    inputs, outputs, states, name
        python-control's signal and system names, passed to ``NonlinearIOSystem`` (defaults:
        python-control's ``u[i]``, ``y[i]``; the states are named by ``STATE_NAMES``, per
        channel for a bank, as below for a Prandtl–Ishlinskii model).
    **kwargs
        Passed to ``NonlinearIOSystem`` as they are (``params``, …).

    Returns
    -------
    control.NonlinearIOSystem
        Input and output in the units of ``obj``'s own input and output (an operator: operator
        units; a model: the model file's input and output units, ``Model.units``).

        The state is the memory of Definition 2.1, six floats per operator (``STATE_NAMES``):
        ``has_history`` (0: no history yet, 1: the other five hold the memory),
        ``reversal_input`` α0 and ``reversal_output`` β0 (the last reversal point),
        ``direction`` (+1 rising, −1 falling), ``last_input`` and ``last_output`` (the last
        sample). α is the operator's input and β its output: (v, u) for ``Hysteresis``,
        (u_d, v) for ``InverseHysteresis``; for a smooth ``Model`` they are those of its
        operator H (H⁻¹ for the inverse) in operator units, between the shaping functions
        (``Model.memory``). A Prandtl–Ishlinskii model's state is ``has_history``, the
        ``last_output`` of its PI sum and its n play outputs ``play[0]`` … ``play[n-1]``
        (``Model.memory`` = (plays, last_output)). The zero state is "no history": an
        operator's first sample then lies on the line output = input, a model starts by its
        start rule (``initial_state`` of the model file), as ``process`` does on a fresh
        object. ``hyst.control.state(obj)`` is the state that continues from an object's
        memory, ``hyst.control.memory(x)`` the memory a state vector holds.

        A ``Compensator``'s state is its n integrators ``v``, ``v_d1`` … ``v_d{n-1}``
        (``Compensator.state``) followed by the six values above of its inverse model's memory
        (``Compensator.memory``, of H⁻¹ in operator units). Its zero state is not where it
        starts (its inverse model starts by the model's start rule): give
        ``X0=hyst.control.state(comp)``.

        The output has direct feedthrough: y[k] = H(memory[k−1], u[k]), so the output
        function computes the sample from the state and the input without changing the state,
        and the update function gives the memory after it. A loop closed through this system
        therefore needs a strictly proper element elsewhere (a plant with no direct term),
        as python-control's interconnections do for any algebraic loop.

    Every sample is the object's own ``step`` from the memory the state encodes, so the
    outputs are ``process``'s bit for bit, for operators, banks and models alike (a
    compensator's are its ``process(u_new, dt)``'s). A model with dynamics or a rate term is
    refused (TypeError): it runs on timed records and keeps no memory; its hysteresis part
    ``Model.hysteresis`` and its ``Compensator(model)`` are taken.

    Raises
    ------
    ImportError
        python-control is not installed (``pip install "hyst[control]"``).
    TypeError
        For an object it cannot represent, naming what is supported.
    ValueError
        For a ``dt`` that is not > 0; in a simulation, at a sample the object refuses (NaN,
        infinity, a desired output beyond a saturating shaping's range), with the time.
    """
    ct = _control()
    if dt is not True and (
        isinstance(dt, bool) or not isinstance(dt, (int, float)) or not (math.isfinite(dt) and dt > 0)
    ):
        raise ValueError(f"dt = {dt!r}: expected the sample time in seconds (> 0), or True")
    impl = _stepper(obj, dt)
    label = name or type(obj).__name__
    cache: Dict[Tuple[bytes, bytes], Tuple[np.ndarray, np.ndarray]] = {}

    def evaluate(t: float, x: Any, u: Any) -> Tuple[np.ndarray, np.ndarray]:
        xs = np.ascontiguousarray(x, dtype=float).reshape(-1)
        us = np.ascontiguousarray(u, dtype=float).reshape(-1)
        key = (xs.tobytes(), us.tobytes())
        hit = cache.get(key)
        if hit is None:
            try:
                hit = impl.step(xs, us)
            except ValueError as e:
                raise ValueError(f"{label} at t = {float(t):.9g} s: {e}") from e
            if len(cache) >= 16:  # outfcn and updfcn ask for the same sample: keep the last few
                cache.pop(next(iter(cache)))
            cache[key] = hit
        return hit

    def updfcn(t: float, x: Any, u: Any, params: Any = None) -> np.ndarray:
        return evaluate(t, x, u)[1].copy()

    def outfcn(t: float, x: Any, u: Any, params: Any = None) -> np.ndarray:
        return evaluate(t, x, u)[0].copy()

    return ct.NonlinearIOSystem(
        updfcn,
        outfcn,
        inputs=impl.ninputs if inputs is None else inputs,
        outputs=impl.noutputs if outputs is None else outputs,
        states=impl.state_names if states is None else states,
        name=name,
        dt=dt,
        **kwargs,
    )
