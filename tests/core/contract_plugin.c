/* contract_plugin.c - a plugin for the contract tests: "TestFailer" fails
 * at the stage its field failAt names (init, bind, reinit, begin_step,
 * end_step) by returning a status without recording any message, as a
 * careless plugin would; the core must still stop and name it. */
#include <pliant/pliant.h>

typedef struct test_failer {
    pl_component base;
    int fail_at;   /* index into STAGES */
    int code;      /* the status returned */
} test_failer;

enum { NONE, INIT, BIND, REINIT, BEGIN, END };
static const char *const STAGES[] = {"none", "init", "bind", "reinit", "begin_step", "end_step",
                                     NULL};

static const pl_field FIELDS[] = {
    PL_FIELD_ENUM(test_failer, fail_at, "failAt", STAGES, "none",
                  "the stage that fails without a message", 0),
    PL_FIELD(test_failer, code, "code", PL_F_INT, "2", "the status returned there", 0),
};

static int at(const pl_component *c, int stage)
{
    const test_failer *f = (const test_failer *)c;
    return f->fail_at == stage ? f->code : PL_OK;
}

static int tf_init(pl_component *c, pl_ctx *ctx) { return at(c, INIT); }
static int tf_bind(pl_component *c, pl_ctx *ctx) { return at(c, BIND); }
static int tf_reinit(pl_component *c, pl_ctx *ctx) { return at(c, REINIT); }
static int tf_begin(const pl_component *c, pl_ctx *ctx, pl_error *err) { return at(c, BEGIN); }
static int tf_end(const pl_component *c, pl_ctx *ctx, pl_error *err) { return at(c, END); }

static const pl_type TEST_FAILER = {
    .abi_version = PL_ABI_VERSION,
    .name = "TestFailer",
    .help = "test component: fails silently at one stage",
    .size = sizeof(test_failer),
    .fields = FIELDS,
    .nfields = 2,
    .ops = {.init = tf_init, .bind = tf_bind, .reinit = tf_reinit, .begin_step = tf_begin,
            .end_step = tf_end},
};

/* For the test of identity by pointer: the type's own address. */
PL_EXPORT const pl_type *pl_contract_failer_type(void);
PL_EXPORT const pl_type *pl_contract_failer_type(void) { return &TEST_FAILER; }

static const pl_type *const TYPES[] = {&TEST_FAILER};
PL_PLUGIN_DEFINE(TYPES)
