"""hyst.Family (Definition 2.8, Proposition 3.2) and hyst.Compensator (Lemma 5.1)."""

import pickle

import numpy as np
import pytest

import hyst


def test_example_1_bound():
    f = hyst.Family(0.14, 0.1, 8.0, 5.0)
    # The paper's Example 1: delta_a = 0.1301 (docs/errata.md), corners of eq. (13).
    assert abs(f.delta_a - 0.1301) < 5e-5
    assert abs(f.corners[0] + 0.1131) < 5e-5
    assert f.corner_params[0] == (0.14 - 0.1, 8.0 - 5.0)
    assert max(abs(c) for c in f.corners) == pytest.approx(f.delta_a)
    assert f.bound()["delta_a"] == f.delta_a
    assert pickle.loads(pickle.dumps(f)).delta_a == f.delta_a
    assert repr(f) == "Family(k1=0.14, dk1=0.1, k2=8.0, dk2=5.0)"


def test_bound_holds_for_members():
    f = hyst.Family(0.2, 0.05, 6.0, 2.0)
    ud = 1.3 * np.sin(np.linspace(0, 30, 6000)) * np.cos(np.linspace(0, 7, 6000))
    nominal = f.inverse_member(0, 0).process(ud)
    for a in (-1.0, 0.0, 1.0):
        for b in (-1.0, 0.5, 1.0):
            m = f.member(a, b)
            assert m.k1 == pytest.approx(0.2 + a * 0.05) and m.k2 == pytest.approx(6.0 + b * 2.0)
            member_inverse = m.inverse().process(ud)
            assert np.max(np.abs(member_inverse - nominal)) <= f.delta_a * (1 + 1e-9)
    lower, upper = f.envelope(ud)
    y = f.nominal().process(ud)
    assert np.all(lower <= y) and np.all(y <= upper)
    with pytest.raises(ValueError, match="member"):
        f.member(2.0, 0.0)


def test_inverse_member_is_the_members_inverse():
    f = hyst.Family(0.2, 0.05, 6.0, 2.0)
    ud = 1.3 * np.sin(np.linspace(0, 30, 3000))
    for a, b in [(0, 0), (-1, 1), (0.5, -0.25)]:
        inverse = f.inverse_member(a, b)
        member = f.member(a, b)
        assert isinstance(inverse, hyst.InverseHysteresis) and inverse.memory is None
        assert (inverse.k1, inverse.k2) == (member.k1, member.k2)
        assert np.array_equal(inverse.process(ud), member.inverse().process(ud))
    nominal = f.inverse_member(0, 0)
    assert (nominal.k1, nominal.k2) == (f.k1, f.k2)
    assert f.inverse_member(1, 1, dtype=np.float32).dtype == "float32"
    with pytest.raises(ValueError, match=r"inverse_member\(2, 0\): the position must lie in"):
        f.inverse_member(2.0, 0.0)
    with pytest.raises(ValueError, match="inverse_member"):
        f.inverse_member(0.0, -1.5)
    assert not hasattr(f, "compensator")


@pytest.mark.parametrize("args", [(0.1, 0.1, 8, 5), (0.1, 0.05, 8, 8), (0.1, -0.01, 8, 1), (0, 0, 1, 0)])
def test_bad_family(args):
    with pytest.raises(ValueError, match="Family"):
        hyst.Family(*args)


def test_compensator_docs_example():
    # hyst_core's doc example: Example 3's F = H^-1'' + 0.9 H^-1' + H^-1, u_new = 0.5 -> 1.3.
    c = hyst.Compensator(hyst.Hysteresis(0.2, 8.0), 1.0, [0.9, 1.0])
    assert abs(c.step(0.5, 1e-3) - 1.3) < 1e-12
    v, v_dot = c.state
    assert abs(v - 0.25e-6) < 1e-18 and abs(v_dot - 0.5e-3) < 1e-15
    assert c.order == 2 and c.a == [0.9, 1.0] and c.b == 1.0
    # The first step evaluates the inverse at the start state v = 0 (then integrates u_new):
    # reference v, target x1 = H^-1[v], command u of eq. (19).
    assert c.last_reference == 0.0 and abs(c.last_target) < 1e-15
    assert abs(c.last_command - 1.3) < 1e-12
    for old in ("reference", "target", "command"):
        assert not hasattr(c, old)


