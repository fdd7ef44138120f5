"""Shared scenes for the package's tests (scenes written for these tests)."""
import os
import re

import pytest

# The tests do not depend on the machine: the CPU path runs even where a GPU
# answers (no implicit CudaDevice), as in CI and in the C tests' ctest
# environment (cmake/PliantTesting.cmake).
os.environ["PLIANT_DEVICE"] = "cpu"

import pliant  # noqa: E402

pliant.set_log_level("warning")

MESHES = os.path.join(os.path.dirname(pliant.scene("cable_finger_small.xml")), "meshes")

# One free tetrahedron under gravity: no support, no contact.
FREE_TETRA = f"""<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <RequiredPlugin name="hyperelastic"/><RequiredPlugin name="sparse_inverse"/>
  <LocalGlobalSolver name="solver" iterations="10"/>
  <SparseInverseSolver name="global"/>
  <Node name="body">
    <MeshLoader name="mesh" filename="{MESHES}/single_tetra.msh"/>
    <MechanicalObject name="dofs"/>
    <DiagonalMass massDensity="1000"/>
    <NeoHookean name="material" youngModulus="1e5" poissonRatio="0.3"/>
  </Node>
</Node>
"""


def finger_xml(keyframes=True):
    """The small cable finger's XML (20 solver iterations a step), without its Keyframes (and keyboard) when
    keyframes is False, so that Python drives the cable."""
    with open(pliant.scene("cable_finger_small.xml")) as f:
        text = f.read()
    text = text.replace('filename="meshes/', f'filename="{MESHES}/')
    text = re.sub(r'<VTKExporter[^>]*/>', "", text)
    # 20 iterations a step rather than the scene's run to 1e-3 N: fast tests
    text = re.sub(r'<LocalGlobalSolver[^>]*/>',
                  '<LocalGlobalSolver name="solver" iterations="20" damping="10"/>', text)
    if not keyframes:
        text = re.sub(r'<Keyframes[^>]*/>', "", text)
        text = re.sub(r'<KeyboardController[^>]*/>', "", text)
    return text


@pytest.fixture
def tetra():
    return pliant.Simulation(xml=FREE_TETRA, name="free_tetra.xml")


@pytest.fixture
def finger():
    return pliant.Simulation(xml=finger_xml(keyframes=False), name="finger.xml")
