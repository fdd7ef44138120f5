#!/bin/sh
# release_build.sh SOURCE_DIR CMAKE
# `cmake -S . -B build -DCMAKE_BUILD_TYPE=Release` as a user types it builds,
# without -Werror (only make test and CI ask for it) and without a warning:
# gcc at -O3 sees more (format truncation, maybe-uninitialized) than the -O2
# of make test's builds.  The library, the plugins and the CLI, without CUDA
# and without the test suite (to keep it short).
set -eu
src=$1
cmake=$2
tmp=$(mktemp -d "${TMPDIR:-/tmp}/pliant_release.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM

fail() {
    echo "release_build: FAIL: $*" >&2
    exit 1
}

"$cmake" -S "$src" -B "$tmp/build" -DCMAKE_BUILD_TYPE=Release -DPLIANT_CUDA=OFF \
    -DPLIANT_TESTS=OFF >"$tmp/configure.log" 2>&1 ||
    { cat "$tmp/configure.log" >&2; fail "configure"; }
if grep -rq -- "-Werror" "$tmp/build" --include=flags.make; then
    grep -r -- "-Werror" "$tmp/build" --include=flags.make | head -3 >&2
    fail "a plain Release configure compiles with -Werror"
fi
"$cmake" --build "$tmp/build" -j "${JOBS:-2}" >"$tmp/build.log" 2>&1 ||
    { grep -E "error|warning" "$tmp/build.log" | head -40 >&2; fail "the Release build failed"; }
if grep -q "warning:" "$tmp/build.log"; then
    grep -A3 "warning:" "$tmp/build.log" | head -60 >&2
    fail "the Release build has warnings"
fi
test -x "$tmp/build/bin/pliant" || fail "no bin/pliant"
"$tmp/build/bin/pliant" list >/dev/null 2>&1 || fail "the Release pliant does not run"
echo "release_build: ok (Release, no -Werror, no warning)"
