/* detect.h - mesh-versus-mesh proximity detection, the numeric part of the
 * CollisionPipeline (static library collision_core, no scene code):
 *   - narrow phase: closest points point-triangle and segment-segment;
 *   - a bounding-volume hierarchy over axis-aligned boxes, built once from a
 *     mesh's primitives and refitted in the steps that walk it;
 *   - detection between two triangle meshes (or one mesh and itself):
 *     vertex-triangle proximities in both directions and edge-edge
 *     proximities within alarmDistance, with the motion over the step.
 *
 * Conventions of a proximity: side A is pushed along `normal` (the unit
 * normal points from B to A), the gap is the signed distance along it at the
 * start of the step.  One of the two sides may be an obstacle (no DOFs). */
#ifndef PLIANT_COLLISION_DETECT_H
#define PLIANT_COLLISION_DETECT_H

#include "pliant/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- narrow phase ---------------------------------------------------------- */

/* Closest point of the triangle (a, b, c) to p: w = its barycentric weights
 * (w0 a + w1 b + w2 c, all >= 0, summing to 1).  Returns the squared
 * distance.  Degenerate triangles are handled (the closest point of their
 * edges). */
double closest_point_triangle(const double p[3], const double a[3], const double b[3],
                                 const double c[3], double w[3]);

/* Closest points of the segments p0 p1 and q0 q1: p0 + s (p1 - p0) and
 * q0 + t (q1 - q0), s and t in [0, 1].  Returns the squared distance.
 * Parallel segments get one pair of the closest set; points (zero-length
 * segments) are handled. */
double closest_segments(const double p0[3], const double p1[3], const double q0[3],
                           const double q1[3], double *s, double *t);

/* ---- bounding boxes and the BVH ------------------------------------------ */

typedef struct pl_aabb {
    double lo[3], hi[3];
} pl_aabb;

static inline int aabb_overlap(const pl_aabb *a, const pl_aabb *b)
{
    return a->lo[0] <= b->hi[0] && b->lo[0] <= a->hi[0] && a->lo[1] <= b->hi[1] &&
           b->lo[1] <= a->hi[1] && a->lo[2] <= b->hi[2] && b->lo[2] <= a->hi[2];
}

/* Whether a grown by ha on every side overlaps b grown by hb: bitwise
 * aabb_overlap of the grown boxes, whose bounds are a->lo - ha, a->hi + ha
 * and so on, rounded as stored.  Rounding is monotonic, so a union of boxes
 * grown by h is the union grown by h, bitwise: a tree fitted once to
 * ungrown boxes answers for every growth (coll_mesh_inflate costs
 * nothing). */
static inline int aabb_overlap_grown(const pl_aabb *a, double ha, const pl_aabb *b, double hb)
{
    return a->lo[0] - ha <= b->hi[0] + hb && b->lo[0] - hb <= a->hi[0] + ha &&
           a->lo[1] - ha <= b->hi[1] + hb && b->lo[1] - hb <= a->hi[1] + ha &&
           a->lo[2] - ha <= b->hi[2] + hb && b->lo[2] - hb <= a->hi[2] + ha;
}

/* A binary tree over primitive boxes: node 0 is the root, children come
 * after their parent (so refitting runs from the last node back), a leaf
 * holds up to PL_BVH_LEAF primitives order[start .. start + count - 1]. */
#define PL_BVH_LEAF 4
typedef struct pl_bvh {
    int nprims, nnodes;
    pl_aabb *box;       /* per node */
    int *left;          /* per node: first child (its sibling is left + 1), -1 for a leaf */
    int *start, *count; /* per node: its primitives in `order` */
    int *order;         /* primitive indices, grouped by leaf */
} pl_bvh;

void bvh_init(pl_bvh *b);
void bvh_free(pl_bvh *b);
/* Builds the tree over n primitive boxes (median splits of the centres along
 * the widest axis; deterministic) and fits it.  PL_OK or PL_EINTERNAL. */
int bvh_build(pl_bvh *b, const pl_aabb *prims, int n);
/* Refits every node to the primitives' new boxes (same topology). */
void bvh_refit(pl_bvh *b, const pl_aabb *prims);

/* A growable list of ints. */
typedef struct pl_ivec {
    int *v;
    int n, cap;
} pl_ivec;
void ivec_free(pl_ivec *a);
int ivec_push(pl_ivec *a, int x);

