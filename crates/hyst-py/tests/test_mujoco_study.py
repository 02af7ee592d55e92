"""examples/mujoco/backlash_study.py: hyst.backlash against MuJoCo's two-joint backlash recipe.

The recipe arm has its play in radians, its load stays where the motor leaves it, and `hyst
fit` finds that play; the one-hinge hyst.backlash arm with the fitted model follows the
recipe's load on a held-out motion within 9 % of the play (RMS; 14 % at most), and within 1 %
when the model is fitted on the motor's angle (the servo's lag then counts once); the recipe's
motor under hyst.compensator tracks a reference load trajectory 10 times better (RMS) than
under the plain servo. The cost figures are only checked to be finite: wall-clock ratios are
not asserted on a shared machine."""

import math
import sys

import numpy as np
import pytest

import mujoco  # noqa: E402  (the test venv installs it: requirements-test.txt)

from conftest import ROOT  # noqa: E402

sys.path.insert(0, str(ROOT / "examples" / "mujoco"))
import backlash_study as study  # noqa: E402


@pytest.fixture(scope="module")
def results(hyst_bin, tmp_path_factory):
    return study.run(hyst_bin, tmp_path_factory.mktemp("study"), cost_repeats=5)


def inertia(xml):
    """The joint-space inertia matrix of an arm at rest."""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    full = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, full)
    return full


def test_the_design_figures_of_the_comments():
    recipe = inertia(study.recipe_xml())
    engaged, load = recipe[0, 0], recipe[1, 1] - study.REL_ARMATURE
    assert engaged == pytest.approx(0.0258, abs=5e-5)
    # The plugin arm's one hinge carries what the recipe's servo moves with the play closed.
    assert inertia(study.hinge_xml("position"))[0, 0] == pytest.approx(engaged, rel=1e-12)
    assert load == pytest.approx(0.0158, abs=5e-5)
    assert load / study.LOAD_DAMPING == pytest.approx(0.32, abs=0.005)
    motor = engaged - recipe[0, 1]  # without the load's share
    assert motor == pytest.approx(0.0100, abs=5e-5)
    assert math.sqrt(study.KP / engaged) == pytest.approx(125, abs=1)
    assert study.KV / (2 * math.sqrt(study.KP * engaged)) == pytest.approx(0.93, abs=0.005)
    assert study.KV / (2 * math.sqrt(study.KP * motor)) == pytest.approx(1.5, abs=0.01)
    assert (study.KV + study.LOAD_DAMPING) / study.KP == pytest.approx(0.015, abs=2e-4)
    assert study.LOAD_FRICTION / load == pytest.approx(25, abs=0.5)
    h = study.TIMESTEP
    peaks = {}
    for name, motion in [("training", study.training_motion()), ("held out", study.held_out_motion()),
                         ("reference", study.reference())]:
        speed = np.diff(motion) / h
        assert np.abs(np.diff(speed) / h).max() < 12  # the load's friction stops it faster
        peaks[name] = np.abs(speed).max()
    assert len(study.training_motion()) * h == pytest.approx(37, abs=0.5)
    assert peaks == pytest.approx({"training": 1.2, "held out": 1.3, "reference": 0.9}, abs=0.05)


def test_the_recipe_has_its_play_in_radians():
    model = mujoco.MjModel.from_xml_string(study.recipe_xml())
    assert model.jnt_range[1].tolist() == [-study.PLAY / 2, study.PLAY / 2]
    # Pushed along, the load trails the command by half the play (and the servo's lag); in
    # the middle of a reversal it crosses the play.
    ctrl = study.training_motion()
    gap = ctrl - study.simulate(study.recipe_xml(), ctrl)
    low, high = np.percentile(gap, [5, 95])
    assert 0.05 < high < 0.07 and -0.07 < low < -0.05


