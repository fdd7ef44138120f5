/* test_export_components.c - VTKExporter and WriteState driven by hand the
 * way the simulation drives exporters (write after loading and after each
 * step, finish at the end), on a node holding a stand-in state and
 * topology.  Their files are read back with libxml2 and pl_state_file_read. */
#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libxml/parser.h>
#include <libxml/xpath.h>

#include "export/export.h"
#include "export_test_util.h"
#include "pliant/pliant.h"

/* ---- a stand-in state and topology --------------------------------------- */

enum { NV = 5 };

typedef struct fake_state {
    pl_component base;
    double x[NV * 3], v[NV * 3];
} fake_state;

static int fs_count(const pl_component *c) { (void)c; return NV; }
static pl_buffer fs_positions(const pl_component *c, const pl_data *d)
{
    (void)d;
    return pl_buffer_host_f64(((fake_state *)c)->x, NV, 3);
}
static pl_buffer fs_velocities(const pl_component *c, const pl_data *d)
{
    (void)d;
    return pl_buffer_host_f64(((fake_state *)c)->v, NV, 3);
}
static const pl_state_ops fs_ops = {.version = PL_STATE_OPS_VERSION, .count = fs_count,
                                    .positions = fs_positions, .velocities = fs_velocities};
static const pl_type fs_type = {.abi_version = PL_ABI_VERSION, .name = "FakeState",
                                .size = sizeof(fake_state), .roles = {[PL_ROLE_STATE] = &fs_ops}};

static int tet[4] = {0, 1, 2, 3}, tri[3] = {1, 2, 4};
static pl_mesh mesh = {NV, NULL, 1, tet, 1, tri};
static const pl_mesh *ft_mesh(const pl_component *c) { (void)c; return &mesh; }
static const pl_topology_ops ft_ops = {.version = PL_TOPOLOGY_OPS_VERSION, .mesh = ft_mesh};
static const pl_type ft_type = {.abi_version = PL_ABI_VERSION, .name = "FakeTopology",
                                .size = sizeof(pl_component),
                                .roles = {[PL_ROLE_TOPOLOGY] = &ft_ops}};

/* ---- a node holding them -------------------------------------------------- */

typedef struct rig {
    pl_node node;
    pl_component *comps[3];
    fake_state state;
    pl_component topo;
    pl_component *exporter;
    pl_diag diag;
    pl_ctx ctx;
    pl_data data;
} rig;

/* The positions/velocities the state has at step k (distinct every step). */
static void set_state(rig *r, int k)
{
    for (int i = 0; i < NV * 3; ++i) {
        r->state.x[i] = i + k / 3.0;
        r->state.v[i] = -i * 0.1 - k;
    }
}

/* A node "bar" (dt 0.02) with the state, optionally a topology, and a new
 * component of type t whose fields are "name=value" pairs. */
static void rig_make(rig *r, const pl_type *t, int with_topology, const char *const *fields,
                     int nfields)
{
    memset(r, 0, sizeof *r);
    r->node.name = "bar";
    r->node.dt = 0.02;
    r->node.has_dt = 1;
    r->state.base = (pl_component){&fs_type, "dofs", &r->node, "test.xml", 3};
    r->topo = (pl_component){&ft_type, "topo", &r->node, "test.xml", 2};
    r->exporter = calloc(1, t->size);
    *r->exporter = (pl_component){t, "out", &r->node, "test.xml", 4};
    int n = 0;
    if (with_topology) r->comps[n++] = &r->topo;
    r->comps[n++] = &r->state.base;
    r->comps[n++] = r->exporter;
    r->node.components = r->comps;
    r->node.ncomponents = n;
    pl_error e;
    for (int k = 0; k < t->nfields; ++k)
        if (t->fields[k].def) ck_assert_int_eq(pl_field_parse(&t->fields[k], r->exporter,
                                                              t->fields[k].def, &e), PL_OK);
    for (int k = 0; k < nfields; ++k) {
        char name[64];
        const char *eq = strchr(fields[k], '=');
        snprintf(name, sizeof name, "%.*s", (int)(eq - fields[k]), fields[k]);
        const pl_field *f = pl_component_field(r->exporter, name);
        ck_assert_msg(f != NULL, "no field %s", name);
        ck_assert_int_eq(pl_field_parse(f, r->exporter, eq + 1, &e), PL_OK);
    }
    pl_diag_init(&r->diag);
    r->ctx = (pl_ctx){.data = &r->data, .diag = &r->diag};
    set_state(r, 0);
}

