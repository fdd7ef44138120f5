/* pvd_series.c - a ParaView time series (.pvd: VTKFile type="Collection").
 *
 * The footer is written after every entry and the next entry overwrites it
 * (the file only grows, so nothing stale is left behind): the .pvd is a
 * complete XML document whenever a viewer opens it during a run. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "export/export.h"
#include "export/export_internal.h"

struct pl_pvd {
    FILE *f;
    char *path;
    long footer_pos;   /* where the next entry goes */
    int count;
};

static const char pvd_header[] =
    "<?xml version=\"1.0\"?>\n"
    "<VTKFile type=\"Collection\" version=\"0.1\">\n"
    "  <Collection>\n";
static const char pvd_footer[] = "  </Collection>\n</VTKFile>\n";

static int write_footer(pl_pvd *s, pl_error *err)
{
    if (fputs(pvd_footer, s->f) < 0 || fflush(s->f) != 0)
        return pl_error_set(err, PL_EINTERNAL, s->path, 0, NULL, "writing the series failed");
    return PL_OK;
}

static int start_new(pl_pvd *s, pl_error *err)
{
    s->f = fopen(s->path, "w+b");
    if (!s->f) return pl_error_set(err, PL_EINPUT, s->path, 0, NULL, "cannot write the series");
    if (fputs(pvd_header, s->f) < 0)
        return pl_error_set(err, PL_EINTERNAL, s->path, 0, NULL, "writing the series failed");
    s->footer_pos = ftell(s->f);
    return write_footer(s, err);
}

/* Finds the footer of an existing series and counts its entries. */
static int resume(pl_pvd *s, pl_error *err)
{
    long size = fseek(s->f, 0, SEEK_END) == 0 ? ftell(s->f) : -1;
    if (size < 0 || fseek(s->f, 0, SEEK_SET) != 0)
        return pl_error_set(err, PL_EINTERNAL, s->path, 0, NULL, "cannot read the series");
    char *text = malloc((size_t)size + 1);
    if (!text) return pl_error_set(err, PL_EINTERNAL, s->path, 0, NULL, "out of memory");
    size_t got = fread(text, 1, (size_t)size, s->f);
    text[got] = '\0';
    size_t nf = strlen(pvd_footer);
    int rc = PL_OK;
    if (got != (size_t)size || got < nf || strcmp(text + got - nf, pvd_footer) != 0 ||
        strncmp(text, pvd_header, strlen(pvd_header)) != 0) {
        rc = pl_error_set(err, PL_EINPUT, s->path, 0, NULL,
                          "cannot append: not a complete .pvd series written by Pliant");
    } else {
        s->footer_pos = (long)(got - nf);
        for (const char *p = text; (p = strstr(p, "<DataSet ")) != NULL; ++p) ++s->count;
    }
    free(text);
    return rc;
}

pl_pvd *pl_pvd_open(const char *path, int append, pl_error *err)
{
    if (!path || !*path) {
        pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "a .pvd series needs a file name");
        return NULL;
    }
    pl_pvd *s = calloc(1, sizeof *s);
    if (s) s->path = strdup(path);
    if (!s || !s->path) {
        free(s);
        pl_error_set(err, PL_EINTERNAL, path, 0, NULL, "out of memory");
        return NULL;
    }
    int rc;
    s->f = append ? fopen(path, "r+b") : NULL;
    if (s->f)
        rc = resume(s, err);
    else if (append && errno != ENOENT)
        rc = pl_error_set(err, PL_EINPUT, path, 0, NULL, "cannot open the series: %s",
                          strerror(errno));
    else
        rc = start_new(s, err);
    if (rc != PL_OK) {
        if (s->f) fclose(s->f);
        free(s->path);
        free(s);
        return NULL;
    }
    return s;
}

int pl_pvd_append(pl_pvd *s, double time, const char *file, pl_error *err)
{
    return pl_pvd_append_part(s, time, 0, file, err);
}

int pl_pvd_append_part(pl_pvd *s, double time, int part, const char *file, pl_error *err)
{
    if (!s || !file) return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "invalid series entry");
    if (fseek(s->f, s->footer_pos, SEEK_SET) != 0)
        return pl_error_set(err, PL_EINTERNAL, s->path, 0, NULL, "seeking in the series failed");
    fprintf(s->f, "    <DataSet timestep=\"%.17g\" group=\"\" part=\"%d\" file=\"", time, part);
    pl_export_xml_attr(s->f, file);
    fputs("\"/>\n", s->f);
    long pos = ftell(s->f);
    if (ferror(s->f) || pos < 0)
        return pl_error_set(err, PL_EINTERNAL, s->path, 0, NULL, "writing the series failed");
    s->footer_pos = pos;
    s->count++;
    return write_footer(s, err);
}

int pl_pvd_count(const pl_pvd *s)
{
    return s ? s->count : 0;
}

int pl_pvd_close(pl_pvd *s, pl_error *err)
{
    if (!s) return PL_OK;
    int rc = PL_OK;
    if (fclose(s->f) != 0)
        rc = pl_error_set(err, PL_EINTERNAL, s->path, 0, NULL, "closing the series failed");
    free(s->path);
    free(s);
    return rc;
}
