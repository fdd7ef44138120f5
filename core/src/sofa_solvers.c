/* sofa_solvers.c - SOFA's loop and solvers gathered into Pliant's.
 *
 * SOFA puts an ODE solver and a linear solver in each body's node and a
 * constraint solver next to the animation loop at the root; Pliant runs one
 * LocalGlobalSolver at the root over every body below it, with one global
 * solver and, for constraints, one contact solver.  So the solvers of a SOFA
 * scene are taken out of their nodes and one of each is written at the
 * root, with the name the user gave the first (so that `--set
 * odesolver.iterations=40` finds it).  What SOFA's placement means and
 * Pliant's cannot express is refused: bodies under no ODE solver (SOFA
 * keeps them still), ODE solvers with different damping, cables under
 * DefaultAnimationLoop (SOFA ignores them). */
#include "sofa_lower.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int zero_or_absent(sofa_lower *L, xmlNode *e, const char *attr, const char *why)
{
    char *v = sofa_get(e, attr);
    double d = 0;
    int ok = !v || (sofa_parse_number(v, &d) && d == 0);
    if (!ok) sofa_error(L, e, "%s=\"%s\": %s", attr, v, why);
    xmlFree(v);
    return ok;
}

/* A Rayleigh factor: a number >= 0 (0 when absent). */
static double factor(sofa_lower *L, xmlNode *e, const char *attr)
{
    double v = 0;
    char *s = sofa_get(e, attr);
    if (s && (!sofa_parse_number(s, &v) || v < 0)) {
        sofa_error(L, e, "%s=\"%s\": expected a number >= 0", attr, s);
        v = 0;
    }
    xmlFree(s);
    return v;
}

static void gather_ode(sofa_lower *L, xmlNode *e)
{
    zero_or_absent(L, e, "vdamping", "velocity damping is not mapped; use rayleighMass");
    char *fo = sofa_get(e, "firstOrder");
    int first = sofa_is_true(fo);
    xmlFree(fo);
    double rm = factor(L, e, "rayleighMass"), rs = factor(L, e, "rayleighStiffness");
    if (L->ode && (rm != L->rayleigh_mass || rs != L->rayleigh_stiffness ||
                   first != L->first_order))
        sofa_error(L, e, "its rayleighMass, rayleighStiffness or firstOrder differ from the "
                         "first EulerImplicitSolver's (line %d): Pliant integrates every body "
                         "with one solver",
                   L->ode_line);
    if (!L->ode++) {
        L->rayleigh_mass = rm, L->rayleigh_stiffness = rs, L->first_order = first;
        L->ode_line = sofa_line(e);
        L->ode_name = sofa_get(e, "name");
    }
    if (L->node_count < 64) L->ode_nodes[L->node_count++] = e->parent;
}

static void gather_linear(sofa_lower *L, xmlNode *e)
{
    if (L->linsolver++) return;
    L->lin_name = sofa_get(e, "name");
    L->lin_direct = !sofa_tag_is(e, "CGLinearSolver");
    if (!L->lin_direct) {
        L->cg_iter = sofa_get(e, "iterations");
        L->cg_tol = sofa_get(e, "tolerance");
        L->cg_thr = sofa_get(e, "threshold");
    }
}

void sofa_gather_solver(sofa_lower *L, xmlNode *e, const pl_sofa_component *entry)
{
    const char *tag = (const char *)e->name;
    char key[128];
    snprintf(key, sizeof key, "solver-%s", tag);
    if (strstr(tag, "AnimationLoop")) {
        if (L->loop++) sofa_error(L, e, "a second animation loop: a scene has one");
        L->free_motion = !strcmp(tag, "FreeMotionAnimationLoop");
    } else if (!strcmp(tag, "EulerImplicitSolver")) {
        gather_ode(L, e);
        sofa_note(L, key, e, "%s", entry->note);
    } else if (!strcmp(entry->pliant, "LinearizedEulerSolver")) { /* a linear solver */
        gather_linear(L, e);
        sofa_note(L, key, e, "%s: %s", tag, entry->note);
    } else {
        if (!L->consolver++) L->con_name = sofa_get(e, "name");
        sofa_note(L, key, e, "%s: %s", tag, entry->note);
    }
    for (xmlAttr *a = e->properties; a; a = a->next) {
        const pl_sofa_attr *r = pl_sofa_find_attr(tag, (const char *)a->name);
        if (r && r->kind == PL_SOFA_A_REFUSE)
            sofa_error(L, e, "'%s' is not supported: %s", (const char *)a->name, r->note);
    }
    sofa_remove(e);
}

