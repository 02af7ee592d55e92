"""Type stubs of the extension module hyst._hyst (the Rust core through PyO3)."""

from os import PathLike
from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, TypedDict, Union, overload

import numpy as np
import numpy.typing as npt
from typing_extensions import deprecated

__version__: str
MAX_ORDER: int
"""The largest plant order n of ``Compensator`` (``len(a)``) and the most time-derivative
columns of ``process(x, derivatives)``: ``hyst_core::compensator::MAX_ORDER``."""
_MUJOCO_VERSION: int
"""The MuJoCo version the actuator plugins were compiled for, as ``mj_version()`` gives it
(4000001 for 4.0.1); 0 when this extension was built without them (``hyst.mujoco``)."""

ArrayLike = npt.ArrayLike
FloatArray = npt.NDArray[np.floating[Any]]
DType = Union[str, type, np.dtype[Any], None]
StrPath = Union[str, "PathLike[str]"]
_Plays = Tuple[Tuple[float, ...], float]
_Parameter = Literal["k1", "k2", "gain", "offset", "input_gain", "input_offset"]
"""The name of a parameter ``Adaptive`` follows."""

class _InputUnits(TypedDict):
    """``Model.in_input_units``: k1 in input units and k2 in 1/input units, with their standard
    errors, and the slope of ψ_in they are converted with."""

    k1_input: float
    k1_input_std_error: float
    k2_input: float
    k2_input_std_error: float
    input_slope: float

class Memory:
    """The memory of Definition 2.1: the last reversal point (alpha0, beta0), the direction
    ("rising" or "falling") and the last sample. Picklable; assign it back to an operator's
    ``memory`` to resume exactly where it was."""

    def __init__(
        self,
        reversal_input: float,
        reversal_output: float,
        direction: Literal["rising", "falling"] = "rising",
        last_input: Optional[float] = None,
        last_output: Optional[float] = None,
    ) -> None: ...
    @property
    def reversal_input(self) -> float: ...
    @property
    def reversal_output(self) -> float: ...
    @property
    def direction(self) -> Literal["rising", "falling"]: ...
    @property
    def last_input(self) -> float: ...
    @property
    def last_output(self) -> float: ...
    def to_dict(self) -> Dict[str, Union[float, str]]: ...

class _Operator:
    @property
    def k1(self) -> float:
        """Half-width of the loop, > 0 (output units of H)."""
    @property
    def k2(self) -> float:
        """Rate of the transition to the asymptotes, > 0 (1 / input units of H)."""
    @property
    def dtype(self) -> Literal["float64", "float32"]: ...
    @overload
    def process(self, x: ArrayLike, derivatives: None = None, *, out: Optional[FloatArray] = None) -> FloatArray: ...
    @overload
    def process(self, x: ArrayLike, derivatives: ArrayLike) -> Tuple[FloatArray, FloatArray]:
        """With ``derivatives`` of shape (n, N), N <= MAX_ORDER (1-D: the first derivative):
        the outputs and their time derivatives ``(y, dy)``."""
    def step(self, x: float) -> float: ...
    def reset(self) -> None: ...
    @property
    def memory(self) -> Optional[Memory]: ...
    @memory.setter
    def memory(self, memory: Optional[Memory]) -> None: ...

class Hysteresis(_Operator):
    """The direct operator u = H(k1, k2)[v] (eq. 2)."""

    def __init__(self, k1: float, k2: float, dtype: DType = None) -> None: ...
    def inverse(self) -> InverseHysteresis:
        """H^-1(k1, k2) (eq. 4) with this operator's memory mirrored (Proposition 4.1)."""

class InverseHysteresis(_Operator):
    """The inverse operator v = H^-1(k1, k2)[u_d] (eq. 4): the exact inverse of
    ``Hysteresis(k1, k2)``, desired output in, command out."""

    def __init__(self, k1: float, k2: float, dtype: DType = None) -> None: ...
    def direct(self) -> Hysteresis: ...