def test_hyst_fit_finds_the_play(results):
    fit = study.fitted(results["fit_report"])
    # Half the play, and the servo's lag and the friction's 1 mrad that the fit takes as play.
    assert 0.05 < fit["k1"] < 0.06
    assert fit["k1"] * fit["k2"] > 1e6  # the backlash limit: corners sharper than k1 / 1e6
    assert fit["rms"] < 0.06 * study.PLAY and fit["max"] < 0.15 * study.PLAY


def test_the_plugin_arm_reproduces_the_recipe_on_a_held_out_motion(results):
    rep = results["reproduction"]
    assert rep["error"]["rms_play"] < 0.09 and rep["error"]["max_play"] < 0.14
    # Without the play the load would trail the command by half the play: the model matters.
    assert np.sqrt(np.mean((rep["ctrl"] - rep["recipe"]) ** 2)) > 0.4 * study.PLAY
    # What limits it: the fit's residual and the plugin servo's own lag, both of this size.
    assert 0.03 < rep["model_error"]["rms_play"] < 0.08
    assert 0.05 < rep["servo_lag"]["rms_play"] < 0.12
    # The servo's lag counts twice: the fit took the recipe's into k1, and the plugin's servo
    # adds its own. Fitted on the motor's angle (no lag in the data), k1 is half the play and
    # the plugin arm follows the recipe within 1 % of the play (RMS).
    assert study.fitted(results["motor_fit_report"])["k1"] == pytest.approx(study.PLAY / 2, abs=5e-4)
    assert rep["lag_once_error"]["rms_play"] < 0.01 and rep["lag_once_error"]["max_play"] < 0.06


def test_the_cost_figures_are_finite(results):
    cost = results["cost"]
    assert cost.pop("repeats") == 5 and cost.pop("steps") == 1000
    assert set(cost) == {"plugin_us", "operator_us", "plain_us", "pid_us", "recipe_us", "plugin_over_plain",
                         "plugin_over_recipe", "operator_over_plain", "pid_over_plain"}
    assert all(math.isfinite(v) and v > 0 for v in cost.values())


def test_the_compensator_cuts_the_tracking_error_tenfold(results):
    comp = results["compensation"]
    assert comp["rms_ratio"] > 10 and comp["max_ratio"] > 6
    assert comp["compensated_error"]["rms_play"] < 0.055
    assert comp["plain_error"]["rms_play"] > 0.45  # the plain servo leaves half the play


def test_the_script_prints_every_figure_and_draws_the_plot(tmp_path, hyst_bin, capsys):
    assert study.main(["--out", str(tmp_path), "--hyst", str(hyst_bin)]) == 0
    out = capsys.readouterr().out
    for words in ["MuJoCo " + mujoco.__version__, "k1 = 0.05", "training residual RMS", "hyst.backlash arm - recipe load",
                  "plugin / plain", "plugin / recipe", "plain / compensated: RMS"]:
        assert words in out
    png = tmp_path / "backlash_study.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_figures_docs_mujoco_md_quotes(results):
    """docs/mujoco.md quotes the study's figures rounded as the script prints them: the
    simulation and the fit are deterministic, so they are these."""
    fit = study.fitted(results["fit_report"])
    rep, comp = results["reproduction"], results["compensation"]
    assert (f"{fit['k1']:.4f}", f"{fit['k2']:.3g}", f"{fit['rms'] / study.PLAY:.1%}") == ("0.0571", "1.15e+88", "4.7%")
    assert (f"{rep['error']['rms_play']:.1%}", f"{rep['error']['max_play']:.1%}") == ("6.4%", "10.0%")
    assert f"{study.fitted(results['motor_fit_report'])['k1']:.4f}" == "0.0501"
    assert f"{rep['lag_once_error']['rms_play']:.1%}" == "0.4%"
    assert (f"{comp['compensated_error']['rms_play']:.1%}", f"{comp['plain_error']['rms_play']:.0%}") == ("4.1%", "52%")
    assert (f"{comp['rms_ratio']:.1f}", f"{comp['max_ratio']:.1f}") == ("12.7", "7.8")
