/* collision.h - the collision plugin's numeric core (static library
 * collision_core): analytic shapes (signed distance, closest surface point,
 * outward normal), their prescribed rigid motion, and the three contact rows
 * of a body point against an obstacle (PAPER_NOTES items 5, 9, 10, 13).
 * No scene code: plain arrays in and out, so the plugin's components and the
 * tests call the same functions.
 *
 * Row conventions (pl_rows, one contact = 3 consecutive rows):
 *   normal   entries w_a n, d = n . p + contactDistance, mu on this row,
 *            pair -> the first friction row; delta = H q - d is the signed
 *            gap along n minus contactDistance (n points out of the obstacle,
 *            p is the closest surface point), so delta >= 0 keeps the gap;
 *   friction entries w_a t_k (k = 1, 2; t1, t2, n right-handed and
 *            orthonormal), d = t_k . v_s (the obstacle's surface velocity at
 *            p), pair -> the normal row.
 * The force on the body is lambda_n n + lambda_t1 t1 + lambda_t2 t2 [N]. */
#ifndef PLIANT_COLLISION_H
#define PLIANT_COLLISION_H

#include "pliant/error.h"
#include "pliant/mesh.h"
#include "pliant/rows.h"
#include "detect.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- shapes --------------------------------------------------------------- */

typedef enum pl_shape_kind {
    PL_SHAPE_PLANE = 0,    /* half-space below the plane is inside */
    PL_SHAPE_SPHERE = 1,
    PL_SHAPE_BOX = 2,
    PL_SHAPE_CAPSULE = 3,  /* segment swept by a ball (rounded ends) */
    PL_SHAPE_CYLINDER = 4  /* flat caps */
} pl_shape_kind;

/* A shape in its own frame, placed by (center, R): x_world = center + R x_local.
 * The local z axis is the plane's normal and the capsule's / cylinder's axis. */
typedef struct pl_shape {
    pl_shape_kind kind;
    double center[3];  /* plane: a point of it; capsule: midpoint of its segment [m] */
    double R[9];       /* local -> world rotation, row-major (columns = local axes) */
    double radius;     /* sphere, capsule, cylinder [m] */
    double half[3];    /* box: half extents; capsule, cylinder: half[2] = half length [m] */
} pl_shape;

/* Constructors: check the arguments (a zero normal or axis, a negative or
 * non-finite size) and return PL_EINPUT with a message, else PL_OK. */
int shape_plane(pl_shape *s, const double point[3], const double normal[3], pl_error *err);
int shape_sphere(pl_shape *s, const double center[3], double radius, pl_error *err);
/* R: the box's orientation (local -> world, row-major), NULL = identity. */
int shape_box(pl_shape *s, const double center[3], const double half[3], const double R[9],
                 pl_error *err);
int shape_capsule(pl_shape *s, const double p0[3], const double p1[3], double radius,
                     pl_error *err);
int shape_cylinder(pl_shape *s, const double center[3], const double axis[3], double radius,
                      double length, pl_error *err);

/* Signed distance phi(x) [m] (negative inside) of the world point x; writes
 * the closest surface point and the unit outward normal there (either may be
 * NULL).  Points with several closest points (the centre of a sphere, the
 * axis of a capsule, ties between box faces) get a fixed choice: the lowest
 * local axis, +x for radial directions. */
double shape_query(const pl_shape *s, const double x[3], double closest[3], double normal[3]);

/* Look-ahead: whether the straight path y0 -> y1 (a body point's motion over
 * a step, relative to the shape) comes within alarm of the surface.  When it
 * does, *t in [0, 1] is the path parameter of its first point at distance
 * <= gap (the kept contactDistance: where the contact will be), or of its
 * nearest point when it comes no closer, and closest / normal are that
 * point's closest surface point and outward normal.  The shapes are convex,
 * so the plane through closest along normal keeps the point out whatever
 * the path does afterwards.  Returns 1 or 0. */
int shape_sweep(const pl_shape *s, const double y0[3], const double y1[3], double alarm,
                   double gap, double *t, double closest[3], double normal[3]);

/* out = the shape moved by the rigid map x -> Rm x + tm. */
void shape_transform(const pl_shape *s, const double Rm[9], const double tm[3], pl_shape *out);

/* A unit vector orthogonal to the unit n and its complement, so that (t1, t2, n)
 * is a right-handed orthonormal frame: Gram-Schmidt of the coordinate axis
 * least aligned with n (the lowest index on ties); deterministic. */
void contact_tangents(const double n[3], double t1[3], double t2[3]);

/* ---- prescribed motion -------------------------------------------------- */

