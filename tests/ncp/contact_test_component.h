/* contact_test_component.h - a plugin-free constraint component for the
 * NonSmoothNewtonContactSolver tests ("TestConstraint"), registered into a
 * registry the test creates, and helpers to run scenes with it.
 *
 * Modes (field `mode`):
 *   plane     every vertex with y < alarm at the start of the step gets a
 *             normal row (0 1 0) against the plane y = 0 and two friction
 *             rows (1 0 0), (0 0 1) with the field mu;
 *   pin       a bilateral row y = height on each of `vertices` (or, when none
 *             are given, the vertices with y >= above at the first step);
 *   bounded   the same rows as bounded rows, lambda in [lo, hi];
 * with pairs="1", `vertices` are taken in pairs (a, b) and each row holds
 * the midpoint, (y_a + y_b) / 2 = height (rows with two vertices).
 * It keeps the multipliers it was handed back and a few sums in its
 * workspace of each data (test_probe). */
#ifndef CONTACT_TEST_COMPONENT_H
#define CONTACT_TEST_COMPONENT_H

#include <pliant/pliant.h>

typedef struct test_constraint {
    pl_component base;
    int mode;
    double alarm, mu, height, compliance, lo, hi, above;
    pl_ints vertices;
    int pairs;
} test_constraint;

/* What the last step of a data handed back: the component's workspace in
 * that data (a step writes no component). */
typedef struct test_probe {
    int *selected;           /* pin/bounded without vertices: chosen at the first step */
    int nselected;
    int nrows;               /* rows emitted by this component */
    double *lambda;          /* nrows */
    double sum_normal;       /* sum of lambda over normal rows [N] */
    double sum_rows;         /* sum of lambda over bilateral/bounded rows [N] */
    double sum_friction[3];  /* sum of friction force vectors [N] */
    double cone_excess;      /* max over contacts of |lambda_f| - mu lambda_n (1 + 1e-6) [N] */
    double min_normal;       /* min lambda_n [N] */
    int ncontacts;
    double total_mass;       /* sum of the system's vertex masses [kg] */
} test_probe;

extern const pl_type test_constraint_type;

/* A scene with its own registry (built-ins + TestConstraint). */
typedef struct test_scene {
    pl_registry *reg;
    pl_sim *sim;
} test_scene;

/* Loads xml (fails the test with the diagnostics on error); overrides
 * "path.field=value" (may be NULL). */
void ts_load(test_scene *t, const char *xml, const char *const *overrides, int noverrides);
void ts_free(test_scene *t);
void ts_step(test_scene *t, int n);
/* positions / velocities of the state at path (owned by the sim) */
const double *ts_positions(test_scene *t, const char *path, int *n);
const double *ts_velocities(test_scene *t, const char *path, int *n);
/* the probe of the constraint at path in the sim's data */
test_probe *ts_constraint(test_scene *t, const char *path);
/* lowest y over the state's vertices [m] */
double ts_min_y(test_scene *t, const char *path);
/* mean of coordinate k of the velocities (uniform grids with DiagonalMass
 * are not uniform in mass: use masses when given, else plain mean) */
double ts_mean_velocity(test_scene *t, const char *path, const double *mass, int k);
double *ts_masses(test_scene *t, const char *mass_path, int n);

#endif
