/* sofa_vocab.c - SOFA's vocabulary in one table: for every SOFA component
 * and attribute Pliant knows, what it becomes and where physics differ.
 * The scene loader (sofa_lower.c), `pliant doc --sofa` and docs/sofa.md all
 * read this table; change a rule here and nowhere else. */
#include "sofa.h"
#include "pliant/sofa.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>

#define SAME(s, plugin, note) {s, PL_SOFA_SAME, s, plugin, note}
#define RENAME(s, p, plugin, note) {s, PL_SOFA_RENAME, p, plugin, note}
#define VISUAL(s) {s, PL_SOFA_VISUAL, NULL, NULL, "drawing or GUI only"}
#define NOTED(s, note) {s, PL_SOFA_NOTED, NULL, NULL, note}
#define LOWERED(s, p, plugin, note) {s, PL_SOFA_LOWERED, p, plugin, note}
#define REFUSED(s, note) {s, PL_SOFA_REFUSED, NULL, NULL, note}

static const char CORR[] = "a constraint correction: Pliant's contact solver works with the "
                           "global solver's factor itself";
static const char PIPE[] = "a part of SOFA's collision pipeline: with collision models that "
                           "can touch, one CollisionPipeline (collision plugin) takes the "
                           "intersection's alarmDistance and contactDistance and the "
                           "response's mu (penalty responses refused); without, ignored";
static const char COLL[] = "SOFA's collision models are not mapped yet (ignored when all "
                           "sit in one node without selfCollision: nothing to touch); closest: "
                           "SurfaceCollisionModel and the obstacles of Pliant's collision plugin";
static const char COLLMAP[] = "on a body (its node, or a child node with its surface by "
                              "Tetra2TriangleTopologicalMapping and IdentityMapping): "
                              "SurfaceCollisionModel; in a node no ODE solver moves: "
                              "MeshObstacle of its triangles (inline or a loader); the "
                              "pipeline becomes CollisionPipeline (collision plugin), "
                              "FrictionContactConstraint's mu its mu; elsewhere (a "
                              "BarycentricMapping surface) refused";
static const char LINSOLVE[] = "the linear solver of the step: LinearizedEulerSolver "
                               "linearSolver=\"direct\" (a Cholesky factor); with constraints "
                               "SparseInverseSolver at the root";
static const char CGSOLVE[] = "LinearizedEulerSolver linearSolver=\"cg\" with its iterations, "
                              "tolerance and threshold; with constraints SparseInverseSolver at "
                              "the root (exact, tuning ignored)";
static const char CONSOLVE[] = "the constraint solver: NonSmoothNewtonContactSolver at the root "
                               "(non-smooth Newton, not Gauss-Seidel; its iteration counts and "
                               "tolerances do not apply)";
static const char TOPO[] = "a topology container: in Pliant the mesh is the loader's; the "
                           "container must take it from a loader of its node (src=\"@loader\" "
                           "or position=\"@loader.position\")";
static const char COROT[] = "Corotational (hyperelastic plugin): psi = mu |F - R|^2 + lambda/2 "
                            "tr(R^T F - I)^2 with R from the polar decomposition, which is "
                            "SOFA's corotational linear FEM; SOFA's 'large' takes R from a "
                            "QR-style frame of the edges (differs at large shear); "
                            "'small' is refused";

