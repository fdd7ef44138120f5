/* sofa.h - SOFA's vocabulary as Pliant reads it: the one table (in libpliant)
 * that the scene loader applies to SOFA scenes, written out for people
 * (docs/sofa-vocabulary.md, `pliant doc --sofa`) and for programs (a
 * Python package reading SOFA scenes uses the same table as tab-separated
 * text instead of a copy of its own).  docs/sofa.md explains it. */
#ifndef PLIANT_SOFA_H
#define PLIANT_SOFA_H

#include "api.h"

/* Writes the table to `stdio_file` (a FILE *): format "markdown" (two
 * tables: components, then attributes) or "tsv" (one line per entry:
 * "component" TAB sofa_name TAB kind TAB pliant_name TAB plugin TAB note, or
 * "attribute" TAB sofa_component TAB sofa_attribute TAB kind TAB pliant_field
 * TAB note; empty cells where there is nothing).  Returns 0, or -1 for an
 * unknown format or a write error. */
#if PL_ABI_TARGET_MINOR >= 3 /* since 5.3 */
PL_API int pl_sofa_write_vocabulary(void *stdio_file, const char *format);
#endif

#endif
