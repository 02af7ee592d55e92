"""hyst: the smooth parametric hysteresis operator, its exact inverse, families with their
guaranteed error bound, Lemma 5.1 compensation and identification from measured data, with
numpy arrays in and out.

The operator is the paper's eq. (2), u = H(k1, k2)[v], with the memory of Definition 2.1;
its inverse is eq. (4). Everything runs in the Rust core (the same code as the ``hyst``
command line, the C API and the FMU), so results are bit-identical across them.

>>> import numpy as np, hyst
>>> v = np.sin(np.linspace(0, 6.3, 100))
>>> u = hyst.Hysteresis(0.2, 8.0).process(v)             # u = H[v]
>>> back = hyst.InverseHysteresis(0.2, 8.0).process(u)   # the exact inverse gives v back
>>> bool(np.max(np.abs(back - v)) < 1e-12)
True

``hyst.control.iosys(obj, dt)`` makes an operator or a fitted model a python-control system
(the optional dependency ``pip install "hyst[control]"``). See docs/python.md for the guide.
"""

from ._hyst import (
    MAX_ORDER,
    Adaptive,
    Bank,
    Compensator,
    Family,
    FitResult,
    Hysteresis,
    InverseHysteresis,
    Memory,
    Model,
    __version__,
    fit,
    load_model,
)
from . import control as control  # needs python-control only when iosys is called

__all__ = [
    "Adaptive",
    "Bank",
    "Compensator",
    "Family",
    "FitResult",
    "Hysteresis",
    "InverseHysteresis",
    "MAX_ORDER",
    "Memory",
    "Model",
    "__version__",
    "fit",
    "load_model",
]