static const pl_sofa_component COMPONENTS[] = {
    /* scene structure, loops and solvers */
    LOWERED("DefaultAnimationLoop", "LocalGlobalSolver", NULL,
            "the loop of the generated LocalGlobalSolver; Lagrangian constraints (cables) are "
            "refused under it, as SOFA ignores them"),
    LOWERED("FreeMotionAnimationLoop", "LocalGlobalSolver", NULL,
            "the loop of the generated LocalGlobalSolver, with constraints solved inside its "
            "iterations"),
    LOWERED("EulerImplicitSolver", "LinearizedEulerSolver", NULL,
            "one solver at the root integrates every body that has an EulerImplicitSolver above "
            "it: LinearizedEulerSolver, SOFA's scheme (one linearised step, Rayleigh damping, "
            "firstOrder); with Lagrangian constraints (cables) LocalGlobalSolver (iterations "
            "20), implicit Euler converged by local-global iterations, rayleighMass as its "
            "damping, its firstOrder and rayleighStiffness (with the rest stiffness for SOFA's "
            "tangent K)"),
    REFUSED("EulerExplicitSolver", "explicit integration is not in Pliant; closest: "
                                   "EulerImplicitSolver (LocalGlobalSolver)"),
    REFUSED("RungeKutta4Solver", "explicit integration is not in Pliant; closest: "
                                 "EulerImplicitSolver (LocalGlobalSolver)"),
    REFUSED("StaticSolver", "static solving with SOFA's Newton loop is not mapped; closest: "
                            "NewtonSolver quasiStatic=\"1\" (a Pliant scene)"),
    LOWERED("CGLinearSolver", "LinearizedEulerSolver", NULL, CGSOLVE),
    LOWERED("PCGLinearSolver", "LinearizedEulerSolver", NULL,
            "preconditioned CG: LinearizedEulerSolver linearSolver=\"direct\" (its "
            "preconditioner is a factorisation); with constraints SparseInverseSolver"),
    LOWERED("SparseLDLSolver", "LinearizedEulerSolver", NULL, LINSOLVE),
    LOWERED("AsyncSparseLDLSolver", "LinearizedEulerSolver", NULL, LINSOLVE),
    LOWERED("SparseCholeskySolver", "LinearizedEulerSolver", NULL, LINSOLVE),
    LOWERED("EigenSimplicialLDLT", "LinearizedEulerSolver", NULL, LINSOLVE),
    LOWERED("EigenSimplicialLLT", "LinearizedEulerSolver", NULL, LINSOLVE),
    LOWERED("GenericConstraintSolver", "NonSmoothNewtonContactSolver", "ncp_contact", CONSOLVE),
    LOWERED("BlockGaussSeidelConstraintSolver", "NonSmoothNewtonContactSolver", "ncp_contact",
            CONSOLVE),
    LOWERED("UnbuiltGaussSeidelConstraintSolver", "NonSmoothNewtonContactSolver", "ncp_contact",
            CONSOLVE),
    LOWERED("NNCGConstraintSolver", "NonSmoothNewtonContactSolver", "ncp_contact", CONSOLVE),
    LOWERED("LCPConstraintSolver", "NonSmoothNewtonContactSolver", "ncp_contact", CONSOLVE),
    NOTED("LinearSolverConstraintCorrection", CORR),
    NOTED("GenericConstraintCorrection", CORR),
    NOTED("UncoupledConstraintCorrection", CORR),
    NOTED("PrecomputedConstraintCorrection", CORR),
    /* loaders and topology */
    RENAME("MeshVTKLoader", "MeshLoader", NULL, "MeshLoader (the format is read from the content)"),
    RENAME("MeshOBJLoader", "MeshLoader", NULL, "MeshLoader (the format is read from the content)"),
    RENAME("MeshSTLLoader", "MeshLoader", NULL, "MeshLoader (the format is read from the content)"),
    RENAME("MeshGmshLoader", "MeshLoader", NULL,
           "MeshLoader (the format is read from the content)"),
    REFUSED("SphereLoader", "sphere collision models are not mapped (in a mapped node that "
                            "only follows its body, its centres become MappedPoints); closest: "
                            "SurfaceCollisionModel (collision plugin)"),
    LOWERED("RegularGridTopology", "RegularGridTetrahedra", NULL,
            "with a Hexa2TetraTopologicalMapping into a body's TetrahedronSetTopologyContainer: "
            "RegularGridTetrahedra (n, min, max: the same vertices in SOFA's order; 6 "
            "tetrahedra per cell split along the main diagonal, where SOFA alternates)"),
    LOWERED("Hexa2TetraTopologicalMapping", "RegularGridTetrahedra", NULL,
            "from a RegularGridTopology: RegularGridTetrahedra in the body's node"),
    LOWERED("Tetra2TriangleTopologicalMapping", NULL, NULL,
            "a body's surface: for drawing (dropped with its node) or for collision models "
            "under an IdentityMapping (SurfaceCollisionModel, the same boundary)"),
    LOWERED("TetrahedronSetTopologyContainer", NULL, NULL, TOPO),
    LOWERED("TriangleSetTopologyContainer", NULL, NULL, TOPO),
    LOWERED("MeshTopology", NULL, NULL, TOPO),
    NOTED("TetrahedronSetTopologyModifier", "topology changes are not simulated"),
    NOTED("TriangleSetTopologyModifier", "topology changes are not simulated"),
    NOTED("TetrahedronSetGeometryAlgorithms", "geometric queries: nothing to do"),
    NOTED("TriangleSetGeometryAlgorithms", "geometric queries: nothing to do"),
    /* state and masses */
    SAME("MechanicalObject", NULL,
         "MechanicalObject: template Vec3, Vec3d or Vec3f only (Rigid3 and others are refused "
         "until rigid bodies exist); dx dy dz rx ry rz scale become translation, rotation, "
         "scale3d"),
    SAME("UniformMass", NULL, "UniformMass (totalMass, vertexMass)"),
    SAME("DiagonalMass", NULL,
         "DiagonalMass (massDensity; on triangles the density is per area, as in SOFA: "
         "thickness 1); totalMass is refused"),
    RENAME("MeshMatrixMass", "DiagonalMass", NULL,
           "DiagonalMass: lumped (a quarter of each tetrahedron per vertex) where SOFA's default "
           "is the consistent mass matrix; the same total mass"),
    /* force fields */
    RENAME("TetrahedronFEMForceField", "Corotational", "hyperelastic", COROT),
    RENAME("TetrahedralCorotationalFEMForceField", "Corotational", "hyperelastic", COROT),
    RENAME("FastTetrahedralCorotationalForceField", "Corotational", "hyperelastic", COROT),
    RENAME("TriangleFEMForceField", "Corotational", "hyperelastic",
           "Corotational on the triangles (a membrane, plane stress) with SOFA's default "
           "thickness 1"),
    LOWERED("RestShapeSpringsForceField", "FixedConstraint", NULL,
            "stiffness >= 1e9 (SoftRobots' 1e12 idiom): the points are held exactly "
            "(FixedConstraint, eliminated from the unknowns); softer springs are PositionTarget "
            "(hyperelastic plugin) on explicit indices"),
    SAME("ConstantForceField", NULL,
         "ConstantForceField (indices, forces, force, totalForce; without indices every point)"),
    SAME("PlaneForceField", NULL,
         "PlaneForceField: SOFA's penalty plane (normal, d, stiffness, damping, bilateral), "
         "energy stiffness/2 d^2 below the plane; the damping force is explicit, as in SOFA"),
    REFUSED("SpringForceField", "springs between points are not mapped"),
    REFUSED("StiffSpringForceField", "springs between points are not mapped"),
    REFUSED("RigidMapping", "it maps a rigid body (Rigid3 state), which Pliant does not have "
                            "yet; closest: a soft body with BarycentricMapping"),
    /* constraints */
    SAME("FixedConstraint", NULL, "FixedConstraint (indices, fixAll)"),
    RENAME("FixedProjectiveConstraint", "FixedConstraint", NULL,
           "FixedConstraint (indices, fixAll): the vertices are eliminated, as SOFA projects "
           "them"),
    REFUSED("PartialFixedProjectiveConstraint",
            "fixing some directions only is not in Pliant; closest: PointOnPlaneConstraint "
            "(template_constraint plugin) or FixedConstraint"),
    REFUSED("PartialFixedConstraint", "fixing some directions only is not in Pliant; closest: "
                                      "FixedConstraint"),
    REFUSED("FixedPlaneProjectiveConstraint", "not mapped; closest: PointOnPlaneConstraint"),
    /* engines */
    LOWERED("BoxROI", "box", NULL,
            "its boxes go to the components that link to its indices (FixedConstraint, "
            "RestShapeSpringsForceField, ConstantForceField), which select the vertices whose "
            "rest positions lie inside (bounds included), as BoxROI does"),
    REFUSED("SphereROI", "not mapped yet; closest: BoxROI"),
    LOWERED("IndexValueMapper", NULL, NULL,
            "per-element values of a FEM (youngModulus, poissonRatio linked to its "
            "outputValues), from numbers or a BoxROI's tetrahedronIndices (all four vertices "
            "in a box; strict=\"false\": the centre), evaluated at load on the rest mesh: the "
            "FEM gets one value per element"),
    /* mappings */
    LOWERED("BarycentricMapping", NULL, NULL,
            "only in a child node that carries a cable's points (its MechanicalObject and "
            "CableConstraint): the cable moves to the body's node and its points follow the "
            "tetrahedra containing them; visual child nodes are dropped"),
    LOWERED("IdentityMapping", NULL, NULL,
            "only in a child node that carries a cable on the body's own vertices"),
    /* collision */
    NOTED("CollisionPipeline", PIPE),
    NOTED("DefaultPipeline", PIPE),
    NOTED("BruteForceBroadPhase", PIPE),
    NOTED("BruteForceDetection", PIPE),
    NOTED("BVHNarrowPhase", PIPE),
    NOTED("DiscreteIntersection", PIPE),
    NOTED("NewProximityIntersection", PIPE),
    NOTED("MinProximityIntersection", PIPE),
    NOTED("LocalMinDistance", PIPE),
    NOTED("CollisionResponse", PIPE),
    NOTED("DefaultContactManager", PIPE),
    NOTED("RuleBasedContactManager", PIPE),
    LOWERED("TriangleCollisionModel", "SurfaceCollisionModel", "collision", COLLMAP),
    LOWERED("LineCollisionModel", "SurfaceCollisionModel", "collision", COLLMAP),
    LOWERED("PointCollisionModel", "SurfaceCollisionModel", "collision", COLLMAP),
    REFUSED("SphereCollisionModel", COLL),
    REFUSED("TriangleModel", COLL),
    REFUSED("LineModel", COLL),
    REFUSED("PointModel", COLL),
    /* SoftRobots */
    SAME("CableConstraint", "cable",
         "CableConstraint (cable plugin): indices, pullPoint, value, valueType, "
         "minForce, maxForce, maxPositiveDisp, maxNegativeDisp, maxDispVariation, "
         "hasPullPoint, cableInitialLength, centers; in a mapped node method=\"geodesic\" / \"sphere\" with "
         "radii and surfaceTopology (pulled areas)"),
    SAME("SurfacePressureConstraint", "cable",
         "SurfacePressureConstraint (cable plugin): triangles, quads, value, valueIndex, "
         "valueType (pressure|volumeGrowth), minPressure, maxPressure, eqPressure, "
         "minVolumeGrowth, maxVolumeGrowth, the variation limits, flipNormal; outputs pressure, "
         "volumeGrowth, cavityVolume; in a mapped node it moves to the body's node"),
    NOTED("VolumeFromTriangles", "the cavity's volume is SurfacePressureConstraint's output "
                                 "cavityVolume"),
    REFUSED("PositionEffector", "inverse problems (SoftRobots.Inverse) are not in Pliant"),
    REFUSED("QPInverseProblemSolver", "inverse problems (SoftRobots.Inverse) are not in Pliant"),
    /* visual and GUI */
    VISUAL("VisualStyle"),
    VISUAL("OglModel"),
    VISUAL("VisualModel"),
    VISUAL("OglSceneFrame"),
    VISUAL("OglLabel"),
    VISUAL("BackgroundSetting"),
    VISUAL("ConstraintAttachButtonSetting"),
    VISUAL("AttachBodyButtonSetting"),
    VISUAL("DefaultVisualManagerLoop"),
    VISUAL("VisualManagerLoop"),
    VISUAL("LightManager"),
    VISUAL("DirectionalLight"),
    VISUAL("PositionalLight"),
    VISUAL("SpotLight"),
    VISUAL("InfoComponent"),
    {NULL, PL_SOFA_SAME, NULL, NULL, NULL}};

