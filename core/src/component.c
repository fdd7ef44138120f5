/* component.c - paths, field lookup and error helpers for components. */
#include "pliant/component.h"
#include "pliant/node.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static const char *const ROLE_NAMES[PL_ROLE_COUNT] = {
    [PL_ROLE_STATE] = "state",
    [PL_ROLE_MASS] = "mass",
    [PL_ROLE_TOPOLOGY] = "topology",
    [PL_ROLE_LOCAL_TERM] = "local term",
    [PL_ROLE_GLOBAL_SOLVER] = "global solver",
    [PL_ROLE_CONSTRAINT] = "constraint",
    [PL_ROLE_CONTACT_SOLVER] = "contact solver",
    [PL_ROLE_COLLISION_MODEL] = "collision model",
    [PL_ROLE_EXPORTER] = "exporter",
    [PL_ROLE_CONTROLLER] = "controller",
    [PL_ROLE_PRESCRIBED] = "prescribed DOFs",
    [PL_ROLE_ANIMATION_LOOP] = "animation loop",
    [PL_ROLE_DEVICE] = "device",
    [PL_ROLE_VISUAL] = "visual",
    [PL_ROLE_EVENT] = "event",
};

const char *pl_role_name(int role)
{
    return role >= 0 && role < PL_ROLE_COUNT && ROLE_NAMES[role] ? ROLE_NAMES[role] : "unknown role";
}

const char *pl_component_path(const pl_component *c, char *buf, size_t size)
{
    char np[160];
    if (c->node)
        snprintf(buf, size, "%s/%s", pl_node_path(c->node, np, sizeof np),
                 c->name ? c->name : "?");
    else
        snprintf(buf, size, "%s", c->name ? c->name : "?");
    return buf;
}

const pl_field *pl_component_field(const pl_component *c, const char *name)
{
    const pl_type *t = c->type;
    for (int k = 0; k < t->nfields; ++k)
        if (!strcmp(t->fields[k].name, name)) return &t->fields[k];
    for (int k = 0; k < t->nfields; ++k)
        if (t->fields[k].alias && !strcmp(t->fields[k].alias, name)) return &t->fields[k];
    return NULL;
}

int pl_component_error(const pl_component *c, pl_ctx *ctx, int code, const char *fmt, ...)
{
    char where[192], what[160];
    pl_error e;
    va_list ap;
    snprintf(where, sizeof where, "%s %s", c->type->name, pl_component_path(c, what, sizeof what));
    va_start(ap, fmt);
    pl_error_vset(&e, code, c->file, c->line, where, fmt, ap);
    va_end(ap);
    if (ctx && ctx->diag) pl_diag_add(ctx->diag, &e);
    return code;
}

void pl_component_warn(const pl_component *c, pl_ctx *ctx, const char *fmt, ...)
{
    char where[192], what[160];
    pl_error e;
    va_list ap;
    snprintf(where, sizeof where, "%s %s", c->type->name, pl_component_path(c, what, sizeof what));
    va_start(ap, fmt);
    pl_error_vset(&e, PL_OK, c->file, c->line, where, fmt, ap);
    va_end(ap);
    if (ctx && ctx->diag) pl_diag_add(ctx->diag, &e);
}

int pl_component_fail(const pl_component *c, pl_error *err, int code, const char *fmt, ...)
{
    char where[192], what[160];
    va_list ap;
    snprintf(where, sizeof where, "%s %s", c->type->name, pl_component_path(c, what, sizeof what));
    va_start(ap, fmt);
    pl_error_vset(err, code, c->file, c->line, where, fmt, ap);
    va_end(ap);
    return code;
}
