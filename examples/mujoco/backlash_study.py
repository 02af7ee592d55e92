#!/usr/bin/env python3
"""The hyst.backlash plugin against MuJoCo's two-joint backlash recipe.

    python examples/mujoco/backlash_study.py --out DIR [--hyst PATH]

1. The recipe arm: a motor hinge driven by a plain <position> servo, and a load hinge in a
   child body whose angle relative to the motor is limited to +-PLAY/2 (the gear's play).
2. It is driven with a varied motion; the motor command and the load angle are logged to a
   CSV and `hyst fit` identifies a smooth model (input: the command, output: the load angle).
3. Reproduction: one hinge with the same inertia, driven by hyst.backlash with that model,
   follows a held-out motion; its load angle is compared with the recipe's.
4. Cost: mj_step of the plugin arm, of the same hinge under a plain <position> servo and of
   the recipe arm, timed in one run with interleaved repeats. The plugin's share depends on
   how hyst was built: its C takes the Cargo profile's opt-level, none in a dev-profile
   build (`maturin develop`), so time it in a release build.
5. Compensation: the recipe's motor driven by hyst.compensator (the model's inverse) against
   the plain servo commanded with the reference: the load's tracking error of both.

Every figure is printed; a PNG plots the three arms. The functions are imported by
crates/hyst-py/tests/test_mujoco_study.py, which asserts the figures.
"""

import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np

import mujoco
import hyst.mujoco

hyst.mujoco.load()

ROOT = Path(__file__).resolve().parents[2]

# The gear's play: the load turns freely over 0.1 rad (+-0.05 rad, ~3 degrees) relative to
# the motor, a coarse hobby-servo gear; large enough that the backlash dwarfs the servo's lag.
PLAY = 0.1
# 1 ms: the servo's natural period (below) is 50 steps and a limit impact's time constant 4.
TIMESTEP = 0.001
# The servo on the motor hinge (N m / rad and N m s / rad). With the motor and the load
# engaged (0.0258 kg m^2) kp = 400 gives 125 rad/s (20 Hz), above the motions (<= 1.7 Hz),
# and kv = 6 damps it near critically (zeta 0.93); the motor alone (0.0100 kg m^2) is
# overdamped (zeta 1.5). A PD servo lags a ramp by (kv + damping) / kp = 15 ms: at 1 rad/s
# that is 15 % of the play.
KP = 400.0
KV = 6.0
# The motor's rotor inertia reflected through the gear (armature) and the load's: a 0.5 kg,
# 0.3 m bar (~0.015 kg m^2 about the hinge). The relative hinge gets a small armature so that
# its free motion inside the play is well conditioned.
MOTOR_ARMATURE = 0.01
REL_ARMATURE = 1e-4
# The motor's body: a small disc (its inertia, 5e-5 kg m^2, is next to nothing beside the
# armature; MuJoCo needs a moving body to have mass).
MOTOR = '<geom type="cylinder" size="0.03 0.01" mass="0.1"/>'
LOAD = '<geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="0.5"/>'
# The load's own drag on its absolute motion (a fixed tendon motor + rel): without it the load
# coasts on through the play when the motor slows down and hits the play's far side. Viscous
# damping alone cannot stop it in time (0.0158 kg m^2 / 0.05 N m s = 0.32 s), so the load also
# has Coulomb friction (bearings, seals): 0.4 N m stops it at 25 rad/s^2, above the motions'
# decelerations (<= 12 rad/s^2), so it stays where the motor leaves it; the servo pushes it
# with a steady 0.4 / KP = 1 mrad more error, which the fit takes in as play.
LOAD_DAMPING = 0.05
LOAD_FRICTION = 0.4
# The play's limits: a stiff, critically damped contact (time constant 4 ms = 4 steps).
LIMIT_SOLREF = "0.004 1"

# Angles in radians (MJCF's default unit for a joint's range is the degree).
HEADER = f"""<mujoco>
  <compiler angle="radian"/>
  <option timestep="{TIMESTEP}" integrator="Euler" gravity="0 0 0"/>
"""


