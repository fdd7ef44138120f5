# A SofaPython3-style scene written for Pliant's tests: the cable finger of
# SoftRobots' CableConstraint example (SOFA vocabulary, millimetres), with a
# controller in a module beside it (imported through sys.path, as SoftRobots'
# Finger.py imports FingerController).
import os

import Sofa.Core  # noqa: F401  (pliant run makes pliant.sofa importable as Sofa)
from finger_keys import FingerKeys

MESH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                    "scenes", "meshes", "finger.vtk")
if not os.path.exists(MESH):  # installed package: its scenes folder
    import pliant
    MESH = os.path.join(os.path.dirname(pliant.scene("cable_finger.xml")), "meshes", "finger.vtk")
POINTS = [[-17.5, 12.5, 2.5], [-32.5, 12.5, 2.5], [-47.5, 12.5, 2.5], [-62.5, 12.5, 2.5],
          [-77.5, 12.5, 2.5], [-83.5, 12.5, 4.5], [-85.5, 12.5, 6.5], [-85.5, 12.5, 8.5],
          [-83.5, 12.5, 10.5], [-77.5, 12.5, 12.5], [-62.5, 12.5, 12.5], [-47.5, 12.5, 12.5],
          [-32.5, 12.5, 12.5], [-17.5, 12.5, 12.5]]


def createScene(rootNode):
    rootNode.addObject("RequiredPlugin", name="SoftRobots")
    rootNode.addObject("RequiredPlugin", pluginName=["Sofa.Component.AnimationLoop",
                                                     "Sofa.Component.Engine.Select"])
    rootNode.addObject("VisualStyle", displayFlags="showVisualModels")
    rootNode.addObject("FreeMotionAnimationLoop")
    rootNode.addObject("GenericConstraintSolver", tolerance=1e-5, maxIterations=100)
    rootNode.gravity = [0, -9810, 0]
    rootNode.dt = 0.01
    finger = rootNode.addChild("finger")
    finger.addObject("EulerImplicitSolver", name="odesolver", rayleighMass=10)
    finger.addObject("SparseLDLSolver", template="CompressedRowSparseMatrixMat3x3d")
    finger.addObject("MeshVTKLoader", name="loader", filename=MESH)
    finger.addObject("MeshTopology", src="@loader", name="container")
    finger.addObject("MechanicalObject", name="tetras", template="Vec3")
    finger.addObject("UniformMass", totalMass=0.075)
    finger.addObject("TetrahedronFEMForceField", name="FEM", method="large",
                     poissonRatio=0.45, youngModulus=600)
    finger.addObject("BoxROI", name="roi", box=[-15, 0, 0, 5, 10, 15], drawBoxes=True)
    finger.addObject("RestShapeSpringsForceField", points=finger.roi.indices.getLinkPath(),
                     stiffness=1e12)
    finger.addObject("GenericConstraintCorrection")
    cable = finger.addChild("cable")
    cable.addObject("MechanicalObject", position=POINTS)
    cable.addObject("CableConstraint", name="aCableActuator", indices=list(range(14)),
                    minForce=0, pullPoint=[0.0, 12.5, 2.5])
    cable.addObject("BarycentricMapping")
    cable.addObject(FingerKeys(name="keys", node=cable))
    rootNode.addObject(Recorder(name="recorder", root=rootNode))
    return rootNode


class Recorder(Sofa.Core.Controller):
    """Records the time of every begin and end event, and the tip's height [mm]."""

    def __init__(self, *a, **kw):
        Sofa.Core.Controller.__init__(self, *a, **kw)
        self.root = kw["root"]
        self.begins, self.ends, self.tip = [], [], []

    def onAnimateBeginEvent(self, e):
        self.begins.append(e["time"])

    def onAnimateEndEvent(self, e):
        self.ends.append(e["time"])
        x = self.root.finger.tetras.position.value
        if not self.tip:
            self.index = int(x[:, 0].argmin())   # the finger points along -x
        self.tip.append(float(x[self.index, 1]))