#define A_REN(c, s, p) {c, s, PL_SOFA_A_RENAME, p, NULL}
#define A_IGN(c, s, note) {c, s, PL_SOFA_A_IGNORE, NULL, note}
#define A_REF(c, s, note) {c, s, PL_SOFA_A_REFUSE, NULL, note}
#define A_LOW(c, s, note) {c, s, PL_SOFA_A_LOWERED, NULL, note}

static const char TUNE[] = "solver tuning without a Pliant meaning";
static const char FEMTUNE[] = "assembly tuning of SOFA's FEM: no effect on the result";

static const pl_sofa_attr ATTRS[] = {
    /* any SOFA component */
    A_IGN("*", "printLog", "logging"),
    A_IGN("*", "listening", "GUI events"),
    A_IGN("*", "tags", "SOFA's visitor tags"),
    A_IGN("*", "bbox", "drawing"),
    A_IGN("*", "componentState", "SOFA's internal state"),
    A_IGN("*", "color", "drawing"),
    A_LOW("*", "template", "Vec3, Vec3d, Vec3f (and matrix types) accepted; other state types "
                           "(Rigid3, Vec2, Vec1, ...) refused"),
    /* MechanicalObject */
    A_LOW("MechanicalObject", "dx", "translation x"),
    A_LOW("MechanicalObject", "dy", "translation y"),
    A_LOW("MechanicalObject", "dz", "translation z"),
    A_LOW("MechanicalObject", "rx", "rotation about x [deg]"),
    A_LOW("MechanicalObject", "ry", "rotation about y [deg]"),
    A_LOW("MechanicalObject", "rz", "rotation about z [deg]"),
    A_LOW("MechanicalObject", "scale", "scale3d = scale scale scale"),
    A_LOW("MechanicalObject", "position", "numbers, or @loader.position (= src=\"@loader\")"),
    A_IGN("MechanicalObject", "size", "Pliant counts the positions"),
    A_REF("MechanicalObject", "force", "initial forces are not in Pliant; use ConstantForceField"),
    A_REF("MechanicalObject", "externalForce", "use ConstantForceField"),
    A_REF("MechanicalObject", "restScale", "not mapped"),
    /* loaders */
    A_LOW("MeshVTKLoader", "scale", "scale3d = scale scale scale"),
    A_LOW("MeshOBJLoader", "scale", "scale3d = scale scale scale"),
    A_LOW("MeshSTLLoader", "scale", "scale3d = scale scale scale"),
    A_LOW("MeshGmshLoader", "scale", "scale3d = scale scale scale"),
    A_IGN("MeshOBJLoader", "handleSeams", "texture seams: drawing"),
    A_IGN("MeshOBJLoader", "loadMaterial", "drawing"),
    A_IGN("MeshVTKLoader", "createSubelements", "Pliant builds the boundary itself"),
    A_IGN("MeshGmshLoader", "createSubelements", "Pliant builds the boundary itself"),
    A_IGN("MeshVTKLoader", "flipNormals", "normals are drawing; orientation is checked"),
    A_IGN("MeshOBJLoader", "flipNormals", "normals are drawing; orientation is checked"),
    A_IGN("MeshSTLLoader", "flipNormals", "normals are drawing; orientation is checked"),
    A_IGN("MeshOBJLoader", "triangulate", "Pliant triangulates polygons"),
    A_IGN("MeshSTLLoader", "forceFilename", "logging"),
    /* masses */
    A_REF("DiagonalMass", "totalMass",
          "not mapped: give massDensity, or use UniformMass totalMass"),
    A_REF("MeshMatrixMass", "totalMass",
          "not mapped: give massDensity, or use UniformMass totalMass"),
    A_REF("MeshMatrixMass", "vertexMass", "not mapped: give massDensity"),
    A_IGN("MeshMatrixMass", "lumping", "Pliant's masses are lumped"),
    A_IGN("UniformMass", "handleTopologicalChanges", "topology changes are not simulated"),
    A_IGN("UniformMass", "showAxisSizeFactor", "drawing"),
    A_REF("UniformMass", "filename", "rigid mass files (Rigid3 bodies) are not in Pliant"),
    /* FEM */
    A_LOW("TetrahedronFEMForceField", "method", "large, polar, svd: Corotational; small refused"),
    A_LOW("TetrahedralCorotationalFEMForceField", "method",
          "large, polar: Corotational; small refused"),
    A_LOW("FastTetrahedralCorotationalForceField", "method",
          "qr, polar, polar2: Corotational; small, linear refused"),
    A_LOW("TriangleFEMForceField", "method", "large: Corotational; small refused"),
    A_LOW("TriangleFEMForceField", "thickness", "membrane thickness (SOFA's default 1)"),
    A_IGN("TetrahedronFEMForceField", "computeGlobalMatrix", FEMTUNE),
    A_IGN("TetrahedronFEMForceField", "updateStiffnessMatrix", FEMTUNE),
    A_IGN("TetrahedronFEMForceField", "assembling", FEMTUNE),
    A_IGN("TetrahedronFEMForceField", "computeVonMisesStress", "an output Pliant does not compute"),
    A_IGN("TetrahedronFEMForceField", "localStiffnessFactor", FEMTUNE),
    A_IGN("TetrahedralCorotationalFEMForceField", "computeGlobalMatrix", FEMTUNE),
    A_IGN("TetrahedralCorotationalFEMForceField", "assembling", FEMTUNE),
    A_REF("TetrahedronFEMForceField", "plasticMaxThreshold", "plasticity is not in Pliant"),
    A_REF("TetrahedronFEMForceField", "plasticYieldThreshold", "plasticity is not in Pliant"),
    A_REF("TetrahedronFEMForceField", "plasticCreep", "plasticity is not in Pliant"),
    A_REF("TetrahedronFEMForceField", "rotations", "given element rotations are not in Pliant"),
    A_REF("TetrahedronFEMForceField", "initialPoints", "a rest shape apart from the mesh: "
                                                       "use MechanicalObject rest_position"),
    /* springs */
    A_LOW("RestShapeSpringsForceField", "points", "the held points (or @ROI.indices)"),
    A_LOW("RestShapeSpringsForceField", "indices", "the held points"),
    A_LOW("RestShapeSpringsForceField", "stiffness", ">= 1e9: held exactly; else springs"),
    A_IGN("RestShapeSpringsForceField", "angularStiffness", "rotational stiffness of Rigid3 "
                                                            "points: none in Vec3"),
    A_IGN("RestShapeSpringsForceField", "recompute_indices", "indices are read once"),
    A_REF("RestShapeSpringsForceField", "external_rest_shape",
          "springs towards another object are not mapped; closest: PositionTarget"),
    A_REF("RestShapeSpringsForceField", "external_points", "not mapped"),
    /* forces */
    A_LOW("ConstantForceField", "force", "forces = force (one vector for every point)"),
    A_LOW("ConstantForceField", "indices", "numbers or @ROI.indices"),
    A_REF("ConstantForceField", "indexFromEnd", "not mapped: give the indices"),
    A_IGN("ConstantForceField", "arrowSizeCoef", "drawing"),
    A_REF("PlaneForceField", "maxForce", "a force cap is not mapped (the force is "
                                         "stiffness * depth); remove it"),
    A_REF("PlaneForceField", "localRange", "not mapped: the plane acts on every point"),
    A_IGN("PlaneForceField", "planeColor", "drawing"),
    /* constraints */
    A_LOW("FixedConstraint", "indices", "numbers or @ROI.indices"),
    A_LOW("FixedProjectiveConstraint", "indices", "numbers or @ROI.indices"),
    A_IGN("FixedProjectiveConstraint", "activate_projectVelocity", "Pliant eliminates the "
                                                                    "vertices: velocity 0"),
    A_IGN("FixedConstraint", "activate_projectVelocity", "Pliant eliminates the vertices"),
    /* solvers (tuning) */
    A_LOW("EulerImplicitSolver", "rayleighMass", "LinearizedEulerSolver rayleighMass; with "
                                                 "constraints LocalGlobalSolver damping [1/s]"),
    A_LOW("EulerImplicitSolver", "rayleighStiffness",
          "LinearizedEulerSolver rayleighStiffness; with constraints LocalGlobalSolver "
          "rayleighStiffness (damping matrix: the rest stiffness, not the current K)"),
    A_LOW("EulerImplicitSolver", "vdamping", "refused unless 0"),
    A_LOW("EulerImplicitSolver", "firstOrder",
          "LinearizedEulerSolver firstOrder; with constraints LocalGlobalSolver firstOrder "
          "(both: Rayleigh factors unused, as in SOFA)"),
    A_IGN("EulerImplicitSolver", "trapezoidalScheme", TUNE),
    A_IGN("EulerImplicitSolver", "solveConstraint", TUNE),
    A_IGN("EulerImplicitSolver", "threadSafeVisitor", TUNE),
    A_LOW("CGLinearSolver", "iterations", "LinearizedEulerSolver iterations"),
    A_LOW("CGLinearSolver", "tolerance", "LinearizedEulerSolver tolerance (|r| / |b|)"),
    A_LOW("CGLinearSolver", "threshold", "LinearizedEulerSolver threshold (smallest p.Ap)"),
    A_IGN("CGLinearSolver", "warmStart", TUNE),
    A_IGN("PCGLinearSolver", "iterations", TUNE),
    A_IGN("PCGLinearSolver", "tolerance", TUNE),
    A_IGN("PCGLinearSolver", "preconditioner", TUNE),
    A_IGN("PCGLinearSolver", "use_precond", TUNE),
    A_IGN("PCGLinearSolver", "update_step", TUNE),
    A_IGN("SparseLDLSolver", "parallelInverseProduct", TUNE),
    A_IGN("SparseLDLSolver", "useSymbolicDecomposition", TUNE),
    A_IGN("SparseLDLSolver", "applyPermutation", TUNE),
    A_IGN("SparseLDLSolver", "ordering", TUNE),
    A_IGN("*", "maxIterations", TUNE),
    A_IGN("*", "maxIt", TUNE),
    A_IGN("*", "tolerance", TUNE),
    A_IGN("*", "resolutionMethod", TUNE),
    A_IGN("*", "regularizationTerm", TUNE),
    A_IGN("*", "computeConstraintForces", TUNE),
    A_IGN("*", "multi_grid", TUNE),
    A_IGN("*", "build_lcp", TUNE),
    A_IGN("*", "verbose", "logging"),
    A_IGN("*", "depth", "collision pipeline tuning"),
    A_IGN("*", "response", "collision response of models Pliant refuses"),
    A_IGN("*", "responseParams", "collision response of models Pliant refuses"),
    A_IGN("*", "alarmDistance", "collision pipeline without collision models"),
    A_IGN("*", "contactDistance", "collision pipeline without collision models"),
    A_IGN("*", "angleCone", "collision pipeline without collision models"),
    A_IGN("*", "linearSolver", "Pliant has one global solver"),
    A_IGN("*", "ODESolver", "Pliant has one integrator"),
    A_IGN("*", "solverName", "Pliant has one global solver"),
    /* BoxROI */
    A_LOW("BoxROI", "box", "the boxes (xmin ymin zmin xmax ymax zmax each)"),
    A_IGN("BoxROI", "doUpdate", "the selection is made once, on rest positions"),
    A_IGN("BoxROI", "computeEdges", "only vertex indices are linked"),
    A_IGN("BoxROI", "computeTriangles", "only vertex indices are linked"),
    A_IGN("BoxROI", "computeTetrahedra", "only vertex indices are linked"),
    A_IGN("BoxROI", "computeHexahedra", "only vertex indices are linked"),
    A_IGN("BoxROI", "computeQuad", "only vertex indices are linked"),
    A_IGN("BoxROI", "strict", "vertex indices are points; for tetrahedronIndices (IndexValueMapper) it is honoured"),
    A_REF("BoxROI", "orientedBox", "oriented boxes are not mapped; use axis-aligned boxes"),
    A_LOW("BoxROI", "position", "@dofs.rest_position (or a loader of the node): the rest "
                                "positions Pliant's boxes select from; other points refused"),
    /* mappings */
    A_LOW("BarycentricMapping", "input", "the parent's MechanicalObject"),
    A_LOW("BarycentricMapping", "output", "the child node's MechanicalObject"),
    A_LOW("BarycentricMapping", "mapConstraints", "must stay true for a cable"),
    A_IGN("BarycentricMapping", "mapForces", "the cable's force acts on the body through "
                                             "the mapping in any case"),
    A_IGN("BarycentricMapping", "mapMasses", "mapped points carry no mass in Pliant"),
    A_IGN("BarycentricMapping", "isMechanical", "alias of mapForces"),
    A_REF("BarycentricMapping", "useRestPosition", "not mapped"),
    A_LOW("IdentityMapping", "input", "the parent's MechanicalObject"),
    A_LOW("IdentityMapping", "output", "the child node's MechanicalObject"),
    /* CableConstraint */
    A_LOW("CableConstraint", "indices", "in a mapped child node: the mapped points"),
    A_LOW("CableConstraint", "method", "point; sphere and geodesic pull areas of surfaceTopology"),
    A_LOW("CableConstraint", "radii", "the radius of each center's pulled area"),
    A_REF("CableConstraint", "surfaceTopology", "only for a surface cable (method sphere or "
                                                "geodesic) in a mapped child node with a loader"),
    A_IGN("CableConstraint", "hasDisplacementVariation", "Pliant reads the bounds given"),
    /* SurfacePressureConstraint */
    A_LOW("SurfacePressureConstraint", "triangles",
          "in a mapped child node: over the mapped points; a link to the node's loader's "
          "triangles (@topo.triangles) means the loader's"),
    A_IGN("SurfacePressureConstraint", "drawPressure", "drawing"),
    A_IGN("SurfacePressureConstraint", "drawScale", "drawing"),
    A_IGN("SurfacePressureConstraint", "visualization", "drawing (deprecated name)"),
    A_IGN("SurfacePressureConstraint", "showVisuScale", "drawing (deprecated name)"),
    /* InteractiveCamera places the viewer's camera (position, lookAt,
     * orientation, fieldOfView); SOFA's clipping and projection settings
     * have no counterpart there */
    A_IGN("InteractiveCamera", "distance", "the viewer frames the scene from position and lookAt"),
    A_IGN("InteractiveCamera", "zNear", "the viewer's clipping planes follow the scene"),
    A_IGN("InteractiveCamera", "zFar", "the viewer's clipping planes follow the scene"),
    A_IGN("InteractiveCamera", "computeZClip", "the viewer's clipping planes follow the scene"),
    A_IGN("InteractiveCamera", "projectionType", "the viewer draws in perspective"),
    {NULL, NULL, PL_SOFA_A_IGNORE, NULL, NULL}};