def recipe_xml(motor: str = "position", model: Optional[Path] = None) -> str:
    """The two-joint recipe. `motor`: "position" (a plain <position> servo on the motor
    hinge) or "compensator" (hyst.compensator with `model`). The load's absolute angle is
    the fixed tendon `load` = motor + rel, which also carries the load's damping."""
    extension, actuator = _actuator("motor", None if motor == "position" else "hyst.compensator", model)
    return f"""{HEADER}{extension}
  <worldbody><body name="motor">
    <joint name="motor" type="hinge" axis="0 0 1" armature="{MOTOR_ARMATURE}"/>
    {MOTOR}
    <body name="load">
      <joint name="rel" type="hinge" axis="0 0 1" limited="true" range="{-PLAY / 2} {PLAY / 2}"
             armature="{REL_ARMATURE}" solreflimit="{LIMIT_SOLREF}"/>
      {LOAD}
    </body>
  </body></worldbody>
  <tendon><fixed name="load" damping="{LOAD_DAMPING}" frictionloss="{LOAD_FRICTION}">
    <joint joint="motor" coef="1"/><joint joint="rel" coef="1"/>
  </fixed></tendon>
  <actuator>{actuator}</actuator>
</mujoco>"""


def hinge_xml(motor: str = "backlash", model: Optional[Path] = None) -> str:
    """One hinge carrying the motor's and the load's inertia and the load's damping: the
    recipe with its play closed. `motor`: "backlash" (hyst.backlash with `model`) or
    "position" (a plain <position> servo, the cost baseline)."""
    extension, actuator = _actuator("hinge", None if motor == "position" else "hyst.backlash", model)
    return f"""{HEADER}{extension}
  <worldbody><body name="load">
    <joint name="hinge" type="hinge" axis="0 0 1" armature="{MOTOR_ARMATURE}" damping="{LOAD_DAMPING}" frictionloss="{LOAD_FRICTION}"/>
    {MOTOR}
    {LOAD}
  </body></worldbody>
  <actuator>{actuator}</actuator>
</mujoco>"""


def _actuator(joint: str, plugin: Optional[str], model: Optional[Path]) -> Tuple[str, str]:
    """The MJCF extension and actuator that drive `joint`: a plain <position> servo when
    `plugin` is None, else that hyst plugin with `model`, both with the servo's KP and KV."""
    if plugin is None:
        return "", f'<position joint="{joint}" kp="{KP}" kv="{KV}"/>'
    extension = f"""  <extension><plugin plugin="{plugin}"><instance name="gear">
    <config key="model" value="{model}"/><config key="kp" value="{KP}"/><config key="kv" value="{KV}"/>
  </instance></plugin></extension>"""
    return extension, f'<plugin joint="{joint}" plugin="{plugin}" instance="gear" actdim="{hyst.mujoco.ACTDIM}"/>'


def angles(xml: str, ctrl: np.ndarray) -> np.ndarray:
    """Steps the arm through ctrl (one value a step) from rest; its joint angles after each
    step (a row a step; the motor's or the one hinge's first)."""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    out = np.empty((len(ctrl), model.nq))
    for k, c in enumerate(ctrl):
        data.ctrl[0] = c
        mujoco.mj_step(model, data)
        out[k] = data.qpos
    return out


def simulate(xml: str, ctrl: np.ndarray) -> np.ndarray:
    """The load's absolute angle after each step through ctrl. Every arm here is a chain of
    hinges about one axis, so that angle is the sum of its joint angles."""
    return angles(xml, ctrl).sum(axis=1)


def reversals(seed: int, n: int, amplitude: float, speeds=(0.2, 0.8)) -> np.ndarray:
    """A motion through n reversal points at random levels within +-amplitude (alternating
    up and down, swings of at least PLAY), joined by half-cosines at random mean speeds
    (rad/s; each at least 0.3 s long): zero speed at each reversal, the peak speed pi / 2
    times the mean."""
    rng = np.random.default_rng(seed)
    levels = [0.0]
    for k in range(n):
        up = k % 2 == 0
        lo, hi = (levels[-1] + PLAY, amplitude) if up else (-amplitude, levels[-1] - PLAY)
        levels.append(rng.uniform(lo, hi) if hi > lo else (amplitude if up else -amplitude))
    pieces = []
    for a, b in zip(levels[:-1], levels[1:]):
        steps = int(max(abs(b - a) / rng.uniform(*speeds), 0.3) / TIMESTEP)
        s = np.arange(1, steps + 1) / steps
        pieces.append(a + (b - a) * (1 - np.cos(np.pi * s)) / 2)
    return np.concatenate(pieces)


def training_motion() -> np.ndarray:
    """The motion the model is fitted on: 40 reversals within +-0.6 rad, swings from the play
    to 1.2 rad at mean speeds of 0.2 to 0.8 rad/s (37 s, peak speed 1.2 rad/s)."""
    return reversals(seed=1, n=40, amplitude=0.6)


