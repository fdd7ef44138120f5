/* test_sofa_errors.c - broken or unsupported SOFA scenes: each is refused
 * with the file, the line of the offending element, the component and why
 * (and the closest alternative where there is one); none runs silently
 * wrong.  One table of cases: a body part spliced into a SOFA scene, the
 * text the error must contain, its line and the component named. */
#include <check.h>
#include <stdio.h>
#include <string.h>

#include "cable/cable_test_util.h"

#define MESH PL_SOURCE_DIR "/scenes/meshes/finger.vtk"

/* Lines 1-7 are fixed; the case's body starts on line 8.  %s: the root's
 * loop and constraint solver (line 3), then the body (from line 8). */
static const char *SCENE =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"                  /* 1 */
    "<RequiredPlugin pluginName=\"SoftRobots Sofa.Component.Mass\"/>\n"         /* 2 */
    "%s\n"                                                                       /* 3 */
    "<Node name=\"finger\">\n"                                                   /* 4 */
    "<EulerImplicitSolver name=\"ode\" %s/><CGLinearSolver iterations=\"25\"/>\n" /* 5 */
    "<MeshVTKLoader name=\"loader\" filename=\"" MESH "\"/>\n"                   /* 6 */
    "<MechanicalObject name=\"dofs\" %s/><UniformMass totalMass=\"0.5\"/>\n"     /* 7 */
    "%s"                                                                         /* 8.. */
    "</Node></Node>\n";

#define FREE_MOTION "<FreeMotionAnimationLoop/><GenericConstraintSolver/>"
#define CABLE_NODE(mo, cable, map)                                                   \
    "<Node name=\"cable\">\n<MechanicalObject name=\"pts\" " mo "/>\n" cable "\n" map \
    "\n</Node>\n"

typedef struct {
    const char *loop, *ode, *mo, *body;
    const char *what;  /* the message contains it */
    int line;          /* of the offending element */
    const char *where; /* the component path or type contains it */
} bad_case;

