"""pliant.Simulation: loading, stepping, views of the state, fields by path,
save/restore, independent simulations (issue 18 item 1)."""
import gc

import numpy as np
import pytest

import pliant
from conftest import FREE_TETRA, finger_xml

G = -9.81


def test_free_fall_matches_implicit_euler(tetra):
    # Internal forces sum to zero: the centre of mass falls as a point under
    # implicit Euler, v_n = g n dt, y_n = y_0 + g dt^2 n (n + 1) / 2.
    x = tetra.positions()
    v = tetra.velocities()
    y0 = x[:, 1].mean()
    n, dt = 25, tetra.dt
    tetra.step(n)
    assert tetra.time == pytest.approx(n * dt, abs=1e-12)
    assert tetra.steps == n
    assert v[:, 1].mean() == pytest.approx(G * n * dt, rel=1e-9)
    assert x[:, 1].mean() - y0 == pytest.approx(G * dt * dt * n * (n + 1) / 2, rel=1e-9)
    np.testing.assert_allclose(v[:, [0, 2]].mean(axis=0), 0, atol=1e-12)


def test_views_are_the_simulations_memory(tetra):
    a = tetra.positions("body/dofs")
    b = tetra.positions()
    assert np.shares_memory(a, b)
    before = a.copy()
    tetra.step(3)
    assert not np.array_equal(a, before)          # the same array shows the new state
    text = np.array(tetra.get("body/dofs.position").split(), dtype=float)
    np.testing.assert_array_equal(a.ravel(), text)
    assert not a.flags.writeable
    with pytest.raises(ValueError):
        a[0, 0] = 1.0


def test_get_of_a_large_state_is_the_state(finger):
    # 158 vertices: the text is longer than a first 4 kB buffer (libpliant once
    # fell back to the scene's empty value instead of saying it did not fit)
    finger.step(2)
    text = np.array(finger.get("finger/dofs.position").split(), dtype=float)
    np.testing.assert_array_equal(text, finger.positions("finger/dofs").ravel())


def test_view_keeps_its_simulation_alive():
    sim = pliant.Simulation(xml=FREE_TETRA, name="t.xml")
    sim.step(2)
    x = sim.positions()
    expected = x.copy()
    del sim
    gc.collect()
    np.testing.assert_array_equal(x, expected)


def test_fields_by_path_and_did_you_mean(finger):
    finger["finger/cable.value"] = 0.004
    assert finger["finger/cable.value"] == pytest.approx(0.004)
    assert finger["root.dt"] == pytest.approx(0.01)
    with pytest.raises(pliant.InputError, match=r"did you mean finger/cable\?"):
        finger["finger/cabel.value"] = 0.005
    with pytest.raises(pliant.InputError, match="did you mean value"):
        finger["finger/cable.valeu"] = 0.005
    with pytest.raises(pliant.InputError) as e:
        finger["finger/cable.value"] = "soft"
    assert e.value.code == 2


def test_cable_pull_bends_the_finger_up(finger):
    tip = finger.positions("finger/dofs")[:, 1].argmax()
    y0 = finger.positions("finger/dofs")[tip, 1]
    finger["finger/cable.value"] = 0.008
    finger.step(30)
    assert finger.positions("finger/dofs")[tip, 1] > y0 + 0.005
    assert finger["finger/cable.force"] > 0                   # the cable pulls
    f = finger.constraint_forces("finger/dofs")
    assert np.abs(f).sum() > 0


def test_save_restore_is_exact_and_views_follow(tmp_path, finger):
    finger["finger/cable.value"] = 0.006
    finger.step(10)
    x = finger.positions("finger/dofs")
    finger.save(tmp_path / "s.state")
    finger.step(10)
    after = x.copy()
    finger.restore(tmp_path / "s.state")
    assert finger.time == pytest.approx(0.1)
    finger.step(10)
    np.testing.assert_array_equal(x, after)                   # bit for bit, same view
    finger.reset()
    assert finger.time == 0.0
    with pytest.raises(pliant.InputError, match="not a Pliant state file"):
        (tmp_path / "bad.state").write_bytes(b"garbage!")
        finger.restore(tmp_path / "bad.state")


