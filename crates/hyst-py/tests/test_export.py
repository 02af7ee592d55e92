"""Model.export_c / export_rust return exactly what `hyst export c|rust` writes for the same
model file (one generator, crates/hyst-codegen), and bad names raise ValueError."""

import pickle

import pytest

import hyst


@pytest.mark.parametrize("name", ["piezo", "steel", "friction"])
def test_export_c_is_the_cli_text(root, cli, name):
    path = root / "examples" / "firmware" / "models" / f"{name}.toml"
    model = hyst.load_model(str(path))
    text = model.export_c(name)
    assert text == cli("export", "c", str(path), "--name", name).stdout
    assert f"int32_t {name}_init_inverse_f32(" in text
    # A pickled model keeps its source and hash: the same text again.
    assert pickle.loads(pickle.dumps(model)).export_c(name) == text


@pytest.mark.parametrize("name", ["piezo", "piezo_pi"])
def test_export_rust_is_the_cli_text(root, cli, name):
    path = root / "examples" / "firmware" / "models" / f"{name}.toml"
    text = hyst.load_model(str(path)).export_rust(name)
    assert text == cli("export", "rust", str(path), "--name", name).stdout


def test_bad_names_and_kinds_raise_value_error(root):
    models = root / "examples" / "firmware" / "models"
    piezo = hyst.load_model(str(models / "piezo.toml"))
    for bad in ["2axis", "stage-x", "hyst_stage", "double", ""]:
        with pytest.raises(ValueError, match="--name"):
            piezo.export_c(bad)
    with pytest.raises(ValueError, match="Prandtl-Ishlinskii"):
        hyst.load_model(str(models / "piezo_pi.toml")).export_c("pi")


def test_timed_model_exports_are_the_cli_text(root, cli):
    """A model with dynamics: the compensator always, the forward model with its plant with
    period, as `hyst export c|rust [--period]`."""
    path = root / "examples" / "firmware" / "models" / "piezo_dyn.toml"
    model = hyst.load_model(str(path))
    for language, export in [("c", model.export_c), ("rust", model.export_rust)]:
        assert export("stage") == cli("export", language, str(path), "--name", "stage").stdout
        with_period = export("stage", period=1e-3)
        assert with_period == cli(
            "export", language, str(path), "--name", "stage", "--period", "0.001"
        ).stdout
        assert "timed" in with_period
    with pytest.raises(ValueError, match="period"):
        model.export_c("stage", period=float("nan"))