class Bank:
    """N operators H(k1[c], k2[c]) (eq. 2), or H^-1 (eq. 4) with ``inverse=True``, each with
    its own memory, stepped together in SIMD lanes. Arrays of shape (ticks, channels); results
    in the bank's dtype. Picklable."""

    def __init__(self, k1: ArrayLike, k2: ArrayLike, inverse: bool = False, dtype: DType = None) -> None: ...
    @property
    def channels(self) -> int: ...
    @property
    def k1(self) -> npt.NDArray[np.float64]: ...
    @property
    def k2(self) -> npt.NDArray[np.float64]: ...
    @property
    def inverse(self) -> bool: ...
    @property
    def dtype(self) -> Literal["float64", "float32"]: ...
    def step(self, x: ArrayLike, *, out: Optional[FloatArray] = None) -> FloatArray:
        """One tick: one sample per channel in, one output per channel out."""
    def process(self, x: ArrayLike, *, out: Optional[FloatArray] = None) -> FloatArray:
        """A block of shape (ticks, channels), row t the samples of tick t."""
    def reset(self) -> None: ...
    def memory(self, channel: int) -> Optional[Memory]: ...
    def set_memory(self, channel: int, memory: Optional[Memory]) -> None: ...

class Model:
    """A fitted model from a model file (``hyst fit``): direct (input x, output y) or as its
    exact inverse (desired output in, command out). A model with dynamics or a rate term runs
    on timed records: ``process(x, time=...)`` and ``compensate(desired, time=..., ...)``."""

    @overload
    def process(
        self,
        x: ArrayLike,
        derivatives: None = None,
        *,
        time: Optional[ArrayLike] = None,
        period: Optional[float] = None,
        hold: Optional[Literal["zoh", "foh"]] = None,
    ) -> FloatArray:
        """With ``time`` (time stamps, s; each step as measured, a gap of more than 10 median
        steps starts afresh with a UserWarning) or ``period`` (s): a model with dynamics or a
        rate term over one record from rest (``hyst run --model M`` with a time column);
        ``hold`` runs its plant under that hold instead of the file's (``hyst run --hold``).
        A static model refuses them."""
    @overload
    def process(self, x: ArrayLike, derivatives: ArrayLike) -> Tuple[FloatArray, FloatArray]:
        """With ``derivatives`` of shape (n, N), N <= MAX_ORDER (1-D: the first derivative):
        the outputs and their time derivatives ``(y, dy)``."""
    @overload
    def compensate(
        self,
        desired: ArrayLike,
        *,
        time: Optional[ArrayLike] = None,
        period: Optional[float] = None,
        derivatives: ArrayLike,
        prefilter_hz: None = None,
    ) -> FloatArray:
        """Lemma 5.1's compensator of a model with dynamics: the commands (shape (len,)) for
        the desired outputs of one record, given their first n time derivatives (shape
        (len, n)); as ``hyst run --model M --inverse`` on a timed record."""
    @overload
    def compensate(
        self,
        desired: ArrayLike,
        *,
        time: Optional[ArrayLike] = None,
        period: Optional[float] = None,
        derivatives: None = None,
        prefilter_hz: float,
    ) -> Tuple[FloatArray, FloatArray]:
        """With a reference prefilter of bandwidth ``prefilter_hz`` (finite, positive, at most
        1/20 of the Nyquist frequency of the sample period): ``(commands, y_filtered)``, the
        commands and the prefiltered reference they track (``hyst run``'s column
        ``<column>_filtered``), both of shape (len,)."""
    @property
    def hysteresis(self) -> "Model":
        """The hysteresis part of a model with dynamics or a rate term: the static model of the
        plant output x1, without the plant or rate term (a copy of a static model)."""
    @property
    def in_input_units(self) -> Optional[_InputUnits]:
        """k1 in input units and k2 in 1/input units, with their standard errors; None for a
        Prandtl-Ishlinskii model."""
    @property
    def dynamics(self) -> Optional[Dict[str, Any]]:
        """The plant before the hysteresis, {"b": b, "a": [a_1, ..., a_n], ...}, or None."""
    @property
    def rate(self) -> Optional[Dict[str, float]]:
        """The rate term c·v', {"c": c, "c_std_error": ...}, or None."""
    def step(self, x: float) -> float: ...
    def reset(self) -> None: ...
    @property
    def memory(self) -> Union[Memory, _Plays, None]:
        """Where the model stands in its history (None before the first sample): a smooth
        model's operator memory (a ``Memory``, operator units), a Prandtl–Ishlinskii model's
        ``(plays, last_output)``. Assign it to the model or a copy to go on bit for bit (None:
        as ``reset()``); TypeError for a memory of the other kind, ValueError for one the model
        cannot be in. Not pickled: a copy starts with no history."""
    @memory.setter
    def memory(self, memory: Union[Memory, _Plays, None]) -> None: ...
    def inverse(self, *, saturate: bool = False) -> Model:
        """The exact inverse of the model (``hyst run --inverse``); with ``saturate=True`` it
        clamps desired outputs into the limits of a bounded output (``saturation``)."""
    def direct(self) -> Model: ...
    @property
    def is_inverse(self) -> bool: ...
    @property
    def saturation(self) -> Optional[Dict[str, Any]]: ...
    @property
    def saturate(self) -> bool:
        """Whether this inverse clamps desired outputs (``inverse(saturate=True)``)."""
    @property
    def saturated(self) -> int: ...
    @property
    @deprecated("renamed saturated")
    def clamped(self) -> int: ...
    @property
    def kind(self) -> Literal["smooth", "prandtl-ishlinskii"]: ...
    @property
    def params(self) -> Dict[str, float]: ...
    @property
    def std_errors(self) -> Dict[str, float]: ...
    @property
    @deprecated("renamed std_errors")
    def stderr(self) -> Dict[str, float]: ...
    @property
    def units(self) -> Dict[str, str]: ...
    @property
    def columns(self) -> Dict[str, Any]: ...
    @property
    def metrics(self) -> Dict[str, Any]: ...
    @property
    def family(self) -> Optional[Dict[str, Any]]: ...
    @property
    def delta_a(self) -> Optional[float]: ...
    def to_toml(self) -> str: ...
    def export_c(self, name: str, *, period: Optional[float] = None) -> str:
        """The model as a header-only C99 file over hyst.h (what ``hyst export c [--period]``
        writes; a model with dynamics also gets its compensator, and with ``period`` its forward
        model with the plant)."""
    def export_rust(self, name: str, *, period: Optional[float] = None) -> str:
        """The model as no_std Rust over hyst-core (what ``hyst export rust [--period]``
        writes)."""
    def save(self, path: StrPath) -> None: ...