def test_independent_simulations_in_one_process():
    a = pliant.Simulation(xml=finger_xml(False), name="a.xml")
    b = pliant.Simulation(xml=finger_xml(False), name="b.xml")
    alone = pliant.Simulation(xml=finger_xml(False), name="alone.xml")
    a["finger/cable.value"] = 0.008
    for _ in range(15):
        a.step()
        b.step()
    alone.step(15)
    np.testing.assert_array_equal(b.positions("finger/dofs"), alone.positions("finger/dofs"))
    assert not np.allclose(a.positions("finger/dofs"), b.positions("finger/dofs"))


def test_bad_scenes_raise_input_errors(tmp_path):
    with pytest.raises(pliant.InputError, match=r"broken.xml:2"):
        pliant.Simulation(xml='<Node name="root">\n  <MechanicalObjekt/>\n</Node>\n',
                          name="broken.xml")
    with pytest.raises(pliant.InputError, match="no_such.xml"):
        pliant.Simulation(tmp_path / "no_such.xml")
    with pytest.raises(TypeError):
        pliant.Simulation()


def test_sofa_scn_loads(tmp_path):
    # a SOFA scene (.scn) goes through the loader's SOFA vocabulary table
    scn = FREE_TETRA.replace("<NeoHookean", "<TetrahedronFEMForceField method=\"large\"")
    scn = scn.replace(' name="material"', "")
    path = tmp_path / "tetra.scn"
    path.write_text(scn)
    sim = pliant.Simulation(path)
    sim.step(5)
    assert sim.velocities()[:, 1].mean() == pytest.approx(G * 5 * sim.dt, rel=1e-9)


def test_forks_share_the_model_and_step_independently():
    base = pliant.Simulation(xml=finger_xml(False), name="base.xml")
    alone = pliant.Simulation(xml=finger_xml(False), name="alone.xml")
    pulled = base.fork()
    free = base.fork()
    pulled["finger/cable.value"] = 0.008               # an input: this fork only
    assert free["finger/cable.value"] == 0.0 and base["finger/cable.value"] == 0.0
    calls = []
    free.add_controller(type("C", (), {"onAnimateBeginEvent":
                                       lambda self, e: calls.append(e["time"])})())
    for _ in range(15):                                  # interleaved
        pulled.step()
        free.step()
    alone.step(15)
    assert len(calls) == 15                              # only free's steps call its controller
    np.testing.assert_array_equal(free.positions("finger/dofs"), alone.positions("finger/dofs"))
    assert pulled.positions("finger/dofs")[:, 1].max() > free.positions("finger/dofs")[:, 1].max()
    assert base.steps == 0 and free.steps == 15 and pulled.time == pytest.approx(0.15)
    x = free.positions("finger/dofs")
    del base                                             # the forks keep the model alive
    gc.collect()
    free.step(1)
    assert free.steps == 16 and np.isfinite(x).all()


def test_fork_save_restore_reset(tmp_path):
    base = pliant.Simulation(xml=finger_xml(False), name="base.xml")
    f = base.fork()
    f["finger/cable.value"] = 0.006
    f.step(5)
    f.save(tmp_path / "f.state")
    f.step(5)
    after = f.positions("finger/dofs").copy()
    f.restore(tmp_path / "f.state")
    assert f.steps == 5
    f.step(5)
    np.testing.assert_array_equal(f.positions("finger/dofs"), after)
    f.reset()
    assert f.steps == 0 and f["finger/cable.value"] == 0.0
    np.testing.assert_array_equal(f.positions("finger/dofs"), base.positions("finger/dofs"))