static int rig_load(rig *r)
{
    const pl_type *t = r->exporter->type;
    int rc = t->ops.init ? t->ops.init(r->exporter, &r->ctx) : PL_OK;
    if (rc == PL_OK && t->ops.bind) rc = t->ops.bind(r->exporter, &r->ctx);
    return rc;
}

/* Exports after loading (step 0) and after steps 1..last, as pl_sim does. */
static void rig_run(rig *r, int first, int last, const char *out_dir, int every)
{
    const pl_exporter_ops *ops = pl_component_role(r->exporter, PL_ROLE_EXPORTER);
    for (int k = first; k <= last; ++k) {
        set_state(r, k);
        pl_export_info info = {out_dir, every, k, 0.02 * k};
        pl_error err;
        ck_assert_msg(ops->write(r->exporter, &r->ctx, &info, &err) == PL_OK, "%s", err.msg);
    }
}

static void rig_finish(rig *r)
{
    const pl_exporter_ops *ops = pl_component_role(r->exporter, PL_ROLE_EXPORTER);
    pl_export_info info = {NULL, 0, 0, 0};
    pl_error err;
    ck_assert_int_eq(ops->finish(r->exporter, &r->ctx, &info, &err), PL_OK);
}

static void rig_free(rig *r)
{
    const pl_type *t = r->exporter->type;
    if (t->ops.destroy) t->ops.destroy(r->exporter);
    for (int k = 0; k < t->nfields; ++k) pl_field_release(&t->fields[k], r->exporter);
    free(r->exporter);
    pl_diag_free(&r->diag);
}

/* ---- XML helpers ---------------------------------------------------------- */

static char *xpath_value(xmlDocPtr doc, const char *expr)
{
    xmlXPathContextPtr ctx = xmlXPathNewContext(doc);
    xmlXPathObjectPtr o = xmlXPathEvalExpression((const xmlChar *)expr, ctx);
    char *s = NULL;
    if (o && o->nodesetval && o->nodesetval->nodeNr > 0) {
        xmlChar *c = xmlNodeGetContent(o->nodesetval->nodeTab[0]);
        s = strdup((const char *)c);
        xmlFree(c);
    }
    xmlXPathFreeObject(o);
    xmlXPathFreeContext(ctx);
    return s;
}

static int xpath_count(xmlDocPtr doc, const char *expr)
{
    xmlXPathContextPtr ctx = xmlXPathNewContext(doc);
    xmlXPathObjectPtr o = xmlXPathEvalExpression((const xmlChar *)expr, ctx);
    int n = (o && o->nodesetval) ? o->nodesetval->nodeNr : -1;
    xmlXPathFreeObject(o);
    xmlXPathFreeContext(ctx);
    return n;
}

/* The series at pvd lists `n` frames <base>_%04d.vtu at times 0.02*steps[i],
 * each holding the state of that step. */