/* A rigid motion from the scene pose, all parts optional and combined:
 *   s(t) = velocity t + key(t)           translation (key: linear between
 *                                        keyframes, constant outside them)
 *   x(t) = c + s(t) + Rot(axis, w t) (x0 - c)
 * with c the rotation centre (it travels with the translation). */
typedef struct pl_motion {
    double velocity[3];        /* [m/s] */
    double axis[3];            /* rotation axis (normalised by motion_prepare) */
    double angular_velocity;   /* [rad/s], right-handed about axis */
    double center[3];          /* a point of the axis at t = 0 [m] */
    const double *times;       /* ntimes keyframe times [s], strictly increasing */
    const double *translations;/* ntimes x 3 translations [m] from the scene pose */
    int ntimes;
} pl_motion;

/* Checks a motion and normalises its axis: finite values, a non-zero axis
 * when angular_velocity != 0, strictly increasing times, ntrans = 3 ntimes
 * translation values.  PL_EINPUT with a message naming the field. */
int motion_prepare(pl_motion *m, int ntrans, pl_error *err);
/* The rigid map of time t: x(t) = R x0 + tr. */
void motion_pose(const pl_motion *m, double t, double R[9], double tr[3]);
/* Velocity [m/s] at time t of the moving body's material point that is at
 * the world point p at time t: s'(t) + w axis x (p - c - s(t)).  Keyframed
 * translation uses its left derivative (the segment ending at t), i.e. the
 * velocity over a step that ends at t; 0 before the first key time. */
void motion_velocity(const pl_motion *m, double t, const double p[3], double v[3]);
/* The rigid map of the motion from time t0 to t1: a point moving with the
 * shape from x at t0 is at R x + tr at t1. */
void motion_step_map(const pl_motion *m, double t0, double t1, double R[9], double tr[3]);
/* Whether the motion moves anything at all. */
int motion_is_static(const pl_motion *m);

/* ---- contacts ------------------------------------------------------------- */

/* One body point against an obstacle, as the plugin records it per step
 * (data slot "contacts" of each obstacle, an array of these). */
typedef struct pl_obstacle_contact {
    double point[3];        /* closest point on the obstacle at t + h [m] */
    double normal[3];       /* outward unit normal there */
    double t1[3], t2[3];    /* tangents of the friction rows */
    double body_point[3];   /* the body point at the start of the step [m] */
    double velocity[3];     /* obstacle surface velocity at point [m/s] */
    double gap;             /* signed distance phi at detection [m] */
    double lambda[3];       /* multipliers: normal, t1, t2 [N] (0 until solved) */
    double force[3];        /* force on the body lambda_n n + lambda_t1 t1 + lambda_t2 t2 [N] */
    int vertex;             /* the body point's first global vertex */
    int model;              /* index of its collision model (scene order) */
} pl_obstacle_contact;

/* ---- motion beyond the prediction (impact.c) ----------------------------- */

/* A collision model's points over a step, summarised: their swept box from
 * the start of the step to the prediction (x + h v + h^2 g for a body; an
 * obstacle's pose at t and t + h) and their mean velocity. */
typedef struct pl_reach {
    pl_aabb box;      /* [m] */
    double v[3];      /* mean velocity [m/s] */
    unsigned groups;
    int n;            /* points */
} pl_reach;

/* n points x (at t, or for an obstacle posed at t + h) with velocities v
 * (NULL: at rest), a body's gravity grav. */
void reach_of(const double *x, const double *v, int n, int is_obstacle, unsigned groups,
                 double h, const double grav[3], pl_reach *r);
/* The relative speed [m/s] at which another of the n models (not model
 * `except`, -1 for none; not sharing a group) can strike model k in this
 * step, as the largest difference of their mean velocities among those
 * whose boxes come within alarm of each other: what an analytic obstacle
 * takes as the strike (a bound that adds the velocity spreads, a spinning
 * rim, made a body gripped by a turning gripper look struck at the rim
 * speed and get rows up to that speed times h from the floor; as the
 * CollisionPipeline's box inflation it made detection's spikes,
 * docs/benchmarks.md). */
double hit_speed(const pl_reach *r, int n, int k, int except, double alarm);

/* ---- messy obstacle meshes (mesh_clean.c) ------------------------------- */

/* What coll_mesh_clean changed and found. */
typedef struct coll_clean_report {
    int degenerate;        /* triangles removed: a repeated vertex or no area */
    int duplicate;         /* triangles removed: a second one on the same three vertices */
    int border_edges;      /* edges of one triangle (left as they are) */
    int nonmanifold_edges; /* edges of three or more triangles (left as they are) */
    int misoriented_edges; /* edges of two triangles that run them the same way */
    int edges;             /* distinct edges */
} coll_clean_report;
/* Removes degenerate and duplicate triangles from m (vertices untouched)
 * and counts the border and non-manifold edges left.  PL_OK or
 * PL_EINTERNAL (out of memory). */