def two_sines(seconds: float, a: float, fa: float, b: float, fb: float) -> np.ndarray:
    """a sin(2 pi fa t) + b sin(2 pi fb t), faded in over its first second (a half-cosine)
    so that it starts from rest, as the arms do."""
    t = np.arange(1, int(seconds / TIMESTEP) + 1) * TIMESTEP
    fade = 0.5 * (1 - np.cos(np.pi * np.minimum(t, 1.0)))
    return fade * (a * np.sin(2 * np.pi * fa * t) + b * np.sin(2 * np.pi * fb * t))


def held_out_motion() -> np.ndarray:
    """The reproduction's motion, of another kind than the training one: two sines (0.3 and
    0.8 Hz, peak speed 1.3 rad/s) for 15 s, whose sum reverses at ever other places and draws
    minor loops inside the large ones."""
    return two_sines(15.0, 0.35, 0.3, 0.12, 0.8)


def reference() -> np.ndarray:
    """The load trajectory the compensation tracks for 12 s: smooth, reversing at various
    places (0.25 and 0.7 Hz, peak speed 0.9 rad/s)."""
    return two_sines(12.0, 0.3, 0.25, 0.1, 0.7)


def write_log(path: Path, x: np.ndarray, load: np.ndarray, name: str = "command", every: int = 5) -> None:
    """The CSV `hyst fit` reads: time, the input `name` (the motor command) and the load
    angle, every `every`-th step (5 ms: the motions are slow, and the fit then takes a
    fraction of a second)."""
    with open(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["t", name, "load"])
        for k in range(every - 1, len(x), every):
            out.writerow([f"{(k + 1) * TIMESTEP:.6g}", repr(float(x[k])), repr(float(load[k]))])


def fit_model(hyst_bin: Path, data: Path, model: Path, name: str = "command") -> str:
    """Fits the smooth model load = H[`name`] with `hyst fit`; returns its report (JSON). The
    start rule `line` is the recipe's start: the load in the middle of the play."""
    done = subprocess.run(
        [str(hyst_bin), "fit", str(data), "--input", name, "--output", "load", "--json",
         "--initial-state", "line", "--input-unit", "rad", "--output-unit", "rad", "-o", str(model)],
        check=True, capture_output=True, text=True,
    )
    return done.stdout


def stats(error: np.ndarray) -> Dict[str, float]:
    """RMS and max of |error|, in rad and as shares of the play."""
    rms, peak = float(np.sqrt(np.mean(error**2))), float(np.max(np.abs(error)))
    return {"rms": rms, "max": peak, "rms_play": rms / PLAY, "max_play": peak / PLAY}


def reproduction(model: Path, motor_model: Path) -> Dict[str, object]:
    """The recipe and the plugin arm on the held-out motion. The plugin's error splits into
    the model's (its output for the command against the recipe's load: the fit's residual)
    and the plugin servo's (its hinge against its target: the servo's lag, which the recipe
    has too and the fit has already taken in, so it counts twice). `motor_model`, fitted on
    the recipe's motor angle instead of its command (the servo's lag left out), shows what
    the plugin arm reaches when the lag counts once."""
    ctrl = held_out_motion()
    recipe = simulate(recipe_xml(), ctrl)
    plugin = simulate(hinge_xml("backlash", model), ctrl)
    target = hyst.load_model(str(model)).process(ctrl)
    once = simulate(hinge_xml("backlash", motor_model), ctrl)
    return {
        "ctrl": ctrl, "recipe": recipe, "plugin": plugin, "plugin_lag_once": once,
        "error": stats(plugin - recipe), "model_error": stats(target - recipe),
        "servo_lag": stats(plugin - target), "lag_once_error": stats(once - recipe),
    }


