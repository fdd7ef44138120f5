"""Python controllers called from the C loop at the start and end of every
step (issue 18 item 3)."""
import numpy as np
import pytest

import pliant
from conftest import finger_xml

TIMES = [0, 0.3, 0.5, 0.7]        # the Keyframes of cable_finger_small.xml
VALUES = [0, 0.01, 0.01, 0]


class Pull(pliant.Controller):
    """What the scene's Keyframes does, in Python: a piecewise linear pull."""

    def __init__(self, sim):
        self.sim = sim
        self.begin_times, self.end_tips = [], []

    def onAnimateBeginEvent(self, event):
        self.begin_times.append(event["time"])
        self.sim["finger/cable.value"] = float(np.interp(event["time"], TIMES, VALUES))

    def onAnimateEndEvent(self, event):
        self.end_tips.append(self.sim.positions("finger/dofs")[-1].copy())


def test_python_controller_drives_like_keyframes():
    scene = pliant.Simulation(xml=finger_xml(keyframes=True), name="keyframes.xml")
    python = pliant.Simulation(xml=finger_xml(keyframes=False), name="python.xml")
    pull = python.add_controller(Pull(python))
    n = 40
    scene.step(n)
    python.step(n)
    np.testing.assert_allclose(pull.begin_times, np.arange(n) * python.dt, atol=1e-12)
    assert len(pull.end_tips) == n
    np.testing.assert_array_equal(pull.end_tips[-1], python.positions("finger/dofs")[-1])
    assert python["finger/cable.value"] == pytest.approx(scene["finger/cable.value"], abs=1e-15)
    np.testing.assert_allclose(python.positions("finger/dofs"), scene.positions("finger/dofs"),
                               rtol=0, atol=1e-12)
    assert python["finger/cable.force"] > 0


def test_controller_exception_stops_step_and_is_raised(finger):
    class Broken:
        def onAnimateBeginEvent(self, event):
            if event["time"] > 0.015:
                raise ZeroDivisionError("controller bug")

    finger.add_controller(Broken())
    with pytest.raises(ZeroDivisionError, match="controller bug"):
        finger.step(5)
    assert finger.steps == 2                   # steps 0 and 1 ran, step 2 did not
    with pytest.raises(RuntimeError, match="inside a step"):
        finger.remove_controller(finger._controllers[0])
        finger.add_controller(type("Nested", (), {
            "onAnimateEndEvent": lambda self, e: finger.step(1)})())
        finger.step(1)


def test_end_event_sees_the_finished_step(finger):
    seen = []
    finger.add_controller(type("C", (), {
        "onAnimateEndEvent": lambda self, e: seen.append((e["time"], finger.time))})())
    finger.step(3)
    assert [a for a, _ in seen] == [b for _, b in seen]
    assert seen[-1][0] == pytest.approx(0.03)