int coll_mesh_clean(pl_mesh *m, coll_clean_report *r);
/* Whether the cleaned surface encloses a volume: at most 1 % of its edges
 * are borders or misoriented (non-manifold fins do not count). */
int coll_mesh_encloses(const coll_clean_report *r);

/* ---- collision groups (groups.c) ----------------------------------------- */
#define PL_COLLISION_MAX_GROUP 32
/* The set of groups a model's `group` field lists, as a bit mask (bit k - 1
 * for group k; 0 in the list means none); PL_EINPUT for a number outside
 * 0..PL_COLLISION_MAX_GROUP. */
int collision_groups(const pl_ints *list, unsigned *mask, pl_error *err);

/* Appends the three rows of contact k (see the top of this file): nv vertices
 * with weights w, the obstacle's closest point p, outward normal n, surface
 * velocity vs, friction mu and contactDistance.  Fills ct's tangents.
 * Returns the normal row's index, or -1 on allocation failure. */
int collision_emit_contact(pl_rows *rows, const pl_component *owner, int nv, const int *vertex,
                              const double *weight, const double p[3], const double n[3],
                              const double vs[3], double mu, double contact_distance,
                              double t1[3], double t2[3]);

/* One side of a contact between two collision models: its points' DOFs as
 * (global vertex, weight) entries, and the part without DOFs (points of an
 * obstacle, or of vertices that are not simulated) as a fixed point at the
 * end of the step with its velocity: the contact point of that side is
 * sum_a weight_a q_a + fixed. */
#define PL_CONTACT_SIDE_MAX 16
typedef struct pl_contact_side {
    int n;
    int vertex[PL_CONTACT_SIDE_MAX];
    double weight[PL_CONTACT_SIDE_MAX];
    double fixed[3];    /* [m] */
    double fixed_v[3];  /* [m/s] */
} pl_contact_side;

/* Appends the three rows of a contact between side a (pushed along n) and
 * side b (PAPER_NOTES item 5): normal entries w n on a's vertices and -w n on
 * b's (a vertex on both sides gets the difference), d = contactDistance +
 * n . (b.fixed - a.fixed); friction entries along t1, t2 likewise with
 * d_f = t . (b.fixed_v - a.fixed_v).  Fills t1 and t2.  Returns the normal
 * row's index, -2 when no entry is left (nothing can move: no rows), -1 on
 * allocation failure. */
int collision_emit_pair(pl_rows *rows, const pl_component *owner, const pl_contact_side *a,
                           const pl_contact_side *b, const double n[3], double mu,
                           double contact_distance, double t1[3], double t2[3]);

/* collision_emit_pair in two halves, so that threads can prepare contacts
 * and their rows land in the contacts' order: collision_pair_prepare merges
 * the sides, orders the entries and makes the tangents and the three rows'
 * right-hand sides (0, or -2 when no entry is left); collision_pair_append
 * appends the prepared rows (the normal row's index, or -1). */
typedef struct pl_pair_rows {
    int n;
    int vertex[2 * PL_CONTACT_SIDE_MAX];
    double coef[2 * PL_CONTACT_SIDE_MAX];
    double normal[3], t1[3], t2[3];
    double d[3]; /* the normal row's, then the two friction rows' */
} pl_pair_rows;
int collision_pair_prepare(pl_pair_rows *pr, const pl_contact_side *a, const pl_contact_side *b,
                           const double n[3], double contact_distance);
int collision_pair_append(pl_rows *rows, const pl_component *owner, const pl_pair_rows *pr,
                          double mu);
/* The entries of the three rows (3 x the nonzero coefficients), and the
 * rows written at rows rn .. rn + 2 and entries e on, room reserved
 * (pl_rows_reserve): what collision_pair_append does at the end, for an
 * emitter that places many pairs in parallel. */
int collision_pair_entries(const pl_pair_rows *pr);
void collision_pair_write(pl_rows *rows, const pl_component *owner, const pl_pair_rows *pr,
                          double mu, int rn, int e);

/* Fills lambda and force of the contacts from the multipliers of their rows
 * (3 per contact in emission order, lambda[0..3 ncontacts-1]). */
void collision_contact_forces(pl_obstacle_contact *c, int ncontacts, const double *lambda);

#ifdef __cplusplus
}
#endif
#endif
