/* log.c - leveled logging to stderr or a sink. */
#include "pliant/log.h"

#include <stdarg.h>
#include <stdio.h>

static pl_log_level g_level = PL_LOG_INFO;
static pl_log_sink g_sink;
static void *g_sink_user;

void pl_log_set_level(pl_log_level level) { g_level = level; }
pl_log_level pl_log_get_level(void) { return g_level; }

void pl_log_set_sink(pl_log_sink sink, void *user)
{
    g_sink = sink;
    g_sink_user = user;
}

void pl_log(pl_log_level level, const char *fmt, ...)
{
    static const char *names[] = {"error", "warning", "info", "debug"};
    char msg[2048];
    va_list ap;
    if (level > g_level) return;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (g_sink)
        g_sink(level, msg, g_sink_user);
    else
        fprintf(stderr, "pliant: %s: %s\n", names[level], msg);
}