def load_model(path: StrPath) -> Model:
    """Reads and checks a model file (OSError if unreadable, ValueError if invalid)."""

class FitResult:
    """The result of ``fit``."""

    @property
    def model(self) -> Model: ...
    @property
    def params(self) -> Dict[str, float]: ...
    @property
    def std_errors(self) -> Dict[str, float]: ...
    @property
    @deprecated("renamed std_errors")
    def stderr(self) -> Dict[str, float]: ...
    @property
    def units(self) -> Dict[str, str]: ...
    @property
    def rms(self) -> float: ...
    @property
    def rms_percent(self) -> float: ...
    @property
    def max_abs(self) -> float: ...
    @property
    def validation(self) -> Optional[Dict[str, Any]]: ...
    @property
    def family(self) -> Optional[Dict[str, Any]]: ...
    @property
    def delta_a(self) -> Optional[float]: ...
    @property
    def output_bound(self) -> Optional[float]: ...
    @property
    def seconds(self) -> float: ...
    @property
    def comparison(self) -> List[Dict[str, Any]]: ...
    @property
    def orientation(self) -> Literal["counterclockwise", "clockwise", "none"]: ...
    @property
    def loop_gap(self) -> float: ...
    @property
    def degenerate(self) -> bool: ...
    @property
    def notes(self) -> List[str]: ...
    def report(self) -> str: ...
    def to_json(self) -> str: ...