static int integrated(const sofa_lower *L, xmlNode *node)
{
    for (; sofa_is_node(node); node = node->parent)
        for (int k = 0; k < L->node_count; ++k)
            if (L->ode_nodes[k] == node) return 1;
    return 0;
}

/* MechanicalObjects with no ODE solver above them; 1 if any Pliant loop. */
static int check_states(sofa_lower *L, xmlNode *node)
{
    int loop = 0;
    for (xmlNode *e = node->children; e; e = e->next) {
        if (sofa_is_node(e))
            loop |= check_states(L, e);
        else if (sofa_tag_is(e, "LocalGlobalSolver") || sofa_tag_is(e, "NewtonSolver") ||
                 sofa_tag_is(e, "LinearizedEulerSolver"))
            loop = 1;
        else if (L->ode && sofa_tag_is(e, "MechanicalObject") && !integrated(L, node))
            sofa_error(L, e, "this MechanicalObject has no EulerImplicitSolver in its node or "
                             "above: SOFA keeps it still, Pliant would simulate it; add an "
                             "EulerImplicitSolver above it, or hold it (FixedConstraint "
                             "fixAll=\"1\")");
    }
    return loop;
}

static xmlNode *first_component(sofa_lower *L)
{
    for (xmlNode *e = L->root->children; e; e = e->next)
        if (sofa_is_element(e) && !sofa_tag_is(e, "RequiredPlugin")) return e;
    return NULL;
}

static xmlNode *emit(sofa_lower *L, const char *tag, const char *name, int line, const char *a1,
                     const char *v1, const char *a2, const char *v2)
{
    xmlNode *e = sofa_new_before(L, first_component(L), tag, line);
    if (!e) return NULL;
    if (name) sofa_set(e, "name", name);
    if (a1) sofa_set(e, a1, v1);
    if (a2) sofa_set(e, a2, v2);
    return e;
}

static void emit_plugins(sofa_lower *L)
{
    static const struct {
        unsigned bit;
        const char *name;
    } P[] = {{NEED_HYPERELASTIC, "hyperelastic"},
             {NEED_SPARSE_INVERSE, "sparse_inverse"},
             {NEED_NCP_CONTACT, "ncp_contact"},
             {NEED_CABLE, "cable"}};
    xmlNode *first = L->root->children;
    while (first && !sofa_is_element(first)) first = first->next;
    for (int k = 0; k < 4; ++k) {
        if (!(L->need & P[k].bit)) continue;
        xmlNode *e = xmlNewDocNode(L->doc, NULL, (const xmlChar *)"RequiredPlugin", NULL);
        if (!e) return;
        e->line = L->root->line;
        sofa_set(e, "name", P[k].name);
        pl_error err; /* now, so that unknown names can be told apart (scene_xml.c reports) */
        pl_registry_load_plugin(L->reg, P[k].name, &err);
        if (first)
            xmlAddPrevSibling(first, e);
        else
            xmlAddChild(L->root, e);
    }
}

/* With Lagrangian constraints: LocalGlobalSolver, SparseInverseSolver and the
 * contact solver, which couple the constraints with the implicit step.
 * firstOrder and rayleighStiffness become its fields (with L, the rest
 * stiffness, for SOFA's tangent K: docs/sofa.md); under firstOrder SOFA
 * uses neither Rayleigh factor (its system is M - h K, its right-hand side
 * f), so neither is passed. */
