/* sofa_collision.c - SOFA's collision models and pipeline as Pliant's
 * collision plugin (fallingBeamLagrangianCollision.scn: a beam's surface
 * falling onto a floor of triangles written in the scene).
 *
 *  - a node without an ODE solver (none in it or above) holding collision
 *    models is still in SOFA (nothing integrates it; moving="0"
 *    simulated="0" says so): its triangles become a MeshObstacle, from an
 *    inline TriangleSetTopologyContainer (position, triangles) or from the
 *    node's mesh loader (with its MechanicalObject's scale, dx dy dz and
 *    rx ry rz);
 *  - collision models on a body (in its node, or in a child node that
 *    takes the body's surface by Tetra2TriangleTopologicalMapping under an
 *    IdentityMapping) become SurfaceCollisionModel in the body's node: the
 *    boundary of its tetrahedra, the same surface;
 *  - the pipeline (CollisionPipeline, broad and narrow phases, the
 *    intersection method, CollisionResponse) becomes one CollisionPipeline
 *    at the root: alarmDistance and contactDistance from the intersection
 *    method, mu from responseParams="mu=..." of a FrictionContactConstraint
 *    response.  Pliant's contacts are Lagrangian (the contact solver), as
 *    SOFA's FrictionContactConstraint; SOFA's penalty response is refused.
 * What differs from SOFA: Pliant detects vertex-triangle (both ways) and
 * edge-edge proximities of the surfaces whatever the model types
 * (Triangle, Line, Point) and solves contact and friction with its
 * non-smooth Newton solver inside the implicit step. */
#include "sofa_lower.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int is_pipeline_part(const xmlNode *e)
{
    static const char *const parts[] = {
        "CollisionPipeline", "DefaultPipeline", "BruteForceBroadPhase", "BruteForceDetection",
        "BVHNarrowPhase", "DiscreteIntersection", "NewProximityIntersection",
        "MinProximityIntersection", "LocalMinDistance", "CollisionResponse",
        "DefaultContactManager", "RuleBasedContactManager", NULL};
    for (int k = 0; parts[k]; ++k)
        if (sofa_tag_is(e, parts[k])) return 1;
    return 0;
}

/* Is node integrated (an EulerImplicitSolver in it or above)? */
static int integrated(xmlNode *node)
{
    for (; sofa_is_node(node); node = node->parent)
        for (xmlNode *e = node->children; e; e = e->next)
            if (sofa_tag_is(e, "EulerImplicitSolver")) return 1;
    return 0;
}

static xmlNode *first_of(xmlNode *node, const char *part)
{
    for (xmlNode *e = node->children; e; e = e->next)
        if (sofa_is_element(e) && !sofa_is_node(e) && strstr((const char *)e->name, part))
            return e;
    return NULL;
}

/* Checks an inline triangle list against its points; 0 (error given) if bad. */
static int inline_triangles(sofa_lower *L, xmlNode *topo, xmlNode *obstacle)
{
    char *pos = sofa_get(topo, "position"), *tri = sofa_get(topo, "triangles");
    int np = 0, nt = 0, ok = pos && tri && pos[0] != '@' && tri[0] != '@';
    char *p, *end;
    for (p = pos; ok && p; p = end) {
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r' || *p == ',') ++p;
        if (!*p) break;
        strtod(p, &end);
        ok = end != p, ++np;
    }
    ok = ok && np > 0 && np % 3 == 0;
    for (p = tri; ok && p; p = end) {
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r' || *p == ',') ++p;
        if (!*p) break;
        long i = strtol(p, &end, 10);
        if (end == p || i < 0 || i >= np / 3) {
            sofa_error(L, topo, "triangles: '%.20s' is not one of the %d points (0 to %d)", p,
                       np / 3, np / 3 - 1);
            ok = -1;
        }
        ++nt;
    }
    if (ok > 0 && (nt == 0 || nt % 3)) ok = 0;
    if (ok > 0) {
        sofa_set(obstacle, "position", pos);
        sofa_set(obstacle, "triangles", tri);
    } else if (!ok) {
        sofa_error(L, topo, "a still collision surface needs its points and triangles as "
                            "numbers (position=\"x y z ...\" triangles=\"i j k ...\": 3 "
                            "numbers per point, 3 indices per triangle)");
    }
    xmlFree(pos);
    xmlFree(tri);
    return ok > 0;
}