Shaping = Literal["affine", "poly2", "poly3", "tanh", "langevin", "quadratic-exp"]

def fit(
    x: ArrayLike,
    y: ArrayLike,
    *,
    output_shaping: Shaping = "affine",
    input_shaping: Shaping = "affine",
    k2: Literal["constant", "affine"] = "constant",
    model_kind: Literal["smooth", "prandtl-ishlinskii"] = "smooth",
    starts: int = 3,
    segment: Optional[int] = None,
    record: Optional[ArrayLike] = None,
    weight: Optional[ArrayLike] = None,
    validate: Optional[Sequence[int]] = None,
    validate_every: Optional[int] = None,
    coverage: float = 0.99,
    plays: int = 16,
    pi_output: Literal["none", "poly2", "poly3"] = "none",
    compare: bool = False,
    input_offset: Optional[bool] = None,
    output_offset: bool = True,
    initial_state: Literal["auto", "rising", "falling", "line"] = "auto",
    estimate_initial_states: bool = False,
    form: Literal["auto", "operator", "stop"] = "auto",
    keep_degenerate: bool = False,
    input_name: str = "x",
    output_name: str = "y",
    input_unit: str = "",
    output_unit: str = "",
    time: Optional[ArrayLike] = None,
    dynamics: Optional[Union[int, Literal["auto"]]] = None,
    rate_term: Optional[Literal["viscous"]] = None,
    hold: Optional[Literal["zoh", "foh"]] = None,
    fit_from_start: bool = False,
) -> FitResult:
    """Identifies a model from its input ``x`` and the measured output ``y`` as ``hyst fit``
    does; ``dynamics`` (1 to 4, or ``"auto"``) and ``rate_term`` (``hyst fit --dynamics``,
    ``--rate-term``) need the time stamps ``time`` (s); ``hold`` (``--hold``, with ``dynamics``;
    default "zoh") is how the plant sees the command between samples (given, the standard
    errors make no allowance for the other hold); ``fit_from_start`` is
    ``--fit-from-start``."""

class Family:
    """The family RH(k1, dk1, k2, dk2) (Definition 2.8) and its bound delta_a (Prop. 3.2)."""

    def __init__(self, k1: float, dk1: float, k2: float, dk2: float) -> None: ...
    @property
    def k1(self) -> float: ...
    @property
    def dk1(self) -> float: ...
    @property
    def k2(self) -> float: ...
    @property
    def dk2(self) -> float: ...
    @property
    def delta_a(self) -> float: ...
    @property
    def corners(self) -> Tuple[float, float, float, float]: ...
    @property
    def corner_params(self) -> List[Tuple[float, float]]: ...
    @property
    def corner_points(self) -> List[float]: ...
    def member(self, a: float, b: float, dtype: DType = None) -> Hysteresis: ...
    def nominal(self, dtype: DType = None) -> Hysteresis: ...
    def inverse_member(self, a: float, b: float, dtype: DType = None) -> InverseHysteresis:
        """H^-1(k1 + a dk1, k2 + b dk2) (eq. 4), (a, b) in [-1, 1]^2, no history;
        ``inverse_member(0, 0)`` is the nominal inverse, within ``delta_a`` of every member's."""
    def envelope(self, x: ArrayLike, grid: int = 3) -> Tuple[FloatArray, FloatArray]: ...
    def bound(self) -> Dict[str, Any]: ...

