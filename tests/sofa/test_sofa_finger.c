/* test_sofa_finger.c - SoftRobots' cable finger written as a SOFA user
 * writes it (millimetres, TetrahedronFEMForceField, BoxROI + stiff
 * RestShapeSprings, the cable's points in a child node mapped by
 * BarycentricMapping, EulerImplicitSolver + SparseLDLSolver,
 * FreeMotionAnimationLoop + GenericConstraintSolver), against the same
 * finger in Pliant's own vocabulary.  The mapped-cable finger is the
 * project's scene file tests/sofa/scenes/cable_finger.scn; the variants
 * (the cable on body vertices, under an IdentityMapping) are that scene with
 * the cable part replaced.
 *  - the SOFA scene and the native one agree vertex by vertex (1e-9 mm):
 *    the mapped cable's indices name the mapped points, whose positions
 *    follow the tetrahedra containing them;
 *  - the cable is shortened by the commanded 10 mm (its displacement
 *    output, and its length recomputed here from the interpolated points),
 *    pulling (tension > 0);
 *  - reading the same indices as body vertices (the cable in the body's
 *    node, SOFA's meaning of unmapped indices) moves the tip differently:
 *    the mapping is honoured, not reinterpreted. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cable/cable_test_util.h"

#define MESH PL_SOURCE_DIR "/scenes/meshes/finger.vtk"
#define CABLE_POINTS                                                                      \
    "-17.5 12.5 2.5  -32.5 12.5 2.5  -47.5 12.5 2.5  -62.5 12.5 2.5  -77.5 12.5 2.5  "  \
    "-83.5 12.5 4.5  -85.5 12.5 6.5  -85.5 12.5 8.5  -83.5 12.5 10.5  -77.5 12.5 12.5 " \
    "-62.5 12.5 12.5  -47.5 12.5 12.5  -32.5 12.5 12.5  -17.5 12.5 12.5"
#define CABLE_ATTRS "pullPoint=\"0.0 12.5 2.5\" value=\"10\" valueType=\"displacement\""

/* The SOFA scene; %s: the cable part (a mapped child node, or not). */
static const char *SOFA =
    "<?xml version=\"1.0\"?>\n"
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
    "  <RequiredPlugin pluginName=\"SoftRobots Sofa.Component.AnimationLoop "
    "Sofa.Component.Mass Sofa.Component.SolidMechanics.FEM.Elastic\"/>\n"
    "  <VisualStyle displayFlags=\"showVisualModels\"/>\n"
    "  <FreeMotionAnimationLoop/>\n"
    "  <GenericConstraintSolver tolerance=\"1e-5\" maxIterations=\"100\"/>\n"
    "  <Node name=\"finger\">\n"
    "    <EulerImplicitSolver name=\"odesolver\" rayleighMass=\"10\"/>\n"
    "    <SparseLDLSolver name=\"preconditioner\" template=\"CompressedRowSparseMatrixMat3x3d\"/>\n"
    "    <MeshVTKLoader name=\"loader\" filename=\"" MESH "\"/>\n"
    "    <TetrahedronSetTopologyContainer name=\"container\" position=\"@loader.position\" "
    "tetras=\"@loader.tetras\"/>\n"
    "    <MechanicalObject name=\"tetras\" template=\"Vec3\"/>\n"
    "    <UniformMass totalMass=\"0.5\"/>\n"
    "    <TetrahedronFEMForceField template=\"Vec3\" name=\"FEM\" method=\"large\" "
    "poissonRatio=\"0.3\" youngModulus=\"18000\"/>\n"
    "    <BoxROI name=\"ROI\" box=\"5 10 15 -15 0 0\" drawBoxes=\"true\"/>\n"
    "    <RestShapeSpringsForceField points=\"@ROI.indices\" stiffness=\"1e12\"/>\n"
    "    <LinearSolverConstraintCorrection/>\n"
    "%s"
    "    <Node name=\"visu\">\n"
    "      <MeshSTLLoader name=\"loader\" filename=\"" PL_SOURCE_DIR "/scenes/meshes/finger.stl\"/>\n"
    "      <OglModel src=\"@loader\" color=\"0.0 0.7 0.7 1\"/>\n"
    "      <BarycentricMapping/>\n"
    "    </Node>\n"
    "  </Node>\n"
    "</Node>\n";

/* The cable in a child node mapped by BarycentricMapping: the scene file. */
#define MAPPED_CABLE NULL

/* The same indices on the body's own vertices (no mapping). */
static const char *VERTEX_CABLE =
    "    <CableConstraint name=\"aCable\" indices=\"0 1 2 3 4 5 6 7 8 9 10 11 12 13\" " CABLE_ATTRS
    "/>\n";

/* The same indices through an IdentityMapping: the body's vertices. */
static const char *IDENTITY_CABLE =
    "    <Node name=\"cable\">\n"
    "      <MechanicalObject/>\n"
    "      <CableConstraint name=\"aCable\" indices=\"0 1 2 3 4 5 6 7 8 9 10 11 12 13\" " CABLE_ATTRS
    "/>\n"
    "      <IdentityMapping/>\n"
    "    </Node>\n";