/* Appends to out the primitives whose boxes overlap q, in increasing order
 * (the same whatever the tree's shape).
 * PL_OK or PL_EINTERNAL. */
int bvh_query(const pl_bvh *b, const pl_aabb *prims, const pl_aabb *q, pl_ivec *out);
/* The same with the tree's boxes and prims grown by hp and q by hq
 * (aabb_overlap_grown); bvh_query is hp = hq = 0. */
int bvh_query_grown(const pl_bvh *b, const pl_aabb *prims, double hp, const pl_aabb *q,
                    double hq, pl_ivec *out);

/* ---- meshes prepared for detection ----------------------------------------- */

typedef enum pl_mesh_sides {
    PL_SIDES_AUTO = 0, /* one-sided when closed (every edge shared by 2 triangles), else two */
    PL_SIDES_ONE = 1,  /* closed and oriented: only the outside repels, inside points are pushed out */
    PL_SIDES_TWO = 2   /* thin: repels on both sides (cloth, knife blades) */
} pl_mesh_sides;

/* A triangle mesh at the start (x0) and predicted end (x1) of the step.
 * The caller owns x0, x1, tris and edges; detection owns the rest
 * (coll_mesh_prepare / coll_mesh_free). */
typedef struct pl_coll_mesh {
    int nverts, ntris, nedges;
    const double *x0, *x1;      /* nverts x 3 [m] */
    const int *tris;            /* ntris x 3 */
    const int *edges;           /* nedges x 2 */
    const unsigned char *active;/* per vertex: 0 = this point carries no DOF (NULL: all active) */
    pl_mesh_sides sides;
    /* derived, by coll_mesh_prepare */
    int two_sided;              /* resolved from sides */
    double orientation;         /* +1 outward-oriented triangles, -1 flipped (one-sided) */
    double *fnormal;            /* ntris x 3 unit face normals at x0, outward for one-sided */
    int *edge_tris;             /* nedges x 2 adjacent triangles (-1 when missing) */
    unsigned char *sharp;       /* per edge, this step: 0 not asked yet, 1 not sharp, 2 sharp
                                   (coll_edge_sharp) */
    unsigned char *border;      /* per vertex: on an edge with one triangle (the mesh's rim) */
    pl_aabb *vbox, *tbox, *ebox;/* swept boxes of vertices, triangles, edges (x0 to x1, not
                                   grown: compare them with coll_mesh_half) */
    pl_bvh tbvh, ebvh;          /* over tbox and ebox */
    double margin;              /* what the boxes stand for grown by now [m]: margin / 2 on
                                   every side */
    int built;
    int stale;                  /* trees not yet refitted to this step's boxes (COLL_TREE_*) */
} pl_coll_mesh;

/* What a mesh's boxes are grown by on every side when compared [m]. */
static inline double coll_mesh_half(const pl_coll_mesh *m) { return 0.5 * m->margin; }

/* Loops over fewer elements than this run on one thread: waking a team
 * costs more than they do (OMP_WAIT_POLICY=PASSIVE, pliant's default, makes
 * every region a futex wake of each thread; docs/benchmarks.md, "The
 * host detection's fixed cost"). */
#define COLL_PAR_MIN 16384

/* cos of the smallest angle between the face normals of a sharp edge (30 deg) */
#define PL_SHARP_COS 0.8660254037844386

/* Whether edge e of a prepared mesh is a feature that can poke through a
 * surface between its vertices (a boundary edge, a fold, a convex crease
 * of a closed mesh sharper than PL_SHARP_COS), at x0: computed when first
 * asked in a step, then remembered (safe from several threads). */
int coll_edge_sharp(const pl_coll_mesh *m, int e);

void coll_mesh_init(pl_coll_mesh *m);
void coll_mesh_free(pl_coll_mesh *m);
/* Once per step after x0/x1 changed: face normals, swept boxes (compared
 * inflated by margin / 2 on every side [m]), BVHs built on first use and
 * refitted after.  The topology (counts, tris, edges) must not change
 * between calls.  PL_OK, PL_EINPUT (an index out of range), PL_EINTERNAL. */
int coll_mesh_prepare(pl_coll_mesh *m, double margin, pl_error *err);
/* After coll_mesh_prepare, in the same step: the swept boxes compared
 * inflated by margin / 2 instead, for a detection that keeps pairs that
 * much farther apart (the same candidates as a coll_mesh_prepare with that
 * margin, bitwise: aabb_overlap_grown; nothing is recomputed). */
