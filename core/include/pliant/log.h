/* log.h - a leveled logger.  Messages go to stderr unless a sink is set.
 * The level is process-wide because logging is a diagnostic concern, not
 * simulation state; everything else in Pliant hangs off explicit handles. */
#ifndef PLIANT_LOG_H
#define PLIANT_LOG_H

#include "api.h"
#ifdef __cplusplus
extern "C" {
#endif

typedef enum pl_log_level {
    PL_LOG_ERROR = 0,
    PL_LOG_WARN = 1,
    PL_LOG_INFO = 2,
    PL_LOG_DEBUG = 3
} pl_log_level;

typedef void (*pl_log_sink)(pl_log_level level, const char *msg, void *user);

PL_API void pl_log_set_level(pl_log_level level);
PL_API pl_log_level pl_log_get_level(void);
/* Redirects messages (NULL restores stderr). */
PL_API void pl_log_set_sink(pl_log_sink sink, void *user);
PL_API void pl_log(pl_log_level level, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

#define pl_log_error(...) pl_log(PL_LOG_ERROR, __VA_ARGS__)
#define pl_log_warn(...) pl_log(PL_LOG_WARN, __VA_ARGS__)
#define pl_log_info(...) pl_log(PL_LOG_INFO, __VA_ARGS__)
#define pl_log_debug(...) pl_log(PL_LOG_DEBUG, __VA_ARGS__)

#ifdef __cplusplus
}
#endif
#endif