const pl_sofa_component *pl_sofa_components(void) { return COMPONENTS; }
const pl_sofa_attr *pl_sofa_attrs(void) { return ATTRS; }

const pl_sofa_component *pl_sofa_find(const char *sofa)
{
    for (const pl_sofa_component *c = COMPONENTS; c->sofa; ++c)
        if (!strcmp(c->sofa, sofa)) return c;
    return NULL;
}

static int is_drawing(const char *attr)
{
    static const char *const pre[] = {"draw", "show", "display"};
    for (int k = 0; k < 3; ++k) {
        size_t l = strlen(pre[k]);
        if (!strncmp(attr, pre[k], l) && (isupper((unsigned char)attr[l]) || attr[l] == '_'))
            return 1;
    }
    return 0;
}

const pl_sofa_attr *pl_sofa_find_attr(const char *component, const char *attr)
{
    static const pl_sofa_attr drawing = {"*", "draw*, show*, display*", PL_SOFA_A_IGNORE, NULL,
                                         "drawing"};
    for (const pl_sofa_attr *a = ATTRS; a->sofa; ++a)
        if (!strcmp(a->component, component) && !strcmp(a->sofa, attr)) return a;
    for (const pl_sofa_attr *a = ATTRS; a->sofa; ++a)
        if (!strcmp(a->component, "*") && !strcmp(a->sofa, attr)) return a;
    return is_drawing(attr) ? &drawing : NULL;
}

