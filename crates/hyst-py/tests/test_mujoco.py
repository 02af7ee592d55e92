"""hyst.mujoco: the actuator plugins hyst.backlash and hyst.compensator inside MuJoCo.

Their targets through mj_step equal `hyst run` on the same ctrl samples bit for bit (the
operator H(k1, k2), its inverse, a fitted model and its inverse); a state saved with
mj_getState resumes exactly, mj_resetData starts afresh; bad configs are refused with a
warning that names the key; a MuJoCo of another version is refused."""

import ctypes

import numpy as np
import pytest

import mujoco  # the test venv installs it (requirements-test.txt)
import hyst  # noqa: E402
import hyst.mujoco  # noqa: E402

from conftest import ROOT, computed  # noqa: E402

TANH_MODEL = ROOT / "crates" / "hyst-model" / "testdata" / "tanh-input.toml"


def arm(plugin="hyst.backlash", config=None, actdim=hyst.mujoco.ACTDIM, integrator="Euler", extra=""):
    """An MJCF of one hinge driven by a hyst actuator plugin."""
    config = {"k1": 0.1, "k2": 20, "kp": 50, "kv": 2} if config is None else config
    keys = "\n".join(f'<config key="{k}" value="{v}"/>' for k, v in config.items())
    return f"""<mujoco>
  <option timestep="0.001" integrator="{integrator}"/>
  <extension><plugin plugin="{plugin}"><instance name="gear">{keys}</instance></plugin></extension>
  <worldbody><body>
    <joint name="hinge" type="hinge" axis="0 0 1" damping="0.1"/>
    <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="0.5"/>
  </body></worldbody>
  <actuator><plugin joint="hinge" plugin="{plugin}" instance="gear" actdim="{actdim}" {extra}/></actuator>
</mujoco>"""


def targets(model, data, ctrl):
    """Steps through ctrl; the target of each step (plugin_state's last value)."""
    out = np.empty(len(ctrl))
    for k, c in enumerate(ctrl):
        data.ctrl[0] = c
        mujoco.mj_step(model, data)
        out[k] = data.plugin_state[hyst.mujoco.NSTATE - 1]
    return out


def ctrl_signal(n=2500, amplitude=0.5):
    t = np.arange(n) * 1e-3
    return amplitude * np.sin(2 * np.pi * 1.3 * t) * (0.4 + 0.6 * np.cos(2 * np.pi * 0.31 * t))


def hyst_run(cli, tmp_path, x, *flags):
    path = tmp_path / "ctrl.csv"
    np.savetxt(path, x, header="x", comments="", fmt="%.17g")
    out = tmp_path / "run.csv"
    cli("run", *flags, "--column", "x", path, "-o", out)
    return computed(out)


def test_load_registers_the_plugins_of_this_mujoco_version():
    assert hyst.mujoco.version() == mujoco.mj_versionString()
    hyst.mujoco.load()
    hyst.mujoco.load()  # again: harmless
    mujoco.MjModel.from_xml_string(arm())


@pytest.mark.parametrize("plugin, inverse", [("hyst.backlash", []), ("hyst.compensator", ["--inverse"])])
def test_targets_equal_hyst_run_bit_for_bit(cli, tmp_path, plugin, inverse):
    x = ctrl_signal()
    model = mujoco.MjModel.from_xml_string(arm(plugin))
    got = targets(model, mujoco.MjData(model), x)
    want = hyst_run(cli, tmp_path, x, "--k1", 0.1, "--k2", 20, *inverse)
    assert got.tobytes() == want.tobytes()
    # The activations hold the operator's memory: the last output is the last target.
    data = mujoco.MjData(model)
    targets(model, data, x[:10])
    assert data.act[0] == 1 and data.act[5] == want[9]


@pytest.mark.parametrize("plugin, inverse", [("hyst.backlash", []), ("hyst.compensator", ["--inverse"])])
def test_a_fitted_model_runs_bit_for_bit(cli, tmp_path, plugin, inverse):
    x = ctrl_signal(amplitude=1.5)
    if inverse:
        x = hyst.load_model(str(TANH_MODEL)).process(x)  # desired outputs the model reaches
    config = {"model": TANH_MODEL, "kp": 50, "kv": 2}
    model = mujoco.MjModel.from_xml_string(arm(plugin, config))
    got = targets(model, mujoco.MjData(model), x)
    want = hyst_run(cli, tmp_path, x, "--model", TANH_MODEL, *inverse)
    assert got.tobytes() == want.tobytes()


