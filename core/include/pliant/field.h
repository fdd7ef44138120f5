/* field.h - typed fields of a component, declared once in a static table.
 *
 * The same table drives XML parsing, validation, `pliant list`, the
 * generated component reference and get/set by path.  A field lives inside
 * the component struct at `offset`; its storage type follows its kind:
 *
 *   PL_F_DOUBLE  double        PL_F_DOUBLES  pl_doubles (list, or per element)
 *   PL_F_INT     int           PL_F_INTS     pl_ints
 *   PL_F_BOOL    int (0/1)     PL_F_ENUM     int (index into choices)
 *   PL_F_STRING  char *        PL_F_LINK     pl_link ("@../loader", "@name")
 *   PL_F_VEC3    double[3]
 */
#ifndef PLIANT_FIELD_H
#define PLIANT_FIELD_H

#include "api.h"
#include <stddef.h>
#include "error.h"

#ifdef __cplusplus
extern "C" {
#endif

struct pl_component;

typedef enum pl_field_type {
    PL_F_DOUBLE,
    PL_F_INT,
    PL_F_BOOL,
    PL_F_STRING,
    PL_F_VEC3,
    PL_F_DOUBLES,
    PL_F_INTS,
    PL_F_ENUM,
    PL_F_LINK
} pl_field_type;

typedef struct pl_doubles {
    double *v;
    int n;
} pl_doubles;

typedef struct pl_ints {
    int *v;
    int n;
} pl_ints;

/* A link to another component: the text after '@' and, after binding,
 * the component it names (NULL while unresolved or when left empty). */
typedef struct pl_link {
    char *path;
    struct pl_component *target;
} pl_link;

enum pl_field_flags {
    PL_FIELD_REQUIRED = 1 << 0, /* the scene must give it */
    PL_FIELD_OUTPUT = 1 << 1,   /* computed by the component; read-only */
    PL_FIELD_RUNTIME = 1 << 2,  /* may change while running without a refactor (a model
                                   value: between steps, for every data) */
    PL_FIELD_INPUT = 1 << 3     /* an input of the simulation (a cable's pull, a target):
                                   its current value lives in each pl_data, where
                                   controllers and pl_sim_set change it (input.h);
                                   implies RUNTIME.  Numeric kinds only. */
};

typedef struct pl_field {
    const char *name;     /* XML attribute name (SOFA's where SOFA has one) */
    pl_field_type type;
    size_t offset;        /* offsetof(component struct, member) */
    const char *def;      /* default value as text; NULL = empty/unset */
    const char *help;     /* one line, with the unit in brackets: "[Pa]" */
    int flags;            /* pl_field_flags */
    const char *const *choices; /* PL_F_ENUM: NULL-terminated names */
    const char *alias;    /* an accepted alternative name (e.g. "tetras"), or NULL */
} pl_field;

/* Table-building helpers: PL_FIELD(type_struct, member, "name", KIND, "default", "help", flags) */
#define PL_FIELD(S, m, nm, kind, def, help, flags) \
    {nm, kind, offsetof(S, m), def, help, flags, NULL, NULL}
#define PL_FIELD_ENUM(S, m, nm, choices, def, help, flags) \
    {nm, PL_F_ENUM, offsetof(S, m), def, help, flags, choices, NULL}
#define PL_FIELD_ALIAS(S, m, nm, kind, def, help, flags, alias) \
    {nm, kind, offsetof(S, m), def, help, flags, NULL, alias}

/* Parses text into the field's storage inside component memory `obj`.
 * Frees what was there before.  On a malformed value returns PL_EINPUT with a
 * message saying what was expected (file/line are left for the caller). */
PL_API int pl_field_parse(const pl_field *f, void *obj, const char *text, pl_error *err);
/* Formats the field's current value as text (as it would be written in XML). */
PL_API int pl_field_format(const pl_field *f, const void *obj, char *buf, size_t size);
/* Releases heap storage held by the field (strings, lists, link paths). */
PL_API void pl_field_release(const pl_field *f, void *obj);
/* Human name of a field type ("double", "vec3", "int list", ...). */
PL_API const char *pl_field_type_name(pl_field_type t);

/* Edit distance used for "did you mean ...?" suggestions. */
PL_API int pl_edit_distance(const char *a, const char *b);

#ifdef __cplusplus
}
#endif
#endif
