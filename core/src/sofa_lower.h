/* sofa_lower.h - private: what the parts of the SOFA lowering share
 * (sofa_lower.c: the driver and per-component rules; sofa_structure.c:
 * solvers, mapped child nodes, BoxROI, topology containers). */
#ifndef PLIANT_SOFA_LOWER_H
#define PLIANT_SOFA_LOWER_H

#include "sofa.h"

enum { SOFA_MAX_NOTES = 128 };

/* Pliant plugins a lowered scene needs (bits). */
enum {
    NEED_HYPERELASTIC = 1,
    NEED_SPARSE_INVERSE = 2,
    NEED_NCP_CONTACT = 4,
    NEED_CABLE = 8,
    NEED_COLLISION = 16, /* MappedPoints: loaded after lower_tree (sofa_mapped_points.c) */
};

typedef struct sofa_lower {
    xmlDoc *doc;
    xmlNode *root;
    const char *file;
    pl_registry *reg;
    pl_diag *diag;
    char *noted[SOFA_MAX_NOTES]; /* keys of the notes already given */
    int nnoted;
    unsigned need;               /* NEED_* */
    /* solvers gathered from the body nodes (sofa_structure.c) */
    int ode, linsolver, consolver, loop; /* how many of each the scene had */
    char *ode_name, *lin_name, *con_name; /* the names of the first ones */
    xmlNode *ode_nodes[64];               /* nodes holding an ODE solver (integrated below) */
    int node_count;
    double rayleigh_mass, rayleigh_stiffness;
    int first_order, ode_line;
    int lin_direct;                       /* the linear solver factors (else CG) */
    char *cg_iter, *cg_tol, *cg_thr;      /* CGLinearSolver's iterations, tolerance, threshold */
    int free_motion;          /* the loop is FreeMotionAnimationLoop */
    int nconstraints;         /* Lagrangian constraints (cables) of the scene */
    int constraint_line;      /* the first one's line */
    const char *constraint_type; /* and its type (SOFA's name), for messages */
    xmlNode *large_fem[64];   /* FEM with method large/qr: rotation from the edges (solvers) */
    int nlarge;
} sofa_lower;

int sofa_line(xmlNode *e);
/* "Type root/a/b" for messages. */
const char *sofa_where(xmlNode *e, char *buf, size_t size);
/* "root/a/b" of a Node element. */
const char *sofa_node_path(xmlNode *node, char *buf, size_t size);
/* The attribute's value (caller xmlFree's it) or NULL. */
char *sofa_get(xmlNode *e, const char *name);
void sofa_set(xmlNode *e, const char *name, const char *value);
void sofa_unset(xmlNode *e, const char *name);
/* A new element before `before` (same parent), given `line`. */
xmlNode *sofa_new_before(sofa_lower *L, xmlNode *before, const char *tag, int line);
void sofa_remove(xmlNode *e);
int sofa_is_node(const xmlNode *e);
int sofa_is_element(const xmlNode *e);
int sofa_tag_is(const xmlNode *e, const char *tag);
/* A warning given once per key. */
void sofa_note(sofa_lower *L, const char *key, xmlNode *e, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* An error at e. */
void sofa_error(sofa_lower *L, xmlNode *e, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* The element a SOFA path (@name, @./name, @../name, ...; no '@') names, from
 * the components of `node` (then its ancestors for a bare name), or NULL. */
xmlNode *sofa_find(xmlNode *node, const char *path);
/* "@x.field" -> the element x (and *field points into value at "field"), or NULL. */
xmlNode *sofa_data_link(xmlNode *node, const char *value, const char **field);
int sofa_parse_number(const char *s, double *v);
int sofa_is_true(const char *s);

/* SOFA's share/ path "mesh/x" of e's filename: "x" unless the scene's folder has it. */
void sofa_lower_mesh_path(sofa_lower *L, xmlNode *e);
/* sofa_mapped_points.c: 1 if the mapped node `node` (its mapping map, its
 * MechanicalObject mo) is kept as MappedPoints, everything else in it removed. */
int sofa_lower_mapped_points(sofa_lower *L, xmlNode *node, xmlNode *map, xmlNode *mo,
                             int identity);

/* sofa_structure.c */
void sofa_lower_plugins(sofa_lower *L);
void sofa_lower_lonely_collision(sofa_lower *L);
void sofa_lower_mapped_nodes(sofa_lower *L, xmlNode *node);
void sofa_lower_rois(sofa_lower *L, xmlNode *node);
void sofa_lower_container(sofa_lower *L, xmlNode *e);
void sofa_gather_solver(sofa_lower *L, xmlNode *e, const pl_sofa_component *entry);
void sofa_lower_springs(sofa_lower *L, xmlNode *e);
/* A SOFA collision model (not a Pliant type of that name)? */
int sofa_is_collision_model(sofa_lower *L, const xmlNode *e);
void sofa_emit_solvers(sofa_lower *L);
/* sofa_cavity.c: moves the SurfacePressureConstraint e of the mapped node
 * (its MechanicalObject mo) into the body's node. */
void sofa_lower_cavity(sofa_lower *L, xmlNode *node, xmlNode *mo, xmlNode *e, int identity);
/* sofa_cable_area.c: 1 when the CableConstraint e pulls areas (method
 * sphere/geodesic); its copy `moved` in the body's node gets the surface. */
int sofa_is_area_cable(xmlNode *e);
void sofa_lower_area_cable(sofa_lower *L, xmlNode *node, xmlNode *e, xmlNode *moved);

/* sofa_values.c: IndexValueMapper and BoxROI tetrahedronIndices -> per-element values */
void sofa_lower_value_mappers(sofa_lower *L);
/* sofa_grid.c: RegularGridTopology + Hexa2TetraTopologicalMapping -> RegularGridTetrahedra */
void sofa_lower_grids(sofa_lower *L);
/* sofa_collision.c: collision models and pipeline -> the collision plugin */
void sofa_lower_collision(sofa_lower *L);

#endif