static const bad_case CASES[] = {
    /* a state Pliant does not have: refused in the state and named */
    {"", "", "template=\"Rigid3\"", "", "\"Rigid3\"", 7, "MechanicalObject"},
    {"", "", "", "<UniformMass name=\"m2\" template=\"Rigid3d\" totalMass=\"1\"/>\n", "rigid", 8,
     "m2"},
    /* known SOFA components Pliant does not do: why, and the alternative */
    /* SOFA's penalty plane and per-element values, given wrong */
    {"", "", "", "<PlaneForceField name=\"plane\" normal=\"0 0 0\"/>\n", "non-zero, finite normal",
     8, "plane"},
    {"", "", "", "<PlaneForceField name=\"plane\" maxForce=\"5\"/>\n", "force cap", 8, "plane"},
    {"", "", "",
     "<IndexValueMapper name=\"ivm\" indices=\"0 1 999999\" value=\"5\"/>\n"
     "<TetrahedronFEMForceField youngModulus=\"@ivm.outputValues\"/>\n",
     "999999 is not an element of the node's mesh", 8, "ivm"},
    {"", "", "",
     "<BoxROI name=\"b\" box=\"0 0\"/>\n<IndexValueMapper name=\"ivm\" "
     "indices=\"@b.tetrahedronIndices\" value=\"5\"/>\n"
     "<TetrahedronFEMForceField youngModulus=\"@ivm.outputValues\"/>\n",
     "expected 6 numbers per box", 8, "b"},
    /* SOFA's grids and still inline surfaces, given wrong */
    {"", "", "",
     "<RegularGridTopology name=\"g\" n=\"1 5 5\" min=\"0 0 0\" max=\"1 1 1\"/>\n"
     "<TetrahedronSetTopologyContainer name=\"c\"/>\n"
     "<Hexa2TetraTopologicalMapping input=\"@g\" output=\"@c\"/>\n",
     "n: 1 vertices along x", 8, "g"},
    {"", "", "",
     "<RegularGridTopology name=\"g\" n=\"2 2\" min=\"0 0 0\" max=\"1 1 1\"/>\n"
     "<TetrahedronSetTopologyContainer name=\"c\"/>\n"
     "<Hexa2TetraTopologicalMapping input=\"@g\" output=\"@c\"/>\n",
     "expected three vertex counts", 8, "g"},
    {"", "", "",
     "<RegularGridTopology name=\"g\" n=\"2 2 2\" min=\"0 0 0\" max=\"1 0 1\"/>\n"
     "<TetrahedronSetTopologyContainer name=\"c\"/>\n"
     "<Hexa2TetraTopologicalMapping input=\"@g\" output=\"@c\"/>\n",
     "max must be above min", 8, "g"},
    {"", "", "",
     "<TriangleCollisionModel name=\"fc\"/>\n"
     "</Node><Node name=\"floor\"><TriangleSetTopologyContainer name=\"t\" "
     "position=\"0 0 0 1 0 0 0 0 1\" triangles=\"0 1 3\"/>\n"
     "<MechanicalObject/><TriangleCollisionModel moving=\"0\" simulated=\"0\"/>\n",
     "triangles: '3' is not one of the 3 points", 9, "t"},
    {"", "", "",
     "<IndexValueMapper name=\"ivm\" indices=\"@dofs.position\" value=\"5\"/>\n"
     "<TetrahedronFEMForceField youngModulus=\"@ivm.outputValues\"/>\n",
     "only a BoxROI's tetrahedronIndices", 8, "ivm"},
    {"", "", "", "<SphereROI name=\"s\" centers=\"0 0 0\" radii=\"1\"/>\n", "closest: BoxROI", 8,
     "SphereROI"},
    {"", "", "", "<PartialFixedProjectiveConstraint indices=\"0\"/>\n", "some directions", 8,
     "PartialFixedProjectiveConstraint"},
    {"", "", "", "<TetrahedronFEMForceField name=\"fem\" method=\"small\"/>\n",
     "without rotations", 8, "fem"},
    {"", "", "", "<TetrahedronFEMForceField name=\"fem\" plasticYieldThreshold=\"0.1\"/>\n",
     "plasticity", 8, "fem"},
    {"", "", "", "<DiagonalMass name=\"dm\" totalMass=\"1\"/>\n", "UniformMass totalMass", 8,
     "dm"},
    /* an unknown name in a SOFA scene */
    {"", "", "", "<FooBarForceField/>\n",
     "unknown component type 'FooBarForceField': neither a Pliant component nor a SOFA", 8, ""},
    {"", "", "", "<TetrahedronFEMForceFeld/>\n", "did you mean SOFA's TetrahedronFEMForceField?",
     8, ""},
    /* a Lagrangian constraint without FreeMotionAnimationLoop: SOFA ignores
     * it; the message names the constraint's own type */
    {"", "", "",
     CABLE_NODE("position=\"-17.5 12.5 2.5\"", "<CableConstraint indices=\"0\"/>",
                "<BarycentricMapping/>"),
     "SOFA solves it only with FreeMotionAnimationLoop", 10, "CableConstraint"},
    /* SOFA's Rayleigh factors are >= 0 (with a cable too) */
    {FREE_MOTION, "rayleighStiffness=\"-0.1\"", "",
     CABLE_NODE("position=\"-17.5 12.5 2.5\"", "<CableConstraint indices=\"0\"/>",
                "<BarycentricMapping/>"),
     "expected a number >= 0", 5, "ode"},
    {"", "vdamping=\"1\"", "", "", "velocity damping", 5, "ode"},
    {"", "", "", "</Node><Node name=\"other\"><MechanicalObject name=\"loose\" "
                 "position=\"0 0 0\"/>\n",
     "no EulerImplicitSolver", 8, "loose"},
    /* a cable SOFA would not solve, or whose indices do not exist */
    {"<DefaultAnimationLoop/>", "", "",
     CABLE_NODE("position=\"-17.5 12.5 2.5 -32.5 12.5 2.5\"",
                "<CableConstraint indices=\"0 1\" pullPoint=\"0 12.5 2.5\"/>",
                "<BarycentricMapping/>"),
     "FreeMotionAnimationLoop", 10, "CableConstraint"},
    {FREE_MOTION, "", "",
     CABLE_NODE("position=\"-17.5 12.5 2.5 -32.5 12.5 2.5\"",
                "<CableConstraint name=\"c\" indices=\"0 2\" pullPoint=\"0 12.5 2.5\"/>",
                "<BarycentricMapping/>"),
     "not one of the 2 mapped points", 10, "c"},
    {FREE_MOTION, "", "",
     CABLE_NODE("position=\"-17.5 12.5 2.5 -32.5 12.5 2.5\"",
                "<CableConstraint indices=\"0 1\" pullPoint=\"0 12.5 2.5\"/>",
                "<BarycentricMapping name=\"map\" input=\"@pts\"/>"),
     "parent node's MechanicalObject", 11, "map"},
    {FREE_MOTION, "", "",
     CABLE_NODE("position=\"-17.5 12.5 2.5 -32.5 12.5 2.5\"",
                "<CableConstraint indices=\"0 1\" pullPoint=\"0 12.5 2.5\"/>",
                "<BarycentricMapping name=\"map\" mapConstraints=\"false\"/>"),
     "act on nothing", 11, "map"},
    {FREE_MOTION, "", "",
     CABLE_NODE("position=\"@../loader.position\"",
                "<CableConstraint indices=\"0 1\" pullPoint=\"0 12.5 2.5\"/>",
                "<BarycentricMapping/>"),
     "as numbers", 9, "pts"},
    {FREE_MOTION, "", "",
     CABLE_NODE("position=\"-17.5 12.5 2.5\"",
                "<CableConstraint indices=\"0\" method=\"geodesic\"/>", "<BarycentricMapping/>"),
     "geodesic", 10, "CableConstraint"},
    /* a mapped cavity with neither a loader nor triangles: no surface to inflate */
    {FREE_MOTION, "", "",
     CABLE_NODE("", "<SurfacePressureConstraint name=\"spc\" value=\"40\"/>",
                "<BarycentricMapping/>"),
     "the cavity has no triangles", 10, "spc"},
    /* BoxROI and links */
    {"", "", "",
     "<BoxROI name=\"ROI\" box=\"-15 0 0 5 10 15\"/>\n"
     "<FixedProjectiveConstraint name=\"fix\" indices=\"@ROI.triangleIndices\"/>\n",
     "only a BoxROI's point indices", 9, "fix"},
    {"", "", "", "<BoxROI name=\"ROI\" box=\"-15 0 0 5 10\"/>\n"
                 "<FixedConstraint indices=\"@ROI.indices\"/>\n",
     "6 numbers per box", 8, "ROI"},
    {"", "", "", "<BoxROI name=\"ROI\" box=\"-15 0 0 5 10 15\" orientedBox=\"1 2 3\"/>\n",
     "oriented boxes", 8, "ROI"},
    /* a BoxROI over other points than the body's rest positions */
    {"", "", "", "<Node name=\"o\"><MechanicalObject name=\"pts\" position=\"0 0 0\"/></Node>\n"
                 "<BoxROI name=\"ROI\" box=\"-15 0 0 5 10 15\" position=\"@o/pts.position\"/>\n"
                 "<FixedConstraint indices=\"@ROI.indices\"/>\n",
     "other points are not mapped", 9, "ROI"},
    {"", "", "", "<BoxROI name=\"ROI\" box=\"-15 0 0 5 10 15\"/>\n"
                 "<RestShapeSpringsForceField name=\"rs\" points=\"@ROI.indices\" "
                 "stiffness=\"100\"/>\n",
     "explicit indices", 9, "rs"},
    /* topology containers */
    {"", "", "", "<TetrahedronSetTopologyContainer name=\"topo\"/>\n", "without a loader", 8,
     "topo"},
    {"", "", "", "<Node name=\"n\"><EulerImplicitSolver/><CGLinearSolver/><MechanicalObject/>"
                 "<TetrahedronSetTopologyContainer name=\"topo\" src=\"@../loader\"/></Node>\n",
     "another node", 8, "topo"},
    /* collision models that could touch each other (two nodes), one of them on
     * points of no state: the body's is mapped, the other refused */
    {"", "", "", "<PointCollisionModel name=\"pc\"/>\n<Node name=\"sub\">"
                 "<TriangleCollisionModel/></Node>\n",
     "TriangleCollisionModel here: on a body", 9, "sub"},
    /* a rigid body's mapping: a known SOFA component, refused with the reason */
    {"", "", "", "<Node name=\"v\"><MechanicalObject name=\"m\" position=\"0 0 0\"/>"
                 "<RigidMapping name=\"rm\"/></Node>\n",
     "rigid body", 8, "rm"},
    /* an old SOFA scene format */
    {"", "", "", "<include href=\"x.xml\"/>\n", "<include>", 8, ""},
};

