/* pipeline.h - the CollisionPipeline component's internals (plugin-
 * internal): its fields and model, the per-step stages (pipeline_step.c)
 * and the contact records kept in the pl_data slot "contacts". */
#ifndef PLIANT_COLLISION_PIPELINE_H
#define PLIANT_COLLISION_PIPELINE_H

#include "collision.h"
#include "detect.h"
#include "pliant/pliant.h"

/* One contact as recorded per step (an array of these in the slot). */
typedef struct coll_contact_record {
    pl_proximity prox;             /* what detection found: models, mesh vertices, weights,
                                      normal (from B to A), gap at the start of the step */
    double point_a[3], point_b[3]; /* closest points at the start of the step [m] */
    double t1[3], t2[3];           /* tangents of the friction rows */
    double lambda[3];              /* multipliers: normal, t1, t2 [N] (0 until solved) */
    double force[3];               /* force on side A [N]; side B gets -force */
} coll_contact_record;

/* frictionRule: how two models' mu combine */
enum { COLL_RULE_MIN, COLL_RULE_MAX, COLL_RULE_MEAN, COLL_RULE_PRODUCT };

/* A collision model as a data's workspace keeps it between steps. */
typedef struct pipe_model {
    pl_component *c;
    pl_collision_geometry g;       /* this step's geometry */
    pl_coll_mesh mesh;             /* detection structures (BVHs refitted per step) */
    double *x0, *x1;               /* nverts x 3 [m] */
    unsigned char *active;         /* per point: maps to at least one free vertex */
    int nverts, ntris, nedges;     /* topology of the last step (a change rebuilds) */
    const int *tris, *edges;
} pipe_model;

typedef struct collision_pipeline {
    pl_component base;
    /* fields */
    double alarm, contact, mu;
    int rule, self, vertex_face, edge_edge, max_per_vertex;
    int out_count, out_ee;
    pl_doubles out_points, out_normals, out_forces;
    /* model */
    pl_component **models;         /* the scene's collision models */
    int nmodels;
    int slot, t_detect;
} collision_pipeline;

/* Per data (pl_data_workspace): the models' geometry and detection
 * structures, and the step's lists. */
typedef struct coll_ws {
    pipe_model *models;            /* nmodels, made on first use */
    double *struck;                /* nmodels x nmodels: speed at which model j strikes k [m/s] */
    pl_proximities prox;
    pl_side_hints hints;           /* sides of the previous step's contacts */
    coll_contact_record *work;
    int nwork, capwork;
    struct emit_item *emit;        /* the contacts prepared for emission (pipeline_step.c) */
    int capemit;
    struct coll_dev *dev;          /* device detection (pipeline_device.c), NULL: host */
    int dev_state;                 /* 0 not yet chosen, 1 device, 2 by the rule, -1 host */
    int dev_step;                  /* this step's pairs went through the device */
    int dev_steps;                 /* steps that did */
    long long last_overlaps;       /* the previous step's box overlaps (the rule's input) */
    int *pairs, cap_pairs;         /* this step's pairs of models (k, l) */
    coll_cand_list *cand;          /* the device's candidates: 3 lists per pair */
    const pl_coll_mesh **batch_a, **batch_b;
    long long *batch_overlaps;     /* per pair: its box overlaps */
    int cap_batch;
    double pairs_ms;               /* this step's time in coll_detect_models [ms] */
    double cand_ms;                /* of which the device's candidates [ms] */
    pl_detect_counts counts;       /* this step's detection work (statistics) */
    double margin_max;             /* the largest margin of a second pass this step [m] */
} coll_ws;

extern const pl_type coll_pipeline_type;

/* Stage 1: geometry of every model, x0 / x1, prepared meshes. */
int coll_pipeline_update_models(const collision_pipeline *p, coll_ws *w, pl_ctx *ctx,
                                const pl_system *sys, const pl_buffer *q, pl_error *err);
/* Stage 2: proximities of every pair of models that may touch (w->prox);
 * d holds the previous step's contacts (their sides are kept); h the step. */
int coll_pipeline_detect(const collision_pipeline *p, coll_ws *w, const pl_data *d, double h,
                         pl_error *err);
/* Models k and l's proximities appended to w->prox: detect_pair, or, on
 * the device as PLIANT_DETECT says, over the device's candidates
 * (pipeline_device.c; the same proximities).  PL_OK or PL_EINTERNAL. */
int coll_detect_models(const collision_pipeline *p, coll_ws *w, int k, int l,
                       const pl_detect_params *prm, pl_error *err);
/* The same for n pairs (k, l) = (kl[2 i], kl[2 i + 1]), appended in that
 * order; on the device, their candidates in one batch. */
int coll_detect_pairs(const collision_pipeline *p, coll_ws *w, int n, const int *kl,
                      const pl_detect_params *prm, pl_error *err);
void coll_detect_ws_free(coll_ws *w);

/* PLIANT_DETECT=auto puts a step's pairs on the device when the step before
 * had at least this many box overlaps (calibration: docs/benchmarks.md,
 * "Detection on the device: the batch"). */
#define COLL_DEV_MIN_OVERLAPS 40000

/* Stage 3: rows and records (w->work) of the proximities. */
int coll_pipeline_emit(const collision_pipeline *p, coll_ws *w, const pl_system *sys,
                       pl_rows *rows, pl_error *err);

/* The contacts recorded in d during the last step (count; *items points
 * into d, valid until the next step). */
int coll_pipeline_contacts(const pl_component *c, const pl_data *d,
                           const coll_contact_record **items);

#endif