@pytest.mark.parametrize("config", [{"k1": 0.1, "k2": 20, "kp": 50, "kv": 2}, {"model": TANH_MODEL, "kp": 50}])
def test_saved_state_resumes_and_reset_starts_afresh(config):
    x = ctrl_signal(amplitude=1.2)
    model = mujoco.MjModel.from_xml_string(arm("hyst.backlash", config))
    whole = targets(model, mujoco.MjData(model), x)
    spec = mujoco.mjtState.mjSTATE_INTEGRATION
    for cut in (1, 333, 1500):
        data = mujoco.MjData(model)
        first = targets(model, data, x[:cut])
        state = np.empty(mujoco.mj_stateSize(model, spec))
        mujoco.mj_getState(model, data, state, spec)
        targets(model, data, -x[cut:])  # go elsewhere, then come back to the saved state
        other = mujoco.MjData(model)  # and resume in another mjData as well
        for d in (data, other):
            mujoco.mj_setState(model, d, state, spec)
            rest = targets(model, d, x[cut:])
            assert np.concatenate([first, rest]).tobytes() == whole.tobytes()
    data = mujoco.MjData(model)
    targets(model, data, x[:700])
    mujoco.mj_resetData(model, data)
    assert not data.act.any()
    assert targets(model, data, x).tobytes() == whole.tobytes()


@pytest.mark.parametrize(
    "xml, words",
    [
        (arm(config={"k1": 0.1, "k2": 20}), "config kp"),
        (arm(config={"k1": 0.1, "k2": 20, "kp": "fast"}), 'kp = "fast" is not a finite number'),
        (arm(config={"k1": 0.1, "k2": 20, "kp": 5, "kv": -1}), "kv = -1"),
        (arm(config={"k1": 0.1, "kp": 5}), "give either k1 and k2"),
        (arm(config={"k1": 0.1, "k2": 20, "kp": 5, "model": TANH_MODEL}), "give either k1 and k2"),
        (arm(config={"k1": -0.1, "k2": 20, "kp": 5}), "k1 = -0.1"),
        (arm(config={"model": "/nonexistent/gear.toml", "kp": 5}), "/nonexistent/gear.toml"),
        (arm(actdim=2), 'add actdim="6"'),
        (arm(integrator="RK4"), "RK4"),
        (arm(extra='dyntype="filter" dynprm="0.1"'), "no dyntype"),
    ],
)
def test_bad_config_is_refused_with_its_reason(xml, words):
    # MuJoCo's error names the failed init, then the plugin's warning: the reason.
    with pytest.raises(ValueError, match="init failed") as refused:
        mujoco.MjModel.from_xml_string(xml)
    assert words in str(refused.value)


def test_a_model_with_dynamics_is_refused(tmp_path):
    text = TANH_MODEL.read_text()
    path = tmp_path / "timed.toml"
    path.write_text(text.replace("version = 3", "version = 4") + "\n[dynamics]\na = [0.01, 1.0]\nb = 1.0\n")
    with pytest.raises(ValueError, match="init failed") as refused:
        mujoco.MjModel.from_xml_string(arm(config={"model": path, "kp": 5}))
    assert "timed.toml" in str(refused.value) and "dynamics" in str(refused.value)


def test_a_prandtl_ishlinskii_model_is_refused(cli, root, tmp_path):
    path = tmp_path / "pi.toml"
    cli("fit", root / "data/piezo-sine/piezo_sine_1hz.csv", "--input", "u_actuator_V", "--output", "y_capsensor_um",
        "--model-kind", "prandtl-ishlinskii", "-o", path)
    with pytest.raises(ValueError, match="init failed") as refused:
        mujoco.MjModel.from_xml_string(arm(config={"model": path, "kp": 5}))
    assert "pi.toml is a Prandtl-Ishlinskii model" in str(refused.value)


def test_another_mujoco_version_is_refused(monkeypatch):
    # The C side: a libmujoco whose mj_version() is not the headers' version.
    version = ctypes.CFUNCTYPE(ctypes.c_int)(lambda: 3002001)
    addresses = [1, 1, 1, 1, ctypes.cast(version, ctypes.c_void_p).value]
    with pytest.raises(RuntimeError, match=r"built against MuJoCo 4\.0\.1.*loaded is 3\.2\.1"):
        hyst._hyst._mujoco_register(addresses)
    with pytest.raises(RuntimeError, match="missing"):
        hyst._hyst._mujoco_register([0, 0, 0, 0, 0])
    # hyst.mujoco.load() checks first, naming both versions.
    monkeypatch.setattr(hyst.mujoco, "_loaded", False)
    monkeypatch.setattr(mujoco, "mj_version", lambda: 3002001)
    with pytest.raises(RuntimeError, match=r"built for MuJoCo 4\.0\.1"):
        hyst.mujoco.load()


