#!/bin/sh
# sdk_test.sh SOURCE_DIR BINARY_DIR CMAKE CTEST
# An out-of-tree plugin against an installed Pliant, as a user would do it:
#  1. cmake --install the build into a temporary prefix, then MOVE the
#     prefix elsewhere (an install is relocatable), and check the layout:
#     bin/pliant finds lib/libpliant.so.0 of the moved prefix, the plugins
#     are libpliant_<name>.so (no libcuda.so, the NVIDIA driver's name),
#     the tutorial plugin is not installed, pliant.pc is beside the CMake
#     package; `pliant list` finds the plugins relative to the library and
#     warns about a plugin folder that is missing or empty;
#  2. configure plugins/template_constraint on its own with
#     find_package(Pliant) (CMAKE_PREFIX_PATH=prefix) and build it;
#  3. run scenes/template_constraint.xml with the installed pliant, the
#     plugin found through PLIANT_PLUGIN_PATH (and check that the copy loaded
#     is the one just built), the others in the moved install;
#  4. run the template's own Check test (ctest in the out-of-tree build);
#  5. build the same plugin with a plain compiler line and pkg-config, run
#     the scene with it;
#  6. build and run a program embedding Pliant through
#     target_link_libraries(x PRIVATE Pliant::pliant).
set -eu
src=$1
bin=$2
cmake=$3
ctest=$4
tmp=$(mktemp -d "${TMPDIR:-/tmp}/pliant_sdk.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM
unset PLIANT_PLUGIN_PATH || true

fail() {
    echo "sdk_test: FAIL: $*" >&2
    exit 1
}

# ---- 1. install, move, layout ------------------------------------------------
"$cmake" --install "$bin" --prefix "$tmp/first" >"$tmp/install.log" 2>&1 ||
    { cat "$tmp/install.log" >&2; fail "cmake --install"; }
prefix=$tmp/moved/elsewhere
mkdir -p "$tmp/moved"
mv "$tmp/first" "$prefix"
for f in bin/pliant lib/libpliant.so include/pliant/pliant.h include/pliant/rows.h \
    include/pliant/util.h include/pliant/api.h lib/cmake/Pliant/PliantConfig.cmake \
    lib/cmake/Pliant/PliantConfigVersion.cmake lib/pkgconfig/pliant.pc \
    lib/pliant/plugins/libpliant_hyperelastic.so lib/pliant/plugins/libpliant_sparse_inverse.so \
    lib/pliant/plugins/libpliant_ncp_contact.so lib/pliant/plugins/libpliant_cable.so \
    lib/pliant/plugins/libpliant_collision.so lib/pliant/plugins/libpliant_cuda.so; do
    test -e "$prefix/$f" || fail "the install has no $f"
done
test ! -e "$prefix/lib/pliant/plugins/libpliant_template_constraint.so" ||
    fail "the tutorial plugin is installed as part of the SDK"
found=$(find "$prefix" -name 'libcuda.so*')
test -z "$found" || fail "the install holds $found, the NVIDIA driver's file name"
if command -v ldd >/dev/null 2>&1; then
    ldd "$prefix/bin/pliant" | grep -q "libpliant.so.0 => $prefix/" ||
        { ldd "$prefix/bin/pliant" >&2; fail "the moved pliant does not use the moved libpliant"; }
fi
"$prefix/bin/pliant" list >"$tmp/list0.txt" 2>"$tmp/list0.err" ||
    { cat "$tmp/list0.err" >&2; fail "pliant list in the moved install"; }
grep -q "^  hyperelastic *$prefix/lib/pliant/plugins/libpliant_hyperelastic.so" "$tmp/list0.txt" ||
    { cat "$tmp/list0.txt" >&2; fail "pliant list does not find the plugins beside the moved library"; }
test ! -s "$tmp/list0.err" || { cat "$tmp/list0.err" >&2; fail "pliant list warns in a good install"; }
mkdir "$tmp/empty"
PLIANT_PLUGIN_PATH="$tmp/nowhere:$tmp/empty" "$prefix/bin/pliant" list >/dev/null 2>"$tmp/list1.err" ||
    true
grep -q "$tmp/nowhere.*warning.*plugin folder missing" "$tmp/list1.err" ||
    { cat "$tmp/list1.err" >&2; fail "pliant list does not warn about a missing plugin folder"; }
grep -q "$tmp/empty.*warning.*plugin folder holds no" "$tmp/list1.err" ||
    { cat "$tmp/list1.err" >&2; fail "pliant list does not warn about an empty plugin folder"; }

# ---- 2. the template plugin, out of tree ------------------------------------
"$cmake" -S "$src/plugins/template_constraint" -B "$tmp/build" \
    -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_C_FLAGS="-Wall -Wextra -Werror" >"$tmp/configure.log" 2>&1 ||
    { cat "$tmp/configure.log" >&2; fail "configuring the template against the install"; }
"$cmake" --build "$tmp/build" >"$tmp/build.log" 2>&1 ||
    { cat "$tmp/build.log" >&2; fail "building the template against the install"; }
plugin_dir=$tmp/build/plugins
test -f "$plugin_dir/libpliant_template_constraint.so" ||
    fail "no $plugin_dir/libpliant_template_constraint.so"

# ---- 3. the installed pliant runs the scene with that plugin -----------------
export PLIANT_PLUGIN_PATH="$plugin_dir"
"$prefix/bin/pliant" list >"$tmp/list.txt" 2>/dev/null || true
grep -q "^  template_constraint *$plugin_dir/libpliant_template_constraint.so" "$tmp/list.txt" ||
    { cat "$tmp/list.txt" >&2; fail "pliant list does not load the template from $plugin_dir"; }
grep -q "^PointOnPlaneConstraint" "$tmp/list.txt" || fail "PointOnPlaneConstraint is not listed"
"$prefix/bin/pliant" run "$src/scenes/template_constraint.xml" -n 20 --out "$tmp/out" \
    --quiet >"$tmp/run.log" 2>&1 || { cat "$tmp/run.log" >&2; fail "pliant run"; }
grep -q "20 steps" "$tmp/run.log" || { cat "$tmp/run.log" >&2; fail "the run did not take 20 steps"; }

# ---- 4. the template's own test -----------------------------------------------
if [ -x "$tmp/build/test_template_constraint" ]; then
    (cd "$tmp/build" && "$ctest" --output-on-failure >"$tmp/ctest.log" 2>&1) ||
        { cat "$tmp/ctest.log" >&2; fail "the template's test against the install"; }
else
    echo "sdk_test: note: Check not found by pkg-config, the template's test was not built" >&2
fi

# ---- 5. the same plugin with pkg-config ----------------------------------------
if command -v pkg-config >/dev/null 2>&1; then
    mkdir "$tmp/pc"
    flags=$(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs pliant) ||
        fail "pkg-config does not know pliant (PKG_CONFIG_PATH=$prefix/lib/pkgconfig)"
    # shellcheck disable=SC2086
    ${CC:-cc} -std=c11 -Wall -Wextra -Werror -shared -fPIC -fvisibility=hidden \
        "$src/plugins/template_constraint/template_constraint.c" \
        -o "$tmp/pc/libpliant_template_constraint.so" $flags -Wl,--no-undefined \
        >"$tmp/pc.log" 2>&1 || { cat "$tmp/pc.log" >&2; fail "building the plugin with pkg-config"; }
    PLIANT_PLUGIN_PATH="$tmp/pc" "$prefix/bin/pliant" run "$src/scenes/template_constraint.xml" \
        -n 5 --out "$tmp/out_pc" --quiet >"$tmp/run_pc.log" 2>&1 ||
        { cat "$tmp/run_pc.log" >&2; fail "pliant run with the pkg-config plugin"; }
    grep -q "5 steps" "$tmp/run_pc.log" || { cat "$tmp/run_pc.log" >&2; fail "pkg-config run"; }
else
    echo "sdk_test: note: no pkg-config, the pkg-config build was not tried" >&2
fi

# ---- 6. an embedding program -------------------------------------------------
mkdir -p "$tmp/embed"
cat >"$tmp/embed/CMakeLists.txt" <<'EOF'
cmake_minimum_required(VERSION 3.20)
project(embed LANGUAGES C)
find_package(Pliant 0.1 REQUIRED)
add_executable(embed main.c)
target_link_libraries(embed PRIVATE Pliant::pliant)
EOF
cat >"$tmp/embed/main.c" <<'EOF'
#include <stdio.h>
#include "pliant/pliant.h"
/* loads a scene, steps it 5 times, prints the slider's force */
int main(int argc, char **argv)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *sim = pl_sim_load_file(argv[1], NULL, &diag);
    if (!sim) {
        pl_diag_print(&diag, stderr);
        return 2;
    }
    pl_error err;
    char buf[64];
    if (pl_sim_step(sim, 5, &err) || pl_sim_get(sim, "slider.force", buf, sizeof buf, &err))
        return 1;
    printf("t = %g force = %s\n", pl_sim_time(sim), buf);
    pl_sim_free(sim);
    pl_diag_free(&diag);
    return argc > 1 ? 0 : 1;
}
EOF
"$cmake" -S "$tmp/embed" -B "$tmp/embed/build" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_C_FLAGS="-Wall -Wextra -Werror -std=c11" >"$tmp/embed.log" 2>&1 &&
    "$cmake" --build "$tmp/embed/build" >>"$tmp/embed.log" 2>&1 ||
    { cat "$tmp/embed.log" >&2; fail "building a program against Pliant::pliant"; }
"$tmp/embed/build/embed" "$src/scenes/template_constraint.xml" >"$tmp/embed.out" 2>&1 ||
    { cat "$tmp/embed.out" >&2; fail "the embedding program"; }
grep -q "t = 0.05 force =" "$tmp/embed.out" || { cat "$tmp/embed.out" >&2; fail "embed output"; }
echo "sdk_test: ok (install moved, find_package, pkg-config, out-of-tree plugin, PLIANT_PLUGIN_PATH, embedding)"