static void check_series(const char *dir, const char *base, int n, const int *steps,
                         int ncells, int with_velocity)
{
    char name[256];
    snprintf(name, sizeof name, "%s.pvd", base);
    xmlDocPtr pvd = xmlReadFile(tu_path(dir, name), NULL, XML_PARSE_NONET);
    ck_assert_ptr_nonnull(pvd);
    ck_assert_int_eq(xpath_count(pvd, "//DataSet"), n);
    for (int i = 0; i < n; ++i) {
        char expr[96], want[256];
        snprintf(expr, sizeof expr, "//DataSet[%d]/@file", i + 1);
        char *file = xpath_value(pvd, expr);
        snprintf(want, sizeof want, "%s_%04d.vtu", base, i);
        ck_assert_str_eq(file, want);
        snprintf(expr, sizeof expr, "//DataSet[%d]/@timestep", i + 1);
        char *ts = xpath_value(pvd, expr);
        ck_assert_double_eq(strtod(ts, NULL), 0.02 * steps[i]);
        free(ts);
        xmlDocPtr vtu = xmlReadFile(tu_path(dir, file), NULL, XML_PARSE_NONET);
        ck_assert_ptr_nonnull(vtu);
        free(file);
        ck_assert_int_eq(xpath_count(vtu, "//Piece[@NumberOfPoints='5']"), 1);
        snprintf(expr, sizeof expr, "//Piece[@NumberOfCells='%d']", ncells);
        ck_assert_int_eq(xpath_count(vtu, expr), 1);
        ck_assert_int_eq(xpath_count(vtu, "//PointData/DataArray[@Name='velocity']"),
                         with_velocity);
        char *fmt = xpath_value(vtu, "//Points/DataArray/@format");
        if (!strcmp(fmt, "ascii")) {
            char *pts = xpath_value(vtu, "//Points/DataArray"), *p = pts;
            for (int j = 0; j < NV * 3; ++j) ck_assert_double_eq(strtod(p, &p), j + steps[i] / 3.0);
            free(pts);
        }
        free(fmt);
        xmlFreeDoc(vtu);
    }
    xmlFreeDoc(pvd);
}

/* ---- VTKExporter ---------------------------------------------------------- */