void coll_mesh_inflate(pl_coll_mesh *m, double margin);
/* The trees: of the triangles, of the edges. */
enum { COLL_TREE_TRIS = 1, COLL_TREE_EDGES = 2 };
/* Refits the given trees (COLL_TREE_* bits) to this step's boxes unless
 * done: coll_mesh_prepare leaves them for detect_pair to refit the ones its
 * passes walk (a mesh whose vertices alone are queried, or detected on the
 * device, never needs its edge tree). */
void coll_mesh_fit(pl_coll_mesh *m, int trees);

/* ---- proximities ------------------------------------------------------------ */

typedef enum pl_prox_kind {
    PL_PROX_VERTEX_FACE = 0, /* vertex a[0] of A against triangle b[0..2] of B */
    PL_PROX_EDGE_EDGE = 1    /* edge a[0..1] of A against edge b[0..1] of B */
} pl_prox_kind;

typedef struct pl_proximity {
    int kind;
    int model_a, model_b;
    int na, nb;
    int a[3], b[3];          /* vertices of each mesh */
    double wa[3], wb[3];     /* barycentric weights of the closest points */
    double normal[3];        /* unit, from B to A */
    double gap;              /* signed distance along normal at the start of the step [m] */
    int side;                /* vertex-face against a two-sided mesh: the side of the triangle's
                                oriented face normal the vertex keeps (+1 / -1; 0 otherwise) */
} pl_proximity;

typedef struct pl_proximities {
    pl_proximity *items;
    int n, cap;
} pl_proximities;

void proximities_free(pl_proximities *p);

/* Sides remembered from the previous step: a pair of primitives that was in
 * contact with a thin (two-sided) mesh keeps the side it was on, so that a
 * point pushed slightly through a blade by an unconverged solve is pushed
 * back instead of being kept on the wrong side.  Keys are the proximities'
 * models and vertices; a hash table, rebuilt every step. */
typedef struct pl_side_hints {
    int n, cap;          /* entries, slots (a power of two) */
    unsigned long long *key;
    int *keyed;          /* per slot: its proximity in items (for exact key comparison) */
    pl_proximity *items; /* the proximities given, copied once */
    unsigned long long *hash; /* per item: its identity's hash */
    int nitems, capitems;
    struct pl_side_vf *vf; /* the vertex-face ones, sorted by models and vertex */
    int nvf, capvf;
} pl_side_hints;

void side_hints_init(pl_side_hints *h);
void side_hints_free(pl_side_hints *h);
/* Clears h and inserts the given proximities.  PL_OK or PL_EINTERNAL. */
int side_hints_build(pl_side_hints *h, const pl_proximity *items, int n);
/* The same over proximities `stride` bytes apart (each the first member of
 * a larger record: the pipeline's contacts, copied once, into h). */
int side_hints_build_strided(pl_side_hints *h, const pl_proximity *first, size_t stride, int n);
/* The remembered proximity with the same kind, models and vertices (NULL
 * when none): its normal, and for vertex-face ones its side. */
const pl_proximity *side_hints_find(const pl_side_hints *h, const pl_proximity *p);
/* For a vertex-face proximity without a remembered side: the same vertex's
 * contact last step with a triangle that shares an edge (or else a vertex)
 * with p's triangle, NULL when none.  A vertex sliding under a cloth (a
 * blade's apex) meets new triangles; they take the side of the neighbour it
 * touched (sides are relative to the oriented face normals, which neighbours
 * share), not the side it has reached by now. */
const pl_proximity *side_hints_find_near(const pl_side_hints *h, const pl_proximity *p);

/* What detection did (summed over calls; the pipeline reports it per
 * frame): the candidate pairs of primitives the broad phase gave the
 * narrow phase. */
typedef struct pl_detect_counts {
    long long candidates;
} pl_detect_counts;

typedef struct pl_detect_params {
    double alarm;        /* alarmDistance [m] */
    double contact;      /* contactDistance [m]: a pair far apart at the start of the step is
                            measured where it will be this close (look-ahead) */
    double margin;       /* motion the prediction x1 may miss [m] (a body hit by another in
                            this step): pairs are kept that far beyond alarm */
    const pl_side_hints *hints; /* sides from the previous step (NULL: none) */
    int vertex_face;     /* detect vertex-triangle proximities (both directions) */
    int edge_edge;       /* detect edge-edge proximities */
    int max_per_vertex;  /* vertex-face proximities kept per vertex and mesh pair (>= 1) */
    double normal_cos;   /* a vertex keeps a further proximity only if its normal differs from
                            the kept ones by more than acos(normal_cos) */
    pl_detect_counts *counts; /* NULL, or added to (deterministic sums) */
} pl_detect_params;

