"""The type stubs (_hyst.pyi) describe what the extension module has: every public class,
function and method is in both, so editors and type checkers see the real API."""

import ast
from pathlib import Path

import hyst
from hyst import _hyst

STUB = Path(hyst.__file__).with_name("_hyst.pyi")


def stub_names():
    tree = ast.parse(STUB.read_text())
    classes, functions, constants = {}, set(), set()
    for node in tree.body:
        # A TypedDict describes the keys of a dict a method returns: not a class of the module.
        if isinstance(node, ast.ClassDef) and not any(ast.unparse(b) == "TypedDict" for b in node.bases):
            classes[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
        elif isinstance(node, ast.FunctionDef):
            functions.add(node.name)
        elif isinstance(node, ast.AnnAssign) and not node.target.id.startswith("_"):
            constants.add(node.target.id)
    # Methods the stub puts on the shared base class.
    base = classes.pop("_Operator", set())
    for name in ("Hysteresis", "InverseHysteresis"):
        classes[name] |= base
    return classes, functions, constants


def public(obj):
    return {n for n in dir(obj) if not n.startswith("_")}


def test_stub_matches_module():
    classes, functions, constants = stub_names()
    module_classes = {n for n in public(_hyst) if isinstance(getattr(_hyst, n), type)}
    module_constants = {n for n in public(_hyst) if not callable(getattr(_hyst, n))}
    module_functions = public(_hyst) - module_classes - module_constants
    assert set(classes) == module_classes
    assert constants == module_constants == {"MAX_ORDER"}
    assert functions - {"_bench_core", "_model_from_toml", "_fit_result_from_json", "_mujoco_register"} == module_functions
    for name, methods in classes.items():
        members = public(getattr(_hyst, name))
        assert methods - {"__init__"} == members, name
    assert set(hyst.__all__) == module_classes | module_functions | module_constants | {"__version__"}


def test_py_typed_and_docstrings():
    assert STUB.with_name("py.typed").exists()
    for name in public(_hyst):
        obj = getattr(_hyst, name)
        # A constant's __doc__ is its type's; the stub documents MAX_ORDER.
        assert not callable(obj) or obj.__doc__, f"{name} has no docstring"


def test_examples_type_check_against_the_stubs():
    """mypy --strict on the examples: the stubs describe the API the examples use."""
    import subprocess
    import sys

    from conftest import ROOT

    examples = ROOT / "examples" / "python"
    for files, extra in [
        ([examples / "piezo_compensation.py", examples / "bench.py"], []),
        # dask.distributed has no annotations on Client and LocalCluster.
        ([examples / "fleet_fit.py"], ["--allow-untyped-calls"]),
    ]:
        p = subprocess.run(
            [sys.executable, "-m", "mypy", "--strict", "--no-incremental", *extra, *map(str, files)],
            capture_output=True, text=True,
        )
        assert p.returncode == 0, p.stdout + p.stderr


def test_package_docstring_runs():
    import doctest

    failures, tried = doctest.testmod(hyst)
    assert tried >= 3 and failures == 0
