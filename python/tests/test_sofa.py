"""pliant.sofa and `python3 -m pliant run`: SofaPython3-style scripts written
for the project (issue 18 item 2)."""
import os
import subprocess
import sys

import numpy as np
import pytest

import pliant
import pliant.sofa as Sofa

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.join(HERE, "scripts")


def run(script, *args):
    return subprocess.run([sys.executable, "-m", "pliant", "run", os.path.join(SCRIPTS, script),
                           "-q", *args], capture_output=True, text=True, timeout=300)


def load(script):
    """The script's createScene on a new root, as pliant run does."""
    import runpy
    from pliant.__main__ import _install_sofa
    _install_sofa()
    sys.path.insert(0, SCRIPTS)
    try:
        module = runpy.run_path(os.path.join(SCRIPTS, script), run_name="scene")
    finally:
        sys.path.remove(SCRIPTS)
    root = Sofa.Core.Node("root")
    module["createScene"](root)
    return root


def test_script_runs_and_controllers_see_each_step():
    root = load("cable_finger.py")
    Sofa.Simulation.init(root)
    rec = root.recorder
    for _ in range(3):
        Sofa.Simulation.animate(root, root.dt.value)
    np.testing.assert_allclose(rec.begins, [0, 0.01, 0.02], atol=1e-12)
    np.testing.assert_allclose(rec.ends, [0.01, 0.02, 0.03], atol=1e-12)
    # the lowering moved the mapped cable to finger/aCableActuator: Data still finds it
    cable = root.finger.cable.aCableActuator
    assert cable.value.value[0] == 0.0
    for _ in range(5):
        assert Sofa.Simulation.keypress(root, Sofa.constants.Key.plus)
    assert cable.value.value[0] == pytest.approx(5.0)           # mm, the script's units
    free = load("cable_finger.py")                                 # the same, never pulled
    Sofa.Simulation.init(free)
    for _ in range(3):
        Sofa.Simulation.animate(free)
    for _ in range(30):
        Sofa.Simulation.animate(root)
        Sofa.Simulation.animate(free)
    assert rec.tip[-1] > free.recorder.tip[-1] + 2.0               # pulled: the tip rises (mm)
    assert root.finger.cable.aCableActuator.force.value > 0
    # value 0 holds the cable at its length (against the sag): less tension than pulled
    assert free.finger.cable.aCableActuator.force.value < root.finger.cable.aCableActuator.force.value


def test_pliant_run_runs_a_script():
    r = run("cable_finger.py", "-n", "5")
    assert r.returncode == 0, r.stderr
    assert "5 steps, t = 0.05 s" in r.stdout


def test_exception_in_createScene_prints_its_traceback_and_exits_2():
    r = run("broken_create.py")
    assert r.returncode == 2
    assert "Traceback" in r.stderr and "ZeroDivisionError" in r.stderr
    assert "broken_create.py\", line 3" in r.stderr


def test_unsupported_call_names_the_closest_supported_one():
    r = run("unsupported_call.py")
    assert r.returncode == 2
    assert "addObjet is not supported" in r.stderr and "closest supported" in r.stderr
    assert ".addObject" in r.stderr
    with pytest.raises(Sofa.UnsupportedError, match="closest supported: Sofa.Simulation.animate"):
        Sofa.Simulation.animat


def test_loader_errors_name_the_script_line():
    r = run("bad_component.py")
    assert r.returncode == 2
    assert "bad_component.py:3:" in r.stderr and "MechanicalObject" in r.stderr


def test_loader_warnings_name_the_script_line():
    # what the loader drops or changes is said, as `pliant run scene.scn` says it,
    # at the script's call (VisualStyle: drawing, ignored)
    with open(os.path.join(SCRIPTS, "cable_finger.py")) as f:
        line = next(i for i, t in enumerate(f, 1) if '"VisualStyle"' in t)
    r = run("cable_finger.py", "-n", "1")
    assert r.returncode == 0, r.stderr
    assert f"cable_finger.py:{line}: warning: VisualStyle" in r.stderr, r.stderr
    sim = load("cable_finger.py")
    Sofa.Simulation.init(sim)
    assert "warning: VisualStyle" in sim.simulation.warnings


def test_sofa_is_only_importable_inside_a_run():
    r = subprocess.run([sys.executable, "-c", "import Sofa"], capture_output=True, text=True)
    assert r.returncode != 0 and "No module named 'Sofa'" in r.stderr


def test_missing_script_is_bad_input():
    r = run("no_such_script.py")
    assert r.returncode == 2 and "no such file" in r.stderr


CLI = os.environ.get("PLIANT_CLI")


@pytest.mark.skipif(not CLI or not os.path.exists(CLI), reason="PLIANT_CLI: no pliant binary")
def test_the_c_cli_hands_scripts_to_the_package():
    env = dict(os.environ, PLIANT_PYTHON=sys.executable)
    r = subprocess.run([CLI, "run", os.path.join(SCRIPTS, "cable_finger.py"), "-n", "3", "-q"],
                       capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "3 steps, t = 0.03 s" in r.stdout
    r = subprocess.run([CLI, "run", os.path.join(SCRIPTS, "broken_create.py")],
                       capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 2 and "ZeroDivisionError" in r.stderr


@pytest.mark.skipif(not CLI or not os.path.exists(CLI), reason="PLIANT_CLI: no pliant binary")
def test_the_c_cli_without_the_package_says_how_to_install_it():
    base = getattr(sys, "_base_executable", None)
    if not base or subprocess.run([base, "-c", "import pliant"],
                                  capture_output=True).returncode == 0:
        pytest.skip("no interpreter without the package")
    r = subprocess.run([CLI, "run", os.path.join(SCRIPTS, "cable_finger.py")],
                       capture_output=True, text=True, env=dict(os.environ, PLIANT_PYTHON=base))
    assert r.returncode == 2
    assert "needs the Python package pliant" in r.stderr and "pip install ." in r.stderr


def test_unsupported_calls_raise_with_the_closest_supported_one():
    root = Sofa.Core.Node("root")
    with pytest.raises(Sofa.UnsupportedError, match=r"createObject is not supported.*addObject"):
        root.createObject("MechanicalObject")
    with pytest.raises(Sofa.UnsupportedError, match=r"Sofa.Core.ForceField is not supported"):
        Sofa.Core.ForceField
    body = root.addChild("body")
    dofs = body.addObject("MechanicalObject", name="dofs", position=[[0, 0, 0], [1, 0, 0]])
    with pytest.raises(Sofa.UnsupportedError, match=r"closest supported: Data.value"):
        dofs.position.valeu
    assert root.body.dofs is dofs and root.getChild("body") is body
    assert dofs.position.value == [[0, 0, 0], [1, 0, 0]]          # before init: as given
    assert dofs.position.getLinkPath() == "@/body/dofs.position"
    assert body.getPathName() == "/body" and dofs.getPathName() == "/body/dofs"


def test_pliant_load_takes_xml_scn_and_scripts():
    sim = pliant.load(os.path.join(SCRIPTS, "cable_finger.py"))
    sim.step(2)
    assert sim.steps == 2 and sim.time == pytest.approx(0.02)
    assert sim.positions("finger/tetras").shape == (158, 3)
    assert isinstance(pliant.load(pliant.scene("cable_finger_small.xml")), pliant.Simulation)
