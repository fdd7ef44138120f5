#!/bin/sh
# exports.sh LIBPLIANT INCLUDE_DIR CC
# libpliant exports exactly what the SDK headers declare: the functions
# declared (not defined inline) in INCLUDE_DIR/pliant/*.h, listed by the
# compiler itself (gcc -aux-info), against the dynamic symbols LIBPLIANT
# defines (nm -D).  Prints both differences; fails if either is not empty.
set -eu
lib=$1
inc=$2
cc=$3
tmp=$(mktemp -d "${TMPDIR:-/tmp}/pliant_exports.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM

for h in "$inc"/pliant/*.h; do
    echo "#include \"pliant/$(basename "$h")\""
done >"$tmp/all.c"
"$cc" -std=c11 -D_GNU_SOURCE -I"$inc" -fsyntax-only -aux-info "$tmp/aux.txt" "$tmp/all.c"
# "/* <inc>/pliant/x.h:12:NC */ extern int pl_f (int);" -> pl_f
grep "^/\* $inc/pliant/[a-z_]*\.h:" "$tmp/aux.txt" | grep " \*/ extern " |
    sed 's/ (.*//; s/.*[ *]//' | sort -u >"$tmp/declared"
# defined dynamic symbols, without the toolchain's own (leading underscore)
nm -D --defined-only "$lib" | awk '{print $NF}' | sed 's/@.*//' | grep -v '^_' | sort -u \
    >"$tmp/exported"
test -s "$tmp/declared" || { echo "exports: no declarations found in $inc/pliant" >&2; exit 1; }
status=0
comm -13 "$tmp/declared" "$tmp/exported" >"$tmp/extra"
comm -23 "$tmp/declared" "$tmp/exported" >"$tmp/missing"
if [ -s "$tmp/extra" ]; then
    echo "exports: libpliant exports $(wc -l <"$tmp/extra") symbols no SDK header declares:" >&2
    sed 's/^/  /' "$tmp/extra" >&2
    status=1
fi
if [ -s "$tmp/missing" ]; then
    echo "exports: $(wc -l <"$tmp/missing") SDK functions are not exported (PL_API missing?):" >&2
    sed 's/^/  /' "$tmp/missing" >&2
    status=1
fi
[ $status = 0 ] && echo "exports: ok, $(wc -l <"$tmp/declared") SDK functions, the same exported"
exit $status
