/* sofa.h - private: SOFA's vocabulary (sofa_vocab.c, the one table of what
 * every SOFA component and attribute means in Pliant) and the lowering of a
 * SOFA scene's document into Pliant's components (sofa_lower.c and its
 * parts), run by scene_xml.c before the tree is built.  docs/sofa.md explains
 * the table to users; `pliant doc --sofa` prints it. */
#ifndef PLIANT_SOFA_PRIVATE_H
#define PLIANT_SOFA_PRIVATE_H

#include <libxml/tree.h>

#include "pliant/error.h"
#include "pliant/registry.h"

/* What Pliant does with a SOFA component. */
typedef enum pl_sofa_kind {
    PL_SOFA_SAME,    /* a Pliant component of the same name and meaning (attribute rules apply) */
    PL_SOFA_RENAME,  /* a Pliant component under another name (`pliant`, from `plugin`) */
    PL_SOFA_VISUAL,  /* drawing or GUI only: dropped with a warning */
    PL_SOFA_NOTED,   /* accepted; nothing to do in Pliant that changes physics (solver tuning,
                        constraint corrections, collision pipeline parts): dropped, noted once */
    PL_SOFA_LOWERED, /* rewritten by the lowering (loops and solvers, topology containers,
                        BoxROI, mappings of child nodes) */
    PL_SOFA_REFUSED  /* an error: `note` says why and the closest supported alternative */
} pl_sofa_kind;

typedef struct pl_sofa_component {
    const char *sofa;   /* SOFA's name (and older names: FixedConstraint, DefaultPipeline) */
    pl_sofa_kind kind;
    const char *pliant; /* the Pliant type (SAME, RENAME, LOWERED: what it becomes) */
    const char *plugin; /* the Pliant plugin providing it (NULL: built in) */
    const char *note;   /* what Pliant does, where physics differ, or why it is refused */
} pl_sofa_component;

/* What Pliant does with a SOFA attribute. */
typedef enum pl_sofa_attr_kind {
    PL_SOFA_A_RENAME,  /* the Pliant field `pliant` */
    PL_SOFA_A_IGNORE,  /* cannot change physics (drawing, solver tuning): dropped, noted once */
    PL_SOFA_A_REFUSE,  /* changes physics in a way Pliant does not honour: an error */
    PL_SOFA_A_LOWERED  /* read by the lowering code of its component */
} pl_sofa_attr_kind;

typedef struct pl_sofa_attr {
    const char *component; /* SOFA component name, or "*" for every SOFA component */
    const char *sofa;      /* the attribute */
    pl_sofa_attr_kind kind;
    const char *pliant;    /* RENAME: the Pliant field */
    const char *note;      /* why (IGNORE, REFUSE) or how (LOWERED) */
} pl_sofa_attr;

/* The tables (static, NULL-terminated by sofa == NULL). */
const pl_sofa_component *pl_sofa_components(void);
const pl_sofa_attr *pl_sofa_attrs(void);
/* The entry of a SOFA component name, or NULL. */
const pl_sofa_component *pl_sofa_find(const char *sofa);
/* The rule for attribute `attr` of SOFA component `component` (its own rule,
 * else a "*" rule; draw... and show... attributes are drawing), or NULL: the
 * attribute passes unchanged to the Pliant field of the same name. */
const pl_sofa_attr *pl_sofa_find_attr(const char *component, const char *attr);
/* What a RequiredPlugin name means: 0 a Pliant plugin (load it), 1 a SOFA
 * module whose components the table maps (nothing to load), 2 SoftRobots
 * (Pliant's cable plugin), -1 a SOFA plugin Pliant cannot stand in for
 * (*why says why). */
int pl_sofa_module(const char *name, const char **why);

/* Rewrites a SOFA scene's document into Pliant's vocabulary in place (see
 * sofa_lower.c): renames, attribute rules, solvers gathered at the root,
 * mapped child nodes, BoxROI.  Pliant scenes pass unchanged, except that a
 * state template other than Vec3 is refused in any scene.  Problems go to
 * diag with file:line. */
void pl_sofa_lower(xmlDoc *doc, const char *file, pl_registry *reg, pl_diag *diag);

#endif