/* The same finger in Pliant's vocabulary. */
static const char *NATIVE =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
    "  <RequiredPlugin name=\"hyperelastic\"/><RequiredPlugin name=\"sparse_inverse\"/>\n"
    "  <RequiredPlugin name=\"ncp_contact\"/><RequiredPlugin name=\"cable\"/>\n"
    "  <LocalGlobalSolver iterations=\"20\" damping=\"10\"/>\n"
    "  <SparseInverseSolver/><NonSmoothNewtonContactSolver/>\n"
    "  <Node name=\"finger\">\n"
    "    <MeshLoader name=\"loader\" filename=\"" MESH "\"/>\n"
    "    <MechanicalObject name=\"tetras\"/>\n"
    "    <UniformMass totalMass=\"0.5\"/>\n"
    "    <Corotational name=\"FEM\" poissonRatio=\"0.3\" youngModulus=\"18000\"/>\n"
    "    <FixedConstraint box=\"-15 0 0 5 10 15\"/>\n"
    "    <CableConstraint name=\"aCable\" position=\"" CABLE_POINTS "\" " CABLE_ATTRS "/>\n"
    "  </Node>\n"
    "</Node>\n";

enum { STEPS = 80 };

#define SCENE_FILE PL_SOURCE_DIR "/tests/sofa/scenes/cable_finger.scn"

/* The SOFA scene with the mapped cable: the project's scene file. */
static pl_sim *sofa_finger_file(void)
{
    pl_diag d;
    pl_diag_init(&d);
    pl_sim *s = pl_sim_load_file(SCENE_FILE, NULL, &d);
    if (!s) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(s);
    pl_diag_free(&d);
    return s;
}

static pl_sim *sofa_finger(const char *cable)
{
    if (!cable) return sofa_finger_file();
    static char xml[8192];
    snprintf(xml, sizeof xml, SOFA, cable);
    return ct_load(xml);
}

/* The tip: the rest vertex with the smallest x (the finger points to -x). */
static int tip_vertex(pl_sim *s)
{
    int n, tip = 0;
    const double *x = ct_positions(s, "finger/tetras", 1, &n);
    for (int i = 1; i < n; ++i)
        if (x[3 * i] < x[3 * tip]) tip = i;
    return tip;
}

static double tip_displacement(pl_sim *s, int tip)
{
    int n;
    const double *x = ct_positions(s, "finger/tetras", 0, &n);
    const double *r = ct_positions(s, "finger/tetras", 1, &n);
    double d = 0;
    for (int j = 0; j < 3; ++j) d += (x[3 * tip + j] - r[3 * tip + j]) * (x[3 * tip + j] - r[3 * tip + j]);
    return sqrt(d);
}

START_TEST(mapped_cable_is_the_native_cable)
{
    pl_sim *a = sofa_finger(MAPPED_CABLE), *b = ct_load(NATIVE);
    ct_step(a, STEPS);
    ct_step(b, STEPS);
    int na, nb;
    const double *xa = ct_positions(a, "finger/tetras", 0, &na);
    const double *xb = ct_positions(b, "finger/tetras", 0, &nb);
    ck_assert_int_eq(na, nb);
    double diff = 0, moved = 0;
    const double *r = ct_positions(b, "finger/tetras", 1, &nb);
    for (int i = 0; i < 3 * na; ++i) {
        diff = fmax(diff, fabs(xa[i] - xb[i]));
        moved = fmax(moved, fabs(xb[i] - r[i]));
    }
    ck_assert_double_lt(diff, 1e-9);
    ck_assert_double_gt(moved, 5.0); /* it did bend (mm) */
    /* the lowered components are what the SOFA names promise */
    ck_assert_str_eq(pl_sim_component(a, "finger/FEM")->type->name, "Corotational");
    ck_assert_str_eq(pl_sim_component(a, "odesolver")->type->name, "LocalGlobalSolver");
    ck_assert_double_eq(ct_get(a, "odesolver.damping"), 10.0);
    pl_sim_free(a);
    pl_sim_free(b);
}
END_TEST

/* The length of the cable through the mapped points, recomputed from the
 * body's vertices: each point is the barycentric combination (weights from
 * the rest positions) of the tetrahedron that contains it at rest. */