def test_last_reference_target_and_command():
    """n = 0 (a static plant of gain b): v = u_new, x1 = H^-1[v] and u = x1 / b."""
    b = 2.0
    c = hyst.Compensator(hyst.Hysteresis(0.2, 8.0), b, [])
    inverse = hyst.InverseHysteresis(0.2, 8.0)
    for v in (0.0, 0.4, 0.9, 0.3, -0.5):
        u = c.step(v, 1e-3)
        assert c.last_reference == v
        assert c.last_target == pytest.approx(inverse.step(v), rel=1e-12, abs=1e-15)
        assert c.last_command == u == c.last_target / b


def test_compensated_first_order_plant_follows_the_reference():
    """Lemma 5.1, n = 1: plant tau x1' = b u - x1, then hysteresis; the output follows v."""
    tau, b, dt = 0.02, 2.0, 1e-4
    t = np.arange(0.0, 2.0, dt)
    v_dot = 3.0 * np.cos(3.0 * t) + 1.2 * np.cos(11.0 * t)  # v = sin 3t + 0.11 sin 11t
    comp = hyst.Compensator(hyst.Hysteresis(0.2, 8.0), b, [tau])
    u = comp.process(v_dot, dt)
    plant = hyst.Hysteresis(0.2, 8.0)
    x1, out, ref = 0.0, [], []
    c2 = hyst.Compensator(hyst.Hysteresis(0.2, 8.0), b, [tau])
    for k in range(t.size):
        assert c2.step(v_dot[k], dt) == u[k]
        out.append(plant.step(x1))
        ref.append(c2.last_reference)
        # Exact discretisation of tau x1' = b u - x1 with u held over dt.
        x1 = x1 * np.exp(-dt / tau) + b * u[k] * (1 - np.exp(-dt / tau))
    err = np.abs(np.array(out) - np.array(ref))
    # Zero-order hold of u: O(dt) error only, not the hysteresis width (k1 = 0.2).
    assert np.max(err[100:]) < 5e-3


def test_compensator_with_a_fitted_model_and_errors(piezo):
    u, y = piezo
    r = hyst.fit(u[:3000], y[:3000])
    c = hyst.Compensator(r.model, 1.0, [], state=None)
    # The compensator starts at rest at v = 0 (the model's start rule there); the desired
    # output starts there too.
    desired = y[:3000] - y[0]
    commands = c.process(desired, 1e-3)
    # n = 0 (a static plant of gain 1): the commands are the model's exact inverse, and the
    # model started at the first command by the same rule gives the desired output back.
    assert np.allclose(r.model.process(commands), desired, rtol=0, atol=1e-9)
    with pytest.raises(ValueError, match=f"at most hyst.MAX_ORDER = {hyst.MAX_ORDER}"):
        hyst.Compensator(r.model, 1.0, [1.0] * (hyst.MAX_ORDER + 1))
    assert hyst.Compensator(r.model, 1.0, [0.1] * hyst.MAX_ORDER).order == hyst.MAX_ORDER
    with pytest.raises(ValueError, match="b"):
        hyst.Compensator(r.model, 0.0, [1.0])
    with pytest.raises(ValueError, match="state"):
        hyst.Compensator(r.model, 1.0, [1.0], state=[0.0, 0.0])
    pi = hyst.fit(u[:3000], y[:3000], model_kind="prandtl-ishlinskii")
    with pytest.raises(ValueError, match="Prandtl-Ishlinskii"):
        hyst.Compensator(pi.model, 1.0, [1.0])
    with pytest.raises(ValueError, match="model"):
        hyst.Compensator("not a model", 1.0, [1.0])
    c = hyst.Compensator(hyst.Hysteresis(0.2, 8.0), 1.0, [0.5])
    c.process(np.full(10, 0.3), 1e-3)
    state = c.state
    with pytest.raises(ValueError, match=r"u_new\[2\]"):
        c.process([0.1, 0.2, np.nan], 1e-3)
    assert c.state == state
    with pytest.raises(ValueError, match="dt"):
        c.step(0.1, -1.0)