START_TEST(vtk_exporter_writes_every_kth_step_with_cells)
{
    char *dir = tu_tmpdir();
    char prefix[1100];
    snprintf(prefix, sizeof prefix, "filename=%s/sub/dir/bar", dir); /* folders made on demand */
    const char *fields[] = {prefix, "every=2"};
    rig r;
    rig_make(&r, &pl_vtk_exporter_type, 1, fields, 2);
    ck_assert_int_eq(rig_load(&r), PL_OK);
    rig_run(&r, 0, 5, NULL, 0);
    rig_finish(&r);
    const int steps[] = {0, 2, 4};
    char sub[1100];
    snprintf(sub, sizeof sub, "%s/sub/dir", dir);
    check_series(sub, "bar", 3, steps, 2, 1);
    const pl_exporter_ops *ops = pl_component_role(r.exporter, PL_ROLE_EXPORTER);
    ck_assert_str_eq(ops->output_path(r.exporter), tu_path(sub, "bar.pvd"));
    ck_assert(!tu_exists(tu_path(sub, "bar_0003.vtu")));
    rig_free(&r);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(vtk_exporter_honours_out_dir_and_every_override)
{
    char *dir = tu_tmpdir();
    const char *fields[] = {"filename=not/used/folder/beam.vtu", "every=5", "binary=1",
                            "exportVelocity=0"};
    rig r;
    rig_make(&r, &pl_vtk_exporter_type, 0, fields, 4); /* no topology: points only */
    ck_assert_int_eq(rig_load(&r), PL_OK);
    char out[1100];
    snprintf(out, sizeof out, "%s/out", dir);
    rig_run(&r, 0, 6, out, 3); /* the run's every (3) overrides the field (5) */
    rig_finish(&r);
    /* after finish, more steps append to the same series */
    rig_run(&r, 7, 9, out, 3);
    rig_finish(&r);
    const int steps[] = {0, 3, 6, 9};
    check_series(out, "beam", 4, steps, NV, 0);
    ck_assert(!tu_exists("not/used"));
    rig_free(&r);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(vtk_exporter_load_errors)
{
    const char *fields[] = {"every=0"};
    rig r;
    rig_make(&r, &pl_vtk_exporter_type, 0, fields, 1);
    ck_assert_int_eq(rig_load(&r), PL_EINPUT);
    ck_assert_int_eq(r.diag.nerrors, 1);
    ck_assert_ptr_nonnull(strstr(r.diag.items[0].msg, "every"));
    ck_assert_int_eq(r.diag.items[0].line, 4);
    rig_free(&r);
    /* no state in the node */
    rig_make(&r, &pl_vtk_exporter_type, 0, NULL, 0);
    r.node.components[0] = r.exporter;
    r.node.ncomponents = 1;
    ck_assert_int_eq(rig_load(&r), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(r.diag.items[0].msg, "no state"));
    rig_free(&r);
}
END_TEST

/* ---- WriteState ----------------------------------------------------------- */

START_TEST(write_state_records_every_step_exactly)
{
    char *dir = tu_tmpdir();
    char fn[1100];
    snprintf(fn, sizeof fn, "filename=%s/bar.state.gz", dir);
    const char *fields[] = {fn, "writeV=1"};
    rig r;
    rig_make(&r, &pl_write_state_type, 0, fields, 2);
    ck_assert_int_eq(rig_load(&r), PL_OK);
    rig_run(&r, 0, 3, NULL, 7); /* the run's every does not thin a state file */
    rig_finish(&r);
    pl_state_records recs;
    pl_state_records_init(&recs);
    pl_error err;
    ck_assert_int_eq(pl_state_file_read(tu_path(dir, "bar.state.gz"), &recs, &err), PL_OK);
    ck_assert_int_eq(recs.count, 4);
    for (int k = 0; k < 4; ++k) {
        set_state(&r, k);
        ck_assert_double_eq(recs.items[k].time, 0.02 * k);
        ck_assert_int_eq(recs.items[k].nx, 3 * NV);
        ck_assert_mem_eq(recs.items[k].x, r.state.x, sizeof r.state.x);
        ck_assert_mem_eq(recs.items[k].v, r.state.v, sizeof r.state.v);
    }
    pl_state_records_free(&recs);
    rig_free(&r);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(write_state_period_and_default_name)
{
    char *dir = tu_tmpdir();
    const char *fields[] = {"period=0.05"};
    rig r;
    rig_make(&r, &pl_write_state_type, 0, fields, 1);
    ck_assert_int_eq(rig_load(&r), PL_OK);
    rig_run(&r, 0, 10, dir, 0); /* default file name "bar.state", put in out_dir */
    rig_finish(&r);
    pl_state_records recs;
    pl_state_records_init(&recs);
    pl_error err;
    ck_assert_int_eq(pl_state_file_read(tu_path(dir, "bar.state"), &recs, &err), PL_OK);
    /* dt 0.02: the first step at or after 0, 0.05, 0.10, 0.15, 0.20 */
    const int steps[] = {0, 3, 5, 8, 10};
    ck_assert_int_eq(recs.count, 5);
    for (int k = 0; k < 5; ++k) {
        ck_assert_double_eq(recs.items[k].time, 0.02 * steps[k]);
        ck_assert_double_eq(recs.items[k].x[1], 1 + steps[k] / 3.0);
        ck_assert_int_eq(recs.items[k].nv, 0);
    }
    const pl_exporter_ops *ops = pl_component_role(r.exporter, PL_ROLE_EXPORTER);
    ck_assert_str_eq(ops->output_path(r.exporter), tu_path(dir, "bar.state"));
    pl_state_records_free(&recs);
    rig_free(&r);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("export_components");
    TCase *tv = tcase_create("VTKExporter");
    tcase_add_test(tv, vtk_exporter_writes_every_kth_step_with_cells);
    tcase_add_test(tv, vtk_exporter_honours_out_dir_and_every_override);
    tcase_add_test(tv, vtk_exporter_load_errors);
    suite_add_tcase(s, tv);
    TCase *tw = tcase_create("WriteState");
    tcase_add_test(tw, write_state_records_every_step_exactly);
    tcase_add_test(tw, write_state_period_and_default_name);
    suite_add_tcase(s, tw);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    xmlCleanupParser();
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