static double mapped_length(pl_sim *s)
{
    static const double P[14][3] = {{-17.5, 12.5, 2.5},  {-32.5, 12.5, 2.5},  {-47.5, 12.5, 2.5},
                                    {-62.5, 12.5, 2.5},  {-77.5, 12.5, 2.5},  {-83.5, 12.5, 4.5},
                                    {-85.5, 12.5, 6.5},  {-85.5, 12.5, 8.5},  {-83.5, 12.5, 10.5},
                                    {-77.5, 12.5, 12.5}, {-62.5, 12.5, 12.5}, {-47.5, 12.5, 12.5},
                                    {-32.5, 12.5, 12.5}, {-17.5, 12.5, 12.5}};
    const pl_component *ld = pl_sim_component(s, "finger/loader");
    const pl_topology_ops *tops = pl_component_role(ld, PL_ROLE_TOPOLOGY);
    const pl_mesh *m = tops->mesh(ld);
    int n;
    const double *x = ct_positions(s, "finger/tetras", 0, &n);
    const double *r = ct_positions(s, "finger/tetras", 1, &n);
    double prev[3] = {0.0, 12.5, 2.5}, L = 0;
    for (int p = 0; p < 14; ++p) {
        double best = -1e300, w[4] = {0}, q[3] = {0};
        const int *bt = NULL;
        for (int t = 0; t < m->ntets; ++t) {
            const int *v = &m->tets[4 * t];
            double M[9], b[3], l[3];
            for (int j = 0; j < 3; ++j) {
                for (int k = 0; k < 3; ++k) M[3 * j + k] = r[3 * v[k + 1] + j] - r[3 * v[0] + j];
                b[j] = P[p][j] - r[3 * v[0] + j];
            }
            double det = M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
                         M[2] * (M[3] * M[7] - M[4] * M[6]);
            if (fabs(det) < 1e-14) continue;
            for (int k = 0; k < 3; ++k) { /* Cramer */
                double C[9];
                memcpy(C, M, sizeof C);
                for (int j = 0; j < 3; ++j) C[3 * j + k] = b[j];
                l[k] = (C[0] * (C[4] * C[8] - C[5] * C[7]) - C[1] * (C[3] * C[8] - C[5] * C[6]) +
                        C[2] * (C[3] * C[7] - C[4] * C[6])) / det;
            }
            double l0 = 1 - l[0] - l[1] - l[2];
            double worst = fmin(fmin(l0, l[0]), fmin(l[1], l[2]));
            if (worst > best) best = worst, bt = v, w[0] = l0, w[1] = l[0], w[2] = l[1], w[3] = l[2];
        }
        ck_assert_ptr_nonnull(bt);
        ck_assert_double_gt(best, -1e-6); /* inside a tetrahedron */
        for (int k = 0; k < 4; ++k)
            for (int j = 0; j < 3; ++j) q[j] += w[k] * x[3 * bt[k] + j];
        L += sqrt((q[0] - prev[0]) * (q[0] - prev[0]) + (q[1] - prev[1]) * (q[1] - prev[1]) +
                  (q[2] - prev[2]) * (q[2] - prev[2]));
        memcpy(prev, q, sizeof prev);
    }
    return L;
}

START_TEST(mapped_cable_is_shortened_by_the_command)
{
    pl_sim *s = sofa_finger(MAPPED_CABLE);
    double L0 = ct_get(s, "finger/aCable.cableInitialLength");
    ck_assert_double_eq_tol(mapped_length(s), L0, 1e-9);
    ct_step(s, STEPS);
    ck_assert_double_eq_tol(ct_get(s, "finger/aCable.displacement"), 10.0, 0.05);
    ck_assert_double_eq_tol(mapped_length(s), L0 - 10.0, 0.05);
    ck_assert_double_gt(ct_get(s, "finger/aCable.force"), 0.0);
    pl_sim_free(s);
}
END_TEST

START_TEST(indices_are_not_reinterpreted)
{
    pl_sim *m = sofa_finger(MAPPED_CABLE), *v = sofa_finger(VERTEX_CABLE);
    int tip = tip_vertex(m);
    ct_step(m, STEPS);
    ct_step(v, STEPS);
    double dm = tip_displacement(m, tip), dv = tip_displacement(v, tip);
    printf("tip displacement under a 10 mm pull: mapped cable %.2f mm, indices read as body "
           "vertices %.2f mm\n",
           dm, dv);
    ck_assert_double_gt(fabs(dm - dv), 2.0);
    pl_sim_free(m);
    pl_sim_free(v);
}
END_TEST

START_TEST(identity_mapped_cable_is_on_body_vertices)
{
    pl_sim *a = sofa_finger(IDENTITY_CABLE), *b = sofa_finger(VERTEX_CABLE);
    ct_step(a, 20);
    ct_step(b, 20);
    int na, nb;
    const double *xa = ct_positions(a, "finger/tetras", 0, &na);
    const double *xb = ct_positions(b, "finger/tetras", 0, &nb);
    ck_assert_int_eq(na, nb);
    for (int i = 0; i < 3 * na; ++i) ck_assert_double_eq_tol(xa[i], xb[i], 1e-12);
    pl_sim_free(a);
    pl_sim_free(b);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("sofa_finger");
    TCase *tc = tcase_create("finger");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, mapped_cable_is_the_native_cable);
    tcase_add_test(tc, mapped_cable_is_shortened_by_the_command);
    tcase_add_test(tc, indices_are_not_reinterpreted);
    tcase_add_test(tc, identity_mapped_cable_is_on_body_vertices);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