int pl_sofa_module(const char *name, const char **why)
{
    static const char *const noted[] = {"SofaPython3", "STLIB", "Sofa.GL", "SofaOpenglVisual",
                                        "SofaCUDA", "ArticulatedSystemPlugin", NULL};
    *why = NULL;
    if (!strncmp(name, "Sofa.", 5) || !strncmp(name, "Sofa", 4)) {
        for (int k = 0; noted[k]; ++k)
            if (!strcmp(name, noted[k])) return 1;
        if (!strncmp(name, "Sofa.", 5) || !strncmp(name, "Sofa", 4)) return 1;
    }
    for (int k = 0; noted[k]; ++k)
        if (!strcmp(name, noted[k])) return 1;
    if (!strcmp(name, "SoftRobots")) return 2;
    if (!strncmp(name, "SoftRobots.Inverse", 18)) {
        *why = "inverse problems (SoftRobots.Inverse) are not in Pliant";
        return -1;
    }
    return 0;
}

/* ---- written out (pliant/sofa.h) ----------------------------------------- */

static const char *const KIND[] = {"same", "renamed", "visual (ignored)", "noted (no physics)",
                                   "lowered", "refused"};
static const char *const AKIND[] = {"renamed", "ignored", "refused", "lowered"};

static int write_tsv(FILE *f)
{
    for (const pl_sofa_component *c = COMPONENTS; c->sofa; ++c)
        fprintf(f, "component\t%s\t%s\t%s\t%s\t%s\n", c->sofa, KIND[c->kind],
                c->pliant ? c->pliant : "", c->plugin ? c->plugin : "", c->note ? c->note : "");
    for (const pl_sofa_attr *a = ATTRS; a->sofa; ++a)
        fprintf(f, "attribute\t%s\t%s\t%s\t%s\t%s\n", a->component, a->sofa, AKIND[a->kind],
                a->pliant ? a->pliant : "", a->note ? a->note : "");
    return ferror(f) ? -1 : 0;
}