static void emit_constrained(sofa_lower *L, int line)
{
    if (!L->free_motion || !L->consolver)
        pl_diag_error(L->diag, PL_EINPUT, L->file, L->constraint_line,
                      L->constraint_type ? L->constraint_type : "constraint",
                      "a Lagrangian constraint: SOFA solves it only with FreeMotionAnimationLoop "
                      "and a constraint solver (GenericConstraintSolver, "
                      "BlockGaussSeidelConstraintSolver, ...) at the root, and ignores it "
                      "otherwise; add them");
    double rm = L->rayleigh_mass, rs = L->rayleigh_stiffness;
    if (L->first_order && (rm != 0 || rs != 0)) {
        pl_diag_warn(L->diag, L->file, L->ode_line, "EulerImplicitSolver",
                     "rayleighMass and rayleighStiffness are not used with firstOrder=\"true\" "
                     "(SOFA's first-order system has no Rayleigh terms): ignored, as in SOFA");
        rm = rs = 0;
    }
    char damping[40], stiff[40];
    snprintf(damping, sizeof damping, "%.17g", rm);
    snprintf(stiff, sizeof stiff, "%.17g", rs);
    emit(L, "NonSmoothNewtonContactSolver", L->con_name, line, NULL, NULL, NULL, NULL);
    emit(L, "SparseInverseSolver", L->lin_name, line, NULL, NULL, NULL, NULL);
    xmlNode *lg =
        emit(L, "LocalGlobalSolver", L->ode_name, line, "iterations", "20", "damping", damping);
    if (lg) {
        if (L->first_order) sofa_set(lg, "firstOrder", "1");
        if (rs != 0) sofa_set(lg, "rayleighStiffness", stiff);
    }
    L->need |= NEED_SPARSE_INVERSE | NEED_NCP_CONTACT;
}

/* Without: SOFA's own scheme, LinearizedEulerSolver, with the linear solver's
 * settings. */
static void emit_linearized(sofa_lower *L, int line)
{
    char rm[40], rs[40];
    snprintf(rm, sizeof rm, "%.17g", L->rayleigh_mass);
    snprintf(rs, sizeof rs, "%.17g", L->rayleigh_stiffness);
    xmlNode *e = sofa_new_before(L, first_component(L), "LinearizedEulerSolver", line);
    if (!e) return;
    if (L->ode_name) sofa_set(e, "name", L->ode_name);
    sofa_set(e, "rayleighMass", rm);
    sofa_set(e, "rayleighStiffness", rs);
    if (L->first_order) sofa_set(e, "firstOrder", "1");
    sofa_set(e, "linearSolver", L->lin_direct ? "direct" : "cg");
    if (L->cg_iter) sofa_set(e, "iterations", L->cg_iter);
    if (L->cg_tol) sofa_set(e, "tolerance", L->cg_tol);
    if (L->cg_thr) sofa_set(e, "threshold", L->cg_thr);
}

/* SOFA's 'large' method: the rotation from a frame on the element's edges.
 * Corotational rotation="edges" is that, but has no energy: only
 * LinearizedEulerSolver can use it; under LocalGlobalSolver (constraints)
 * the polar rotation stays, and a note says so. */
static void lower_large_fem(sofa_lower *L, int linearized)
{
    for (int k = 0; k < L->nlarge; ++k) {
        xmlNode *e = L->large_fem[k];
        if (linearized)
            sofa_set(e, "rotation", "edges");
        else
            sofa_note(L, "fem-large", e,
                      "method=\"large\": Pliant's Corotational takes each element's rotation "
                      "from the polar decomposition here (SOFA's 'polar': the solver, "
                      "LocalGlobalSolver with a cable, needs an energy); SOFA's frame on the "
                      "edges (rotation=\"edges\", LinearizedEulerSolver only) differs under "
                      "large shear");
    }
}

void sofa_emit_solvers(sofa_lower *L)
{
    int line = L->ode_line ? L->ode_line : sofa_line(L->root);
    int has_loop = check_states(L, L->root) && L->ode;
    if (has_loop)
        pl_diag_error(L->diag, PL_EINPUT, L->file, line, "EulerImplicitSolver",
                      "the scene has both SOFA's EulerImplicitSolver and a Pliant animation loop "
                      "(LocalGlobalSolver, NewtonSolver, ...): keep one");
    else if (L->ode && !L->linsolver)
        pl_diag_error(L->diag, PL_EINPUT, L->file, line, "EulerImplicitSolver",
                      "EulerImplicitSolver needs a linear solver in its node (CGLinearSolver, "
                      "SparseLDLSolver, ...), as in SOFA");
    else if (L->ode && L->nconstraints)
        emit_constrained(L, line);
    else if (L->ode)
        emit_linearized(L, line);
    lower_large_fem(L, L->ode && !L->nconstraints && !has_loop);
    emit_plugins(L);
}
