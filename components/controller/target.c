/* target.c - resolving a controller's target="@component.field". */
#include <stdio.h>
#include <string.h>

#include "controller/target.h"

static int no_field(pl_component *c, pl_ctx *ctx, const pl_component *comp, const char *path,
                    const char *fname)
{
    const char *best = NULL;
    int bestd = 1 << 30;
    for (int i = 0; i < comp->type->nfields; ++i) {
        int d = pl_edit_distance(fname, comp->type->fields[i].name);
        if (d < bestd) bestd = d, best = comp->type->fields[i].name;
    }
    if (best && bestd <= 3)
        return pl_component_error(c, ctx, PL_EINPUT, "target: %s '%s' has no field '%s' (did "
                                  "you mean %s?)", comp->type->name, path, fname, best);
    return pl_component_error(c, ctx, PL_EINPUT, "target: %s '%s' has no field '%s'",
                              comp->type->name, path, fname);
}

/* The names of t's input fields, for messages ("value, pullPoint"). */
static void input_names(const pl_type *t, char *buf, size_t size)
{
    size_t w = 0;
    buf[0] = '\0';
    for (int i = 0; i < t->nfields && w < size; ++i)
        if (t->fields[i].flags & PL_FIELD_INPUT) {
            int n = snprintf(buf + w, size - w, "%s%s", w ? ", " : "", t->fields[i].name);
            if (n < 0) break;
            w += (size_t)n;
        }
}

int pl_controller_target(pl_component *c, pl_ctx *ctx, const char *what, const char *text,
                         pl_component **comp, const pl_field **field)
{
    const char *t = text && text[0] == '@' ? text + 1 : text ? text : "";
    const char *dot = strrchr(t, '.');
    if (!dot || dot == t || !dot[1] || strchr(dot, '/'))
        return pl_component_error(c, ctx, PL_EINPUT, "target: expected @component.field (e.g. "
                                  "@cable.value), got '%s'", text ? text : "");
    char path[512];
    snprintf(path, sizeof path, "%.*s", (int)(dot - t), t);
    *comp = pl_node_resolve(c, path);
    if (!*comp)
        return pl_component_error(c, ctx, PL_EINPUT, "target: no component '%s' (looked in this "
                                  "node and above; use ../name, child/name or /abs/path)", path);
    const pl_field *f = pl_component_field(*comp, dot + 1);
    if (!f) return no_field(c, ctx, *comp, path, dot + 1);
    if (f->flags & PL_FIELD_OUTPUT)
        return pl_component_error(c, ctx, PL_EINPUT, "target: '%s' is an output of %s", f->name,
                                  (*comp)->type->name);
    if (!(f->flags & PL_FIELD_INPUT)) {
        char names[256];
        input_names((*comp)->type, names, sizeof names);
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "target: %s.%s is not an input field (a model value, which a "
                                  "step never changes); %s drives input fields only%s%s%s",
                                  (*comp)->type->name, f->name, what, names[0] ? " (" : "",
                                  names, names[0] ? ")" : "");
    }
    if (f->type != PL_F_DOUBLE && f->type != PL_F_INT && f->type != PL_F_VEC3 &&
        f->type != PL_F_DOUBLES && f->type != PL_F_INTS)
        return pl_component_error(c, ctx, PL_EINPUT, "target: '%s' is a %s field; %s drives "
                                  "numbers (double, int, vec3, lists)", f->name,
                                  pl_field_type_name(f->type), what);
    *field = f;
    return PL_OK;
}
