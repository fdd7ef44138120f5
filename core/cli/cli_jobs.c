/* cli_jobs.c - a run in a forked child, its report through a pipe.
 *
 * The parent must not have entered an OpenMP parallel region before it
 * forks (libgomp's thread pool does not survive fork): the commands that
 * use this do all their computing in children. */
#include <pliant/pliant.h>

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli_jobs.h"

static void child(int wfd, int job, cli_job_fn fn, void *ctx, const char *gpu)
{
    if (gpu) setenv("CUDA_VISIBLE_DEVICES", gpu, 1);
    FILE *out = fdopen(wfd, "w");
    int rc = out ? fn(job, ctx, out) : 1;
    if (out) fclose(out);
    fflush(stdout);
    fflush(stderr);
    _exit(rc); /* not exit(): the parent's atexit handlers (MPI's) are not ours to run */
}

int cli_job_start(cli_job *j, int job, cli_job_fn fn, void *ctx, double timeout, const char *gpu)
{
    memset(j, 0, sizeof *j);
    j->job = job;
    j->timeout = timeout;
    j->pid = -1;
    j->fd = -1;
    int p[2];
    if (pipe(p) != 0) return -1;
    fflush(stdout); /* else the child would write the parent's buffered lines again */
    fflush(stderr);
    j->t0 = pl_now();
    pid_t pid = fork();
    if (pid < 0) {
        close(p[0]);
        close(p[1]);
        return -1;
    }
    if (pid == 0) {
        close(p[0]);
        child(p[1], job, fn, ctx, gpu);
    }
    close(p[1]);
    fcntl(p[0], F_SETFL, O_NONBLOCK); /* drain() reads what is there, never waits */
    j->pid = pid;
    j->fd = p[0];
    return 0;
}

/* Reads what is there; returns 1 at end of file. */
static int drain(cli_job *j)
{
    for (;;) {
        if (j->cap - j->len < 4096) {
            size_t cap = j->cap ? 2 * j->cap : 8192;
            char *b = realloc(j->buf, cap);
            if (!b) return 1;
            j->buf = b, j->cap = cap;
        }
        ssize_t n = read(j->fd, j->buf + j->len, j->cap - j->len - 1);
        if (n > 0) {
            j->len += (size_t)n;
            continue;
        }
        if (n < 0 && errno == EINTR) continue;
        return n == 0 || errno != EAGAIN;
    }
}

static void finish(cli_job *j, int status, int timed_out, cli_job_result *res)
{
    memset(res, 0, sizeof *res);
    res->job = j->job;
    res->seconds = pl_now() - j->t0;
    if (j->pid < 0) {
        res->end = CLI_JOB_NOT_STARTED;
    } else if (timed_out) {
        res->end = CLI_JOB_TIMED_OUT;
    } else if (WIFSIGNALED(status)) {
        res->end = CLI_JOB_SIGNALLED;
        res->code = WTERMSIG(status);
    } else {
        res->end = CLI_JOB_EXITED;
        res->code = WIFEXITED(status) ? WEXITSTATUS(status) : 1;
    }
    if (j->buf) j->buf[j->len] = '\0';
    res->text = j->buf ? j->buf : calloc(1, 1);
    j->buf = NULL;
    if (j->fd >= 0) close(j->fd);
    j->fd = -1;
    gethostname(res->host, sizeof res->host - 1);
}

int cli_job_poll(cli_job *j, int wait_ms, cli_job_result *res)
{
    int status = 0;
    if (j->pid < 0) return finish(j, 0, 0, res), 1;
    if (j->fd >= 0) {
        double left = j->timeout > 0 ? j->timeout - (pl_now() - j->t0) : 1e9;
        if (left <= 0) {
            kill(j->pid, SIGKILL);
            while (waitpid(j->pid, &status, 0) < 0 && errno == EINTR) {}
            return finish(j, status, 1, res), 1;
        }
        int ms = left * 1e3 < wait_ms ? (int)(left * 1e3) + 1 : wait_ms;
        struct pollfd pfd = {j->fd, POLLIN, 0};
        if (poll(&pfd, 1, ms) <= 0) return 0;
        if (!drain(j)) return 0;
        close(j->fd);
        j->fd = -1;
    }
    /* end of the report: the child is exiting (or was killed) */
    while (waitpid(j->pid, &status, 0) < 0 && errno == EINTR) {}
    finish(j, status, 0, res);
    return 1;
}

void cli_job_result_free(cli_job_result *r)
{
    free(r->text);
    r->text = NULL;
}

void cli_job_describe(const cli_job_result *r, double timeout, char *buf, size_t size)
{
    switch (r->end) {
    case CLI_JOB_EXITED: snprintf(buf, size, "ended with exit code %d", r->code); break;
    case CLI_JOB_SIGNALLED: {
        const char *abbrev = sigabbrev_np(r->code);
        snprintf(buf, size, "crashed: SIG%s (%s)", abbrev ? abbrev : "?", strsignal(r->code));
        break;
    }
    case CLI_JOB_TIMED_OUT: snprintf(buf, size, "timed out after %g s", timeout); break;
    default: snprintf(buf, size, "could not start (fork failed)"); break;
    }
}

const char *cli_report_get(const char *report, const char *key, char *buf, size_t size)
{
    size_t n = strlen(key);
    for (const char *p = report; p && *p;) {
        const char *nl = strchr(p, '\n');
        size_t len = nl ? (size_t)(nl - p) : strlen(p);
        if (len > n && !strncmp(p, key, n) && p[n] == ' ') {
            snprintf(buf, size, "%.*s", (int)(len - n - 1), p + n + 1);
            return buf;
        }
        p = nl ? nl + 1 : NULL;
    }
    return NULL;
}