static int write_markdown(FILE *f)
{
    fprintf(f, "# SOFA vocabulary\n\nGenerated by `pliant doc --sofa` from the table in "
               "core/src/sofa_vocab.c; do not edit by hand.\ndocs/sofa.md explains what the "
               "kinds mean and how a SOFA scene becomes a Pliant one.\n\n## Components\n\n"
               "| SOFA component | kind | in Pliant | plugin | what Pliant does, or why not |\n"
               "| --- | --- | --- | --- | --- |\n");
    for (const pl_sofa_component *c = COMPONENTS; c->sofa; ++c)
        fprintf(f, "| `%s` | %s | %s%s%s | %s | %s |\n", c->sofa, KIND[c->kind],
                c->pliant ? "`" : "", c->pliant ? c->pliant : "", c->pliant ? "`" : "",
                c->plugin ? c->plugin : "", c->note ? c->note : "");
    fprintf(f, "\n## Attributes\n\nAttributes not listed pass unchanged to the Pliant field of "
               "the same name (an unknown one is an error naming the closest field); `draw*`, "
               "`show*` and `display*` attributes are drawing and ignored.\n\n"
               "| SOFA component | attribute | kind | Pliant field | note |\n"
               "| --- | --- | --- | --- | --- |\n");
    for (const pl_sofa_attr *a = ATTRS; a->sofa; ++a)
        fprintf(f, "| %s | `%s` | %s | %s | %s |\n",
                strcmp(a->component, "*") ? a->component : "any", a->sofa, AKIND[a->kind],
                a->pliant ? a->pliant : "", a->note ? a->note : "");
    return ferror(f) ? -1 : 0;
}

int pl_sofa_write_vocabulary(void *stdio_file, const char *format)
{
    FILE *f = stdio_file;
    if (!f || !format) return -1;
    if (!strcmp(format, "markdown")) return write_markdown(f);
    if (!strcmp(format, "tsv")) return write_tsv(f);
    return -1;
}