def test_the_c_plugin_library_runs_bit_for_bit(cli, tmp_path):
    """The plugin library for C and C++ programs, built as docs/mujoco.md shows (warnings as
    errors, under AddressSanitizer and UndefinedBehaviorSanitizer), loaded by a C program with
    mj_loadPluginLibrary: its targets equal `hyst run` too."""
    import os
    import subprocess

    capi = ROOT / "target" / "release" / "libhyst.so"
    if not capi.exists():
        pytest.fail(f"{capi}: missing; run `cargo build --release -p hyst-capi`")
    mj = os.path.dirname(mujoco.__file__)
    libmujoco = sorted(p for p in os.listdir(mj) if p.startswith("libmujoco.so"))[0]
    flags = ["-std=c11", "-g", "-Wall", "-Wextra", "-Werror", "-fsanitize=address,undefined",
             "-fno-sanitize-recover=all", f"-I{mj}/include", f"-I{ROOT}/include",
             f"-I{ROOT}/crates/hyst-capi/mujoco"]
    plugin = tmp_path / "libhyst_mujoco.so"
    subprocess.run(["cc", *flags, "-fPIC", "-shared", "-DHYST_MUJOCO_LIBRARY",
                    ROOT / "crates/hyst-capi/mujoco/hyst_mujoco.c", "-o", plugin,
                    f"-L{capi.parent}", "-lhyst", f"{mj}/{libmujoco}",
                    f"-Wl,-rpath,{capi.parent}", f"-Wl,-rpath,{mj}"], check=True)
    program = tmp_path / "step_arm"
    subprocess.run(["cc", *flags, ROOT / "examples/mujoco/step_arm.c", "-o", program,
                    f"{mj}/{libmujoco}", f"-Wl,-rpath,{mj}"], check=True)
    x = ctrl_signal(1000)
    for plugin_name, flags_run in (("hyst.backlash", []), ("hyst.compensator", ["--inverse"])):
        xml = tmp_path / "arm.xml"
        xml.write_text(arm(plugin_name))
        env = dict(os.environ, ASAN_OPTIONS="detect_leaks=1", UBSAN_OPTIONS="halt_on_error=1")
        run = subprocess.run([program, plugin, xml], input="\n".join(f"{v:.17g}" for v in x),
                             capture_output=True, text=True, env=env, check=True)
        got = np.array([float(v) for v in run.stdout.split()])
        want = hyst_run(cli, tmp_path, x, "--k1", 0.1, "--k2", 20, *flags_run)
        assert got.tobytes() == want.tobytes(), plugin_name


def test_finite_differences_see_the_memory_and_change_nothing():
    model = mujoco.MjModel.from_xml_string(arm())
    data = mujoco.MjData(model)
    targets(model, data, ctrl_signal(400))
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    before = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, before, spec)
    nx = 2 * model.nv + model.na
    a, b = np.zeros((nx, nx)), np.zeros((nx, model.nu))
    mujoco.mjd_transitionFD(model, data, 1e-6, True, a, b, None, None)
    after = np.empty_like(before)
    mujoco.mj_getState(model, data, after, spec)
    assert after.tobytes() == before.tobytes()
    assert np.isfinite(a).all() and np.isfinite(b).all()
    # The next memory's last input is ctrl itself, and its last output (the target) moves with
    # ctrl: d act_last_input / d ctrl = 1, and the joint is pulled along.
    last_input = 2 * model.nv + 4
    assert b[last_input, 0] == pytest.approx(1.0, rel=1e-6)
    assert b[2 * model.nv + 5, 0] != 0


def test_a_keyframe_holds_the_memory(tmp_path):
    """A keyframe's act is the operator's memory: resetting to it resumes the run (the MJCF
    read from a file, as mujoco.MjModel.from_xml_path reads a user's)."""
    x = ctrl_signal(1200)
    base = mujoco.MjModel.from_xml_string(arm())
    whole = targets(base, mujoco.MjData(base), x)
    data = mujoco.MjData(base)
    targets(base, data, x[:500])
    key = (f'<keyframe><key qpos="{float(data.qpos[0])!r}" qvel="{float(data.qvel[0])!r}" '
           f'act="{" ".join(repr(float(a)) for a in data.act)}"/></keyframe>')
    path = tmp_path / "arm.xml"
    path.write_text(arm().replace("</mujoco>", key + "\n</mujoco>"))
    model = mujoco.MjModel.from_xml_path(str(path))
    resumed = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, resumed, 0)
    assert resumed.act.tobytes() == data.act.tobytes()
    assert targets(model, resumed, x[500:]).tobytes() == whole[500:].tobytes()