/* Default parameters for an alarm distance. */
pl_detect_params detect_defaults(double alarm);

/* Appends the proximities between the prepared meshes A (index ia) and B
 * (index ib); A == B (same pointer) is self-collision: primitives sharing a
 * vertex are skipped.  Edge-edge proximities are made only where one of the
 * two edges is sharp (elsewhere the vertex-triangle contacts of the edges'
 * ends hold the surfaces apart and an edge-edge row would nearly repeat
 * them).  A proximity is kept when its gap minus the predicted
 * approach over the step (relative motion x1 - x0 along the normal) is below
 * alarm, so fast bodies are caught before they cross.  Parallel (OpenMP),
 * deterministic: the order depends on the inputs only.  Refits the trees
 * it walks (coll_mesh_fit).  PL_OK or PL_EINTERNAL. */
int detect_pair(pl_coll_mesh *A, int ia, pl_coll_mesh *B, int ib, const pl_detect_params *prm,
                pl_proximities *out);

/* The same by brute force over all primitive pairs (tests, small meshes):
 * identical results, possibly in another order. */
int detect_pair_brute(const pl_coll_mesh *A, int ia, const pl_coll_mesh *B, int ib,
                         const pl_detect_params *prm, pl_proximities *out);

/* Candidate pairs given from outside (the device's broad phase and filter,
 * detect_cand.h): for each item i of a pass (a vertex, or an edge), its
 * primitives idx[start[i] .. start[i + 1]) in increasing order. */
typedef struct coll_cand_list {
    int n;          /* items */
    int *start;     /* n + 1 */
    int *idx;
    int cap_start, cap_idx;
} coll_cand_list;

void coll_cand_list_free(coll_cand_list *l);
/* Sizes l for n items and m candidates; PL_OK or PL_EINTERNAL. */
int coll_cand_list_fit(coll_cand_list *l, int n, int m);

/* detect_pair over given candidates instead of the BVHs: given[0] A's
 * vertices against B's triangles, given[1] B's vertices against A's (unused
 * when A == B), given[2] A's edges against B's.  When each list holds every
 * pair that detect_pair keeps (a superset of them), the result is
 * detect_pair's, in its order. */
int detect_pair_given(const pl_coll_mesh *A, int ia, const pl_coll_mesh *B, int ib,
                      const pl_detect_params *prm, const coll_cand_list given[3],
                      pl_proximities *out);

/* The candidate lists of detect_pair_given as the device makes them, by the
 * same item bodies run on the host (detect_cand_host.c): A, B prepared.
 * PL_OK or PL_EINTERNAL. */
int coll_cand_host(const pl_coll_mesh *A, const pl_coll_mesh *B, const pl_detect_params *prm,
                   coll_cand_list out[3]);
/* The same, and *broad: the box overlaps the broad phase found, which is
 * what detect_pair adds to prm->counts (the statistic is the same on both
 * paths). */
int coll_cand_host_counted(const pl_coll_mesh *A, const pl_coll_mesh *B,
                           const pl_detect_params *prm, coll_cand_list out[3], long long *broad);

/* ---- barycentric mapping into tetrahedra ------------------------------------ */

/* For each of the npts points: the tetrahedron containing it (the one it is
 * deepest in when on shared faces) or, outside the mesh, the nearest one,
 * and its 4 barycentric coordinates there (extrapolated outside: they may be
 * negative; sum_k bary_k v_k reproduces the point exactly).  tet_of: npts,
 * bary: npts x 4.  *outside (may be NULL) counts the points outside every
 * tetrahedron.  PL_OK, PL_EINPUT (no tetrahedra, an index out of range, a
 * flat tetrahedron), PL_EINTERNAL. */
int barycentric_map(const double *verts, int nverts, const int *tets, int ntets,
                       const double *pts, int npts, int *tet_of, double *bary, int *outside,
                       pl_error *err);

/* Unique undirected edges of triangles, sorted (a < b, lexicographic).
 * *edges malloc'ed (NULL when none).  PL_OK or PL_EINTERNAL. */
int triangle_edges(const int *tris, int ntris, int **edges, int *nedges);

#ifdef __cplusplus
}
#endif
#endif