/* The state's placement (SOFA's MechanicalObject scale, dx.., rx..) onto the obstacle. */
static void placement(xmlNode *mo, xmlNode *obstacle)
{
    static const char *const axes[2][3] = {{"dx", "dy", "dz"}, {"rx", "ry", "rz"}};
    static const char *const field[2] = {"translation", "rotation"};
    for (int a = 0; a < 2; ++a) {
        double v[3] = {0, 0, 0};
        int any = 0;
        for (int k = 0; k < 3; ++k) {
            char *s = sofa_get(mo, axes[a][k]);
            if (s) v[k] = atof(s), any = 1;
            xmlFree(s);
        }
        char *whole = sofa_get(mo, field[a]), buf[96];
        if (whole) sofa_set(obstacle, field[a], whole);
        else if (any) {
            snprintf(buf, sizeof buf, "%.17g %.17g %.17g", v[0], v[1], v[2]);
            sofa_set(obstacle, field[a], buf);
        }
        xmlFree(whole);
    }
    char *s = sofa_get(mo, "scale");
    if (s) {
        char buf[96];
        snprintf(buf, sizeof buf, "%s %s %s", s, s, s);
        sofa_set(obstacle, "scale3d", buf);
    }
    xmlFree(s);
}

/* A node SOFA keeps still: its collision surface becomes a MeshObstacle. */
static void still_node(sofa_lower *L, xmlNode *node, xmlNode *model)
{
    xmlNode *topo = first_of(node, "TriangleSetTopologyContainer");
    if (!topo) topo = first_of(node, "MeshTopology");
    xmlNode *loader = first_of(node, "Loader"), *mo = first_of(node, "MechanicalObject");
    xmlNode *ob = sofa_new_before(L, model, "MeshObstacle", sofa_line(model));
    char *nm = sofa_get(model, "name");
    if (nm) sofa_set(ob, "name", nm);
    xmlFree(nm);
    int ok = 1;
    char *inl = topo ? sofa_get(topo, "triangles") : NULL;
    if (inl) {
        ok = inline_triangles(L, topo, ob);
    } else if (loader) {
        char *lname = sofa_get(loader, "name"), buf[300];
        snprintf(buf, sizeof buf, "@%s", lname ? lname : "");
        if (lname) sofa_set(ob, "src", buf);
        else sofa_error(L, loader, "the loader of a still collision surface needs a name");
        xmlFree(lname);
    } else {
        sofa_error(L, model, "a still collision surface (no ODE solver in this node or above) "
                             "needs its triangles: an inline TriangleSetTopologyContainer "
                             "(position, triangles) or a mesh loader in the node");
        ok = 0;
    }
    xmlFree(inl);
    if (ok && mo) placement(mo, ob);
    if (!ok) sofa_remove(ob);
    char path[160];
    sofa_note(L, "still-collision", model,
              "the collision models of '%s', which no ODE solver moves (SOFA keeps it still), "
              "are a MeshObstacle of its triangles", sofa_node_path(node, path, sizeof path));
    /* what only described the surface goes */
    xmlNode *next;
    for (xmlNode *e = node->children; e; e = next) {
        next = e->next;
        if (sofa_is_node(e) || !sofa_is_element(e) || e == ob || e == loader) continue;
        if (sofa_is_collision_model(L, e) || e == mo || e == topo ||
            strstr((const char *)e->name, "TopologyModifier"))
            sofa_remove(e);
    }
}

/* Collision models on a body's surface: SurfaceCollisionModel in `body`. */
static void body_surface(sofa_lower *L, xmlNode *body, xmlNode *model, xmlNode *before)
{
    for (xmlNode *e = body->children; e; e = e->next)
        if (sofa_tag_is(e, "SurfaceCollisionModel")) return; /* one per body */
    xmlNode *s = sofa_new_before(L, before, "SurfaceCollisionModel", sofa_line(model));
    char *nm = sofa_get(model, "name");
    sofa_set(s, "name", nm ? nm : "surface");
    xmlFree(nm);
    char *g = sofa_get(model, "group");
    if (g) sofa_set(s, "group", g);
    xmlFree(g);
    char path[160];
    sofa_note(L, "surface-collision", model,
              "SOFA's collision models of the body '%s' are its SurfaceCollisionModel (the "
              "boundary of its tetrahedra; vertex-triangle and edge-edge proximities whatever "
              "the model types)", sofa_node_path(body, path, sizeof path));
}

/* A child node mapping the body's own surface (Tetra2Triangle under an
 * IdentityMapping) that holds collision models. */