class Compensator:
    """Lemma 5.1: feed-forward compensation of the plant x1/u = b / (a_n s^n + ... + a_1 s + 1)
    followed by the hysteresis, n = len(a) <= MAX_ORDER. Each step takes u_new = v^(n), the
    n-th derivative of the reference v, and returns the command u of eq. (19)."""

    def __init__(
        self,
        model: Union[Model, Hysteresis, InverseHysteresis],
        b: Optional[float] = None,
        a: Optional[Sequence[float]] = None,
        state: Optional[Sequence[float]] = None,
    ) -> None:
        """b and a: the plant; a Model with dynamics brings its own (give neither)."""
    def step(self, u_new: float, dt: float) -> float: ...
    def process(self, u_new: ArrayLike, dt: float) -> FloatArray: ...
    def reset(self) -> None: ...
    @property
    def order(self) -> int: ...
    @property
    def b(self) -> float: ...
    @property
    def a(self) -> List[float]: ...
    @property
    def state(self) -> List[float]:
        """The integrators (v, v', ..., v^(n-1)); assignable."""
    @state.setter
    def state(self, state: Sequence[float]) -> None: ...
    @property
    def memory(self) -> Optional[Memory]:
        """The inverse model's memory (of H^-1, operator units); assignable."""
    @memory.setter
    def memory(self, memory: Optional[Memory]) -> None: ...
    @property
    def last_reference(self) -> float:
        """The reference v of the last step: the plant output the command aims at."""
    @property
    def last_target(self) -> float:
        """The target x1 of the last step: the hysteresis input (plant state) that gives v."""
    @property
    def last_command(self) -> float:
        """The command u of the last step (eq. 19): the plant input."""

class Adaptive:
    """Online adaptation: the recursive estimator of a fitted model's parameters (k1, k2, the
    output gain and offset; input gain and offset where asked) and the compensator that
    follows a drifting actuator (docs/adaptation.md). Parameter names: k1, k2, gain, offset,
    input_gain, input_offset."""

    def __init__(
        self,
        model: Model,
        *,
        parameters: Optional[Sequence[_Parameter]] = None,
        noise: Optional[float] = None,
        drift: float = 1e-3,
        uncertainty: float = 0.01,
        rest: float = 1e-3,
        step: float = 0.01,
        range: float = 4.0,
        dead_zone: float = 0.0,
        input_range: Optional[Tuple[float, float]] = None,
        strict: bool = False,
    ) -> None: ...
    def process(self, x: ArrayLike, y: ArrayLike) -> Tuple[FloatArray, FloatArray]:
        """(y_pred, params): one-step predictions, and the parameters after each sample
        (n, len(parameters))."""
    def update(self, x: float, y: float) -> Tuple[float, str]: ...
    def step(self, desired: float) -> float:
        """The exact inverse of the current model: the command for a desired output."""
    def measure(self, y: float) -> Optional[float]: ...
    def reset(self) -> None: ...
    def model(self) -> Model: ...
    @property
    def parameters(self) -> List[_Parameter]: ...
    @property
    def values(self) -> Dict[_Parameter, float]: ...
    @property
    def std_errors(self) -> Dict[_Parameter, float]: ...
    @property
    @deprecated("renamed std_errors")
    def sigmas(self) -> Dict[_Parameter, float]: ...
    @property
    def counts(self) -> Dict[_Parameter, int]: ...

def _bench_core(
    k1: float,
    k2: float,
    x: ArrayLike,
    inverse: bool = False,
    dtype: DType = None,
    repeats: int = 5,
) -> float: ...
def _model_from_toml(
    text: str, inverse: bool = False, source: str = "<toml>", saturate: bool = False
) -> Model: ...
def _fit_result_from_json(
    toml: str, output_span: float, comparison: str, findings: str
) -> FitResult: ...
def _mujoco_register(functions: list[int]) -> None:
    """Registers hyst.backlash and hyst.compensator with the libmujoco whose mj_getPluginConfig,
    mju_warning, mjp_defaultPlugin, mjp_registerPlugin and mj_version are at these addresses
    (``hyst.mujoco.load`` takes them with ctypes)."""
    ...
