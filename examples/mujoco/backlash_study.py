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
   the recipe arm, timed in one run with interleaved repeats.
5. Compensation: the recipe's motor driven by hyst.compensator (the model's inverse) against
   the plain servo commanded with the reference: the load's tracking error of both.

Every figure is printed; a PNG plots the three arms. The functions are imported by
crates/hyst-py/tests/test_mujoco_study.py, which asserts the figures.
"""

import argparse
import csv
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Dict, List, Optional

import numpy as np

import mujoco
import hyst.mujoco

hyst.mujoco.load()

ROOT = Path(__file__).resolve().parents[2]

# The gear's play: the load turns freely over 0.1 rad (+-0.05 rad, ~3 degrees) relative to
# the motor, a coarse hobby-servo gear; large enough that the backlash dwarfs the servo's lag.
PLAY = 0.1
# 1 ms: the servo's natural period (below) is ~60 steps and a limit impact ~4 steps.
TIMESTEP = 0.001
# The servo on the motor hinge (N m / rad and N m s / rad). With the motor and load inertia
# engaged (~0.025 kg m^2) kp = 400 gives 126 rad/s (20 Hz), well above the motions (<= 1 Hz),
# and kv = 6 damps it near critically (zeta ~ 0.95); the motor alone (0.01 kg m^2) is
# overdamped. A PD servo lags a ramp by (kv + damping) / kp = 15 ms: at 1 rad/s that is 15 %
# of the play, the price of the servo the plugin reproduces.
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
# damping alone cannot stop it in time (0.015 kg m^2 / 0.05 N m s = 0.3 s), so the load also
# has Coulomb friction (bearings, seals): 0.4 N m stops it at 27 rad/s^2, above the motions'
# decelerations (<= 14 rad/s^2), so it stays where the motor leaves it; the servo pushes it
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
    if motor == "position":
        extension = ""
        actuator = f'<position joint="motor" kp="{KP}" kv="{KV}"/>'
    else:
        extension = _extension("hyst.compensator", model)
        actuator = f'<plugin joint="motor" plugin="hyst.compensator" instance="gear" actdim="{hyst.mujoco.ACTDIM}"/>'
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
    if motor == "position":
        extension = ""
        actuator = f'<position joint="hinge" kp="{KP}" kv="{KV}"/>'
    else:
        extension = _extension("hyst.backlash", model)
        actuator = f'<plugin joint="hinge" plugin="hyst.backlash" instance="gear" actdim="{hyst.mujoco.ACTDIM}"/>'
    return f"""{HEADER}{extension}
  <worldbody><body name="load">
    <joint name="hinge" type="hinge" axis="0 0 1" armature="{MOTOR_ARMATURE}" damping="{LOAD_DAMPING}" frictionloss="{LOAD_FRICTION}"/>
    {MOTOR}
    {LOAD}
  </body></worldbody>
  <actuator>{actuator}</actuator>
</mujoco>"""


def _extension(plugin: str, model: Path) -> str:
    return f"""  <extension><plugin plugin="{plugin}"><instance name="gear">
    <config key="model" value="{model}"/><config key="kp" value="{KP}"/><config key="kv" value="{KV}"/>
  </instance></plugin></extension>"""


def simulate(xml: str, ctrl: np.ndarray) -> np.ndarray:
    """Steps the arm through ctrl (one value a step) from rest; the load's absolute angle
    after each step. Every arm here is a chain of hinges about one axis, so that angle is
    the sum of its joint angles."""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    load = np.empty(len(ctrl))
    for k, c in enumerate(ctrl):
        data.ctrl[0] = c
        mujoco.mj_step(model, data)
        load[k] = data.qpos.sum()
    return load


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
