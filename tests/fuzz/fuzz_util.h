/* fuzz_util.h - what the harnesses of tests/fuzz share: quiet logging, and
 * a file in memory (memfd) for the readers that take a path. */
#ifndef PL_FUZZ_UTIL_H
#define PL_FUZZ_UTIL_H

#include <stddef.h>
#include <stdint.h>

/* Every harness defines this one (libFuzzer's entry point). */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Turns Pliant's log down to errors (once). */
void fuzz_quiet(void);
/* Writes data into this process's memory file and returns a path that
 * opens it ("/proc/self/fd/N"); NULL on failure. */
const char *fuzz_memfile(const uint8_t *data, size_t size);

#endif