def cost(model: Path, steps: int = 1000, repeats: int = 60, chunk: int = 10) -> Dict[str, float]:
    """Microseconds per mj_step of the plugin arm (with the fitted model, and with the bare
    operator H(PLAY / 2, 200) for comparison), the same hinge under a plain <position> servo
    and under MuJoCo's own actuator plugin mujoco.pid (what any actuator plugin costs), and
    the recipe arm, each the median over `repeats` runs of `steps` steps of the thread's
    CPU time. The arms take turns within each repeat (in a rotating order), and each ratio is
    the median of the repeats' own ratios: a slow spell of a shared machine hits both arms of
    a ratio alike. The command is a 1 Hz sine, set every `chunk` steps (mj_step's nstep keeps
    Python's share of the time small)."""
    plugin = hinge_xml("backlash", model)
    operator = f'<config key="k1" value="{PLAY / 2}"/><config key="k2" value="200"/>'
    pid = plugin.replace(f'<config key="model" value="{model}"/>', "").replace('key="kv"', 'key="kd"')
    arms = {
        "plugin": plugin,
        "operator": plugin.replace(f'<config key="model" value="{model}"/>', operator),
        "plain": hinge_xml("position"),
        "pid": pid.replace("hyst.backlash", "mujoco.pid").replace(f'actdim="{hyst.mujoco.ACTDIM}"', 'actdim="0"'),
        "recipe": recipe_xml(),
    }
    runs = []
    for xml in arms.values():
        m = mujoco.MjModel.from_xml_string(xml)
        runs.append((m, mujoco.MjData(m)))
    ctrl = 0.3 * np.sin(2 * np.pi * np.arange(0, steps, chunk) * TIMESTEP)
    us = np.empty((repeats, len(runs)))
    for r in range(repeats):
        for k in np.roll(np.arange(len(runs)), r):
            m, d = runs[k]
            mujoco.mj_resetData(m, d)
            start = time.thread_time()
            for c in ctrl:
                d.ctrl[0] = c
                mujoco.mj_step(m, d, nstep=chunk)
            us[r, k] = (time.thread_time() - start) / steps * 1e6
    col = {name: us[:, k] for k, name in enumerate(arms)}
    return {
        **{f"{name}_us": float(np.median(t)) for name, t in col.items()},
        "plugin_over_plain": float(np.median(col["plugin"] / col["plain"])),
        "plugin_over_recipe": float(np.median(col["plugin"] / col["recipe"])),
        "operator_over_plain": float(np.median(col["operator"] / col["plain"])),
        "pid_over_plain": float(np.median(col["pid"] / col["plain"])),
        "repeats": repeats, "steps": steps,
    }


def compensation(model: Path) -> Dict[str, object]:
    """The recipe arm tracking the reference load trajectory: its motor under the plain
    <position> servo commanded with the reference, and under hyst.compensator (the servo's
    target is the model's inverse of the reference). The load's tracking error of both."""
    ref = reference()
    plain = simulate(recipe_xml(), ref)
    compensated = simulate(recipe_xml("compensator", model), ref)
    out = {"reference": ref, "plain": plain, "compensated": compensated,
           "plain_error": stats(plain - ref), "compensated_error": stats(compensated - ref)}
    out["rms_ratio"] = out["plain_error"]["rms"] / out["compensated_error"]["rms"]
    out["max_ratio"] = out["plain_error"]["max"] / out["compensated_error"]["max"]
    return out


