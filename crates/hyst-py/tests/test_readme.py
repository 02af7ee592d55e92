"""The README's Python block runs as written, after the README's `hyst fit` (scripts/test-readme
runs the shell blocks), and gives the numbers `hyst run` gives, as its comment says."""

import re

import numpy as np

from conftest import ROOT, computed

README = ROOT / "README.md"


def python_blocks():
    """The text of every ```python block of README.md, in order."""
    return re.findall(r"^```python[ \t]*\n(.*?)^```[ \t]*$", README.read_text(), re.M | re.S)


def test_readme_python_block_runs(cli, piezo_path, tmp_path, monkeypatch):
    blocks = python_blocks()
    assert blocks, "README.md has no ```python block"
    # The README's tour fits piezo.toml in the directory it works in before the Python block.
    cli("fit", piezo_path, "--input", "u_actuator_V", "--output", "y_capsensor_um",
        "-o", tmp_path / "piezo.toml")
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for i, block in enumerate(blocks):
        exec(compile(block, f"README.md python block {i + 1}", "exec"), namespace)

    # The block's inverse gives the numbers of `hyst run --model piezo.toml --inverse`.
    command = namespace["command"]
    desired = np.linspace(-110.0, -90.0, 100)
    path = tmp_path / "desired.csv"
    path.write_text("y_capsensor_um\n" + "".join(f"{float(v)!r}\n" for v in desired))
    cli("run", "--model", tmp_path / "piezo.toml", "--inverse", path, "-o", tmp_path / "cmd.csv")
    assert np.array_equal(command, computed(tmp_path / "cmd.csv"))