START_TEST(bad_sofa_scene)
{
    const bad_case *c = &CASES[_i];
    char xml[8192];
    snprintf(xml, sizeof xml, SCENE, c->loop, c->ode, c->mo, c->body);
    pl_diag d = ct_load_fail(xml);
    const pl_error *e = ct_find_error(&d, c->what);
    if (!e) {
        fprintf(stderr, "case %d: no error containing '%s' in:\n", _i, c->what);
        pl_diag_print(&d, stderr);
    }
    ck_assert_ptr_nonnull(e);
    ck_assert_str_eq(e->file, "scene.xml");
    ck_assert_int_eq(e->line, c->line);
    if (!strstr(e->where, c->where) && !strstr(e->msg, c->where))
        ck_abort_msg("case %d: '%s' / '%s' does not name %s", _i, e->where, e->msg, c->where);
    ck_assert_int_eq(pl_diag_status(&d), PL_EINPUT);
    pl_diag_free(&d);
}
END_TEST

/* The same scene without the fault loads: each case fails for its fault. */
START_TEST(good_sofa_scene_loads)
{
    char xml[8192];
    snprintf(xml, sizeof xml, SCENE, FREE_MOTION, "", "",
             CABLE_NODE("position=\"-17.5 12.5 2.5 -32.5 12.5 2.5\"",
                        "<CableConstraint indices=\"0 1\" pullPoint=\"0 12.5 2.5\"/>",
                        "<BarycentricMapping name=\"map\" input=\"@../dofs\" output=\"@pts\"/>"));
    pl_sim *s = ct_load(xml);
    pl_sim_free(s);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("sofa_errors");
    TCase *tc = tcase_create("errors");
    tcase_set_timeout(tc, 120);
    tcase_add_loop_test(tc, bad_sofa_scene, 0, (int)(sizeof CASES / sizeof CASES[0]));
    tcase_add_test(tc, good_sofa_scene_loads);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