def plot(rep: Dict[str, object], comp: Dict[str, object], path: Path) -> None:
    """Left: the recipe and the plugin arm on the held-out motion, and the plugin's error.
    Right: the recipe arm tracking the reference under the plain servo and under
    hyst.compensator, and their tracking errors. Errors in shares of the play."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(14, 7.5), sharex="col", gridspec_kw={"height_ratios": [3, 2]})
    t = np.arange(1, len(rep["ctrl"]) + 1) * TIMESTEP
    ax[0, 0].plot(t, rep["ctrl"], color="0.7", lw=1, label="motor command")
    ax[0, 0].plot(t, rep["recipe"], lw=2, label="recipe load (two joints, play)")
    ax[0, 0].plot(t, rep["plugin"], "--", lw=1.5, label="hyst.backlash arm (one joint)")
    ax[0, 0].set(title="Reproduction on a held-out motion", ylabel="angle (rad)")
    ax[1, 0].plot(t, (rep["plugin"] - rep["recipe"]) / PLAY, label="hyst.backlash - recipe")
    ax[1, 0].plot(t, (rep["plugin_lag_once"] - rep["recipe"]) / PLAY, label="the same, fitted on the motor's angle")
    ax[1, 0].set(xlabel="time (s)", ylabel="error / play")
    t = np.arange(1, len(comp["reference"]) + 1) * TIMESTEP
    ax[0, 1].plot(t, comp["reference"], color="0.3", lw=1, label="reference")
    ax[0, 1].plot(t, comp["plain"], lw=1.5, label="recipe load, plain servo")
    ax[0, 1].plot(t, comp["compensated"], "--", lw=1.5, label="recipe load, hyst.compensator")
    ax[0, 1].set(title="Compensation of the recipe's play", ylabel="load angle (rad)")
    ax[1, 1].plot(t, (comp["plain"] - comp["reference"]) / PLAY, label="plain servo")
    ax[1, 1].plot(t, (comp["compensated"] - comp["reference"]) / PLAY, label="hyst.compensator")
    ax[1, 1].set(xlabel="time (s)", ylabel="tracking error / play")
    for a in ax.flat:
        a.grid(alpha=0.3)
        a.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run(hyst_bin: Path, out: Path, cost_repeats: int = 60) -> Dict[str, object]:
    """The whole study in `out`: the training log and model, reproduction, cost and
    compensation figures."""
    out.mkdir(parents=True, exist_ok=True)
    ctrl = training_motion()
    q = angles(recipe_xml(), ctrl)
    data, model = out / "recipe_training.csv", out / "recipe_backlash.toml"
    write_log(data, ctrl, q.sum(axis=1))
    report = fit_model(hyst_bin, data, model)
    motor_data, motor_model = out / "recipe_training_motor.csv", out / "recipe_backlash_motor.toml"
    write_log(motor_data, q[:, 0], q.sum(axis=1), name="motor")
    motor_report = fit_model(hyst_bin, motor_data, motor_model, name="motor")
    return {
        "model": model, "fit_report": report, "training_seconds": len(ctrl) * TIMESTEP,
        "motor_fit_report": motor_report,
        "reproduction": reproduction(model, motor_model), "cost": cost(model, repeats=cost_repeats),
        "compensation": compensation(model),
    }


def fitted(report: str) -> Dict[str, float]:
    """k1 and k2 in input units (rad, 1/rad) and the training residual's RMS and max (rad)
    from the JSON report of `hyst fit --json`."""
    fit = json.loads(report)
    training = fit["model"]["metrics"]["training"]
    return {"k1": fit["k1_input"], "k2": fit["k2_input"], "rms": training["rms"], "max": training["max_abs"]}


def describe(results: Dict[str, object]) -> List[str]:
    """The study's figures as lines of text."""
    rep, c, comp = results["reproduction"], results["cost"], results["compensation"]
    fit = fitted(results["fit_report"])

    def err(s: Dict[str, float]) -> str:
        return f"RMS {s['rms']:.4f} rad ({s['rms_play']:.1%} of the play), max {s['max']:.4f} rad ({s['max_play']:.1%})"

    return [
        f"MuJoCo {mujoco.__version__}, play {PLAY} rad, timestep {TIMESTEP} s, servo kp {KP} kv {KV}",
        f"fit on {results['training_seconds']:.1f} s of the recipe ({results['model']}):",
        f"  k1 = {fit['k1']:.4f} rad (half the play is {PLAY / 2}), k2 = {fit['k2']:.3g} 1/rad",
        f"  training residual RMS {fit['rms']:.4f} rad ({fit['rms'] / PLAY:.1%} of the play), "
        f"max {fit['max']:.4f} rad ({fit['max'] / PLAY:.1%})",
        "reproduction (held-out motion, 15 s), hyst.backlash arm - recipe load:",
        f"  {err(rep['error'])}",
        f"  the model's output - recipe load:  {err(rep['model_error'])}",
        f"  the plugin's hinge - its target:   {err(rep['servo_lag'])}",
        f"  fitted on the motor's angle (k1 = {fitted(results['motor_fit_report'])['k1']:.4f} rad; "
        f"the servo's lag counted once): {err(rep['lag_once_error'])}",
        f"cost per mj_step (CPU time, median of {c['repeats']} interleaved runs of {c['steps']} steps):",
        f"  hyst.backlash arm {c['plugin_us']:.2f} us (bare operator {c['operator_us']:.2f} us), "
        f"plain <position> {c['plain_us']:.2f} us, mujoco.pid {c['pid_us']:.2f} us, recipe {c['recipe_us']:.2f} us",
        f"  plugin / plain {c['plugin_over_plain']:.2f} (operator / plain {c['operator_over_plain']:.2f}, "
        f"mujoco.pid / plain {c['pid_over_plain']:.2f}), plugin / recipe {c['plugin_over_recipe']:.2f}",
        "compensation (reference 12 s), recipe load - reference:",
        f"  plain servo:      {err(comp['plain_error'])}",
        f"  hyst.compensator: {err(comp['compensated_error'])}",
        f"  plain / compensated: RMS {comp['rms_ratio']:.1f}x, max {comp['max_ratio']:.1f}x",
    ]


def default_hyst() -> Path:
    """$HYST_BIN, else `hyst` on the PATH, else this checkout's release build."""
    found = os.environ.get("HYST_BIN") or shutil.which("hyst")
    return Path(found) if found else ROOT / "target" / "release" / "hyst"


def main(argv: Optional[List[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=Path("."), help="directory for the CSV, model and PNG")
    p.add_argument("--hyst", type=Path, default=None, help="the hyst CLI (default: $HYST_BIN, hyst on PATH)")
    args = p.parse_args(argv)
    results = run(args.hyst or default_hyst(), args.out)
    print("\n".join(describe(results)))
    png = args.out / "backlash_study.png"
    plot(results["reproduction"], results["compensation"], png)
    print(f"wrote {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
