/* groups.c - collision groups as sets, as SoftRobots writes them: a model's
 * `group` lists the groups it belongs to ("1 2 3"; 0 or nothing: none), and
 * two models that share a group never collide.  A finger's collision patches
 * can then each share a group with the finger's own surface (so they ignore
 * it) without sharing one with each other (so they touch when it bends). */
#include "collision.h"

int collision_groups(const pl_ints *list, unsigned *mask, pl_error *err)
{
    unsigned m = 0;
    for (int i = 0; i < list->n; ++i) {
        int k = list->v[i];
        if (k < 0 || k > PL_COLLISION_MAX_GROUP)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "group %d: groups are numbered 1..%d (0: none)", k,
                                PL_COLLISION_MAX_GROUP);
        if (k > 0) m |= 1u << (k - 1);
    }
    *mask = m;
    return PL_OK;
}