static int surface_node(sofa_lower *L, xmlNode *node)
{
    xmlNode *t2t = first_of(node, "Tetra2TriangleTopologicalMapping");
    xmlNode *idm = first_of(node, "IdentityMapping"), *model = NULL;
    for (xmlNode *e = node->children; e && !model; e = e->next)
        if (sofa_is_collision_model(L, e)) model = e;
    if (!model || !t2t || !idm || !first_of(node->parent, "MechanicalObject")) return 0;
    body_surface(L, node->parent, model, node);
    /* its points may stay (mapped states, sofa_mapped_points.c); the rest
     * goes, its drawing child too */
    xmlNode *mo = first_of(node, "MechanicalObject");
    if (!sofa_lower_mapped_points(L, node, idm, mo, 1)) sofa_remove(node);
    return 1;
}

/* Settings of the SOFA pipeline onto Pliant's CollisionPipeline. */
static void pipeline_settings(sofa_lower *L, xmlNode *node, xmlNode *pipe, int *refused)
{
    xmlNode *next;
    for (xmlNode *e = node->children; e; e = next) {
        next = e->next;
        if (sofa_is_node(e)) {
            pipeline_settings(L, e, pipe, refused);
            continue;
        }
        if (!sofa_is_element(e) || e == pipe || !is_pipeline_part(e)) continue;
        static const char *const dist[] = {"alarmDistance", "contactDistance"};
        for (int k = 0; k < 2; ++k) {
            char *v = sofa_get(e, dist[k]);
            if (v) sofa_set(pipe, dist[k], v);
            xmlFree(v);
        }
        char *nm = strstr((const char *)e->name, "Pipeline") ? sofa_get(e, "name") : NULL;
        if (nm) sofa_set(pipe, "name", nm); /* --set Pipeline.alarmDistance=... as named */
        xmlFree(nm);
        if (sofa_tag_is(e, "CollisionResponse") || strstr((const char *)e->name, "ContactManager")) {
            char *r = sofa_get(e, "response"), *p = sofa_get(e, "responseParams");
            if (!r || strstr(r, "Penality") || strstr(r, "Penalty")) {
                sofa_error(L, e, "response=\"%s\": SOFA's penalty contact is not mapped; Pliant's "
                                 "contact is Lagrangian: response=\"FrictionContactConstraint\" "
                                 "(with FreeMotionAnimationLoop and a constraint solver)",
                           r ? r : "PenalityContactForceField (SOFA's default)");
                *refused = 1;
            }
            const char *mu = p ? strstr(p, "mu=") : NULL;
            if (mu) {
                char buf[64];
                snprintf(buf, sizeof buf, "%.*s", (int)strcspn(mu + 3, " &,;"), mu + 3);
                sofa_set(pipe, "mu", buf);
            }
            xmlFree(r);
            xmlFree(p);
        }
        sofa_remove(e);
    }
}

/* Collision models of every node: 1 if any remains to be mapped. */
static int lower_models(sofa_lower *L, xmlNode *node, int *line)
{
    int any = 0;
    xmlNode *next;
    for (xmlNode *c = node->children; c; c = next) {
        next = c->next;
        if (sofa_is_node(c)) {
            xmlNode *model = NULL;
            for (xmlNode *e = c->children; e && !model; e = e->next)
                if (sofa_is_collision_model(L, e)) model = e;
            if (model && !*line) *line = sofa_line(model);
            if (model && !integrated(c)) {
                still_node(L, c, model);
                any = 1;
            } else if (model && surface_node(L, c)) {
                any = 1;
            } else {
                any |= lower_models(L, c, line);
            }
        } else if (sofa_is_collision_model(L, c) && first_of(node, "MechanicalObject") &&
                   integrated(node)) {
            if (!*line) *line = sofa_line(c);
            body_surface(L, node, c, c);
            sofa_remove(c);
            any = 1;
        }
    }
    return any;
}

void sofa_lower_collision(sofa_lower *L)
{
    int line = 0;
    if (!lower_models(L, L->root, &line)) return;
    xmlNode *first = L->root->children;
    while (first && (!sofa_is_element(first) || sofa_tag_is(first, "RequiredPlugin")))
        first = first->next;
    xmlNode *pipe = sofa_new_before(L, first, "CollisionPipeline", line);
    int refused = 0;
    pipeline_settings(L, L->root, pipe, &refused);
    xmlNode *req = sofa_new_before(L, pipe, "RequiredPlugin", line);
    sofa_set(req, "name", "collision");
    pl_error err;
    pl_registry_load_plugin(L->reg, "collision", &err); /* its names are Pliant's from now */
    sofa_note(L, "collision-pipeline", pipe,
              "SOFA's collision pipeline: Pliant's CollisionPipeline (collision plugin) with the "
              "intersection's alarmDistance and contactDistance and the response's mu; contacts "
              "are Lagrangian constraints solved with the implicit step");
    if (!L->nconstraints++) L->constraint_line = line, L->constraint_type = "CollisionPipeline";
}
