/* test_timer.c - the timers' per-frame table ("frames" in the timings JSON):
 * one value per frame for every phase (0 where it did not run, a phase
 * created late padded with zeros) and every pl_stat_max statistic (the largest
 * value of each frame, while the statistic itself keeps the run's maximum);
 * a watched phase's off-CPU time and page faults (pl_timer_watch). */
#define _POSIX_C_SOURCE 200809L
#include <check.h>
#include <pliant/pliant.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The JSON of t, in a malloc'd string. */
static char *json_of(const pl_timers *t)
{
    FILE *f = tmpfile();
    ck_assert_ptr_nonnull(f);
    ck_assert_int_eq(pl_timers_write_json(t, f), 0);
    long len = ftell(f);
    char *buf = malloc((size_t)len + 1);
    ck_assert_ptr_nonnull(buf);
    rewind(f);
    ck_assert_int_eq((long)fread(buf, 1, (size_t)len, f), len);
    buf[len] = '\0';
    fclose(f);
    return buf;
}

START_TEST(frames_align_phases_and_frame_maxima)
{
    pl_timers *t = pl_timers_create();
    int frame = pl_timer_id(t, "Frame");
    /* frame 0: Frame 2 ms, contacts 3 then 5 */
    pl_timer_add(t, frame, 0.002);
    pl_stat_max(t, "contacts max", 3);
    pl_stat_max(t, "contacts max", 5);
    pl_stat_set(t, "nnz(S)", 7);
    pl_timers_end_frame(t);
    /* frame 1: Detection appears (1 ms), Frame 4 ms, contacts 2 */
    int det = pl_timer_id(t, "Detection");
    pl_timer_add(t, det, 0.001);
    pl_timer_add(t, frame, 0.004);
    pl_stat_max(t, "contacts max", 2);
    pl_timers_end_frame(t);
    /* frame 2: Frame 1 ms, no contact statistic, no detection */
    pl_timer_add(t, frame, 0.001);
    pl_timers_end_frame(t);

    double v;
    ck_assert_int_eq(pl_stat_get(t, "contacts max", &v), 0);
    ck_assert(v == 5.0); /* the run's maximum is unchanged */
    ck_assert_int_eq(pl_timers_samples(t, det), 1); /* samples: frames that ran */
    char *js = json_of(t);
    ck_assert_ptr_nonnull(strstr(js, "\"count\": 3"));
    ck_assert_ptr_nonnull(strstr(js, "\"Frame\": [2, 4, 1]"));
    ck_assert_ptr_nonnull(strstr(js, "\"Detection\": [0, 1, 0]"));
    ck_assert_ptr_nonnull(strstr(js, "\"contacts max\": [5, 2, 0]"));
    ck_assert_ptr_null(strstr(js, "\"nnz(S)\": [")); /* set, not max: no column */
    free(js);

    pl_timers_clear(t); /* a fresh table; the phases' ids stay valid */
    pl_timer_add(t, frame, 0.003);
    pl_timers_end_frame(t);
    ck_assert_int_eq(pl_timer_id(t, "Frame"), frame);
    ck_assert_int_eq(pl_timers_samples(t, frame), 1);
    ck_assert_int_eq(pl_stat_get(t, "contacts max", &v), -1);
    js = json_of(t);
    ck_assert_ptr_nonnull(strstr(js, "\"count\": 1"));
    ck_assert_ptr_nonnull(strstr(js, "\"Frame\": [3]"));
    free(js);
    pl_timers_free(t);
}
END_TEST

/* The two values of column `name` in the JSON js of two frames. */
static void two_values(const char *js, const char *name, double v[2])
{
    char key[96];
    snprintf(key, sizeof key, "\"%s\": [", name);
    const char *p = strstr(js, key);
    ck_assert_msg(p != NULL, "no column %s", name);
    ck_assert_int_eq(sscanf(p + strlen(key), "%lf, %lf", &v[0], &v[1]), 2);
}

/* Frame 0 sleeps 30 ms inside the watched phase: off its CPU for about that
 * long.  Frame 1 writes 32 MB of fresh memory: page faults (at least one
 * even with 2 MB pages), and the writing thread on its CPU, so less than
 * half the wall time off it on any machine not starved of CPU. */
START_TEST(watch_tells_off_cpu_and_faults)
{
    pl_timers *t = pl_timers_create();
    int w = pl_timer_id(t, "Watched");
    pl_timer_watch(t, w);
    pl_timer_start(t, w);
    struct timespec ts = {0, 30000000L};
    while (nanosleep(&ts, &ts) != 0) {
    }
    pl_timer_stop(t, w);
    pl_timers_end_frame(t);
    size_t bytes = (size_t)32 << 20;
    pl_timer_start(t, w);
    volatile char *mem = malloc(bytes);
    ck_assert_ptr_nonnull((void *)mem);
    for (size_t k = 0; k < bytes; k += 4096) mem[k] = (char)k;
    pl_timer_stop(t, w);
    free((void *)mem);
    pl_timers_end_frame(t);

    char *js = json_of(t);
    double wall[2], off[2], faults[2], pre[2];
    two_values(js, "Watched", wall);
    two_values(js, "Watched off-CPU ms", off);
    two_values(js, "Watched page faults", faults);
    two_values(js, "Watched preemptions", pre);
    ck_assert_msg(wall[0] >= 29.0 && off[0] >= 25.0 && off[0] <= wall[0],
                  "sleep: wall %g ms, off-CPU %g ms", wall[0], off[0]);
    ck_assert_msg(faults[1] >= 1.0, "32 MB written, %g page faults", faults[1]);
    ck_assert_msg(off[1] < 0.5 * wall[1] + 1.0, "writing: wall %g ms, off-CPU %g ms", wall[1],
                  off[1]);
    ck_assert(pre[0] >= 0.0 && pre[1] >= 0.0);
    ck_assert_ptr_null(strstr(js, "\"Frame off-CPU ms\"")); /* only the watched phase */
    free(js);
    pl_timers_free(t);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("timer");
    TCase *tc = tcase_create("frames");
    tcase_add_test(tc, frames_align_phases_and_frame_maxima);
    tcase_add_test(tc, watch_tells_off_cpu_and_faults);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
