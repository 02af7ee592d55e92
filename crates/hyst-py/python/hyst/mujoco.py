"""hyst inside MuJoCo: the actuator plugins ``hyst.backlash`` and ``hyst.compensator``.

``hyst.backlash`` is a position servo through the hysteresis: its target is H(k1, k2)[ctrl]
(eq. 2), or the fitted model of ctrl when the config key ``model`` names a model file of
``hyst fit``; the force is kp (target - length) - kv velocity. ``hyst.compensator`` is the same
servo with the exact inverse applied to ctrl first (eq. 4, or the model's inverse): the
feed-forward that cancels the backlash of a real gear. The operator's memory lives in the
actuator's ``actdim="6"`` activations, so ``mj_getState``/``mj_setState``, keyframes and
``mj_resetData`` carry it. See docs/mujoco.md.

>>> import hyst.mujoco, mujoco            # doctest: +SKIP
>>> hyst.mujoco.load()                    # doctest: +SKIP
>>> model = mujoco.MjModel.from_xml_path("arm.xml")   # doctest: +SKIP

``import mujoco`` already registers the plugins when hyst is installed (its ``mujoco.plugins``
entry point calls :func:`load`); calling :func:`load` again is harmless.
"""

import ctypes
import glob
import os

from . import _hyst

__all__ = ["ACTDIM", "NSTATE", "load", "version"]

#: The activations of each hyst actuator (its ``actdim``): the memory of Definition 2.1 as
#: has_history, direction, reversal input, reversal output, last input, last output.
ACTDIM = 6
#: The plugin state of each hyst actuator: its memory after the last step, then the target.
NSTATE = ACTDIM + 1

# The MuJoCo functions the plugins call, in the order of hyst_mujoco_api (hyst_mujoco.h).
_FUNCTIONS = (
    "mj_getPluginConfig",
    "mju_warning",
    "mjp_defaultPlugin",
    "mjp_registerPlugin",
    "mj_version",
)

_loaded = False


def version() -> str:
    """The MuJoCo version the plugins were built for (``"4.0.1"``), or ``""`` when this hyst
    was built without them."""
    v = _hyst._MUJOCO_VERSION
    return f"{v // 1000000}.{v // 1000 % 1000}.{v % 1000}" if v else ""


def _libmujoco(package_dir: str) -> ctypes.CDLL:
    """The libmujoco the ``mujoco`` package loaded (opening it again gives the same one)."""
    for pattern in ("libmujoco.so*", "libmujoco*.dylib", "mujoco.dll"):
        found = sorted(glob.glob(os.path.join(package_dir, pattern)))
        if found:
            return ctypes.CDLL(found[0])
    raise RuntimeError(f"no libmujoco in the mujoco package at {package_dir}")


def load() -> None:
    """Registers ``hyst.backlash`` and ``hyst.compensator`` with the installed MuJoCo.

    Raises ``ImportError`` when the ``mujoco`` package is not installed, and ``RuntimeError``
    when its version is not the one the plugins were built for (MuJoCo plugins are tied to
    the exact libmujoco version) or this hyst was built without them.
    """
    global _loaded
    if _loaded:
        return
    try:
        import mujoco
    except ImportError as e:
        raise ImportError(
            'hyst.mujoco needs the mujoco package: pip install "./crates/hyst-py[mujoco]"'
        ) from e
    built = version()
    have = mujoco.mj_versionString()
    if built and mujoco.mj_version() != _hyst._MUJOCO_VERSION:
        raise RuntimeError(
            f"the hyst MuJoCo plugins were built for MuJoCo {built}, and MuJoCo {have} is "
            f"installed: MuJoCo plugins work only with the version they were built for "
            f"(pip install mujoco=={built}, or reinstall hyst with this MuJoCo)"
        )
    lib = _libmujoco(os.path.dirname(mujoco.__file__))
    addresses = [ctypes.cast(getattr(lib, name), ctypes.c_void_p).value or 0 for name in _FUNCTIONS]
    _hyst._mujoco_register(addresses)
    _loaded = True
