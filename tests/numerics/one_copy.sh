#!/bin/sh
# one_copy.sh SOURCE_DIR [CXX] - the numerical kernels exist once.
#
# The SVD, the material laws, the local solves (ADMM-PD, KEEP_NORM) and the
# NCP functions, residuals and projections are written once, in headers
# compiled as C and as CUDA (PL_HD, pliant/hostdevice.h):
#   plugins/hyperelastic: svd.h sym_eigen.h material_law.h local_solve.h keep_norm.h
#   plugins/ncp_contact:  ncp_functions.h ncp_residual.h ncp_project.h
# This test fails when
#   1. a .cu or .cuh file anywhere in the tree, or a .c file of those two
#      plugins, defines (or #defines) a function whose name says it is one
#      of those kernels (a second copy), except the CPU's public pl_* entry
#      points and the CPU-only hyper_* helpers, which call the headers;
#   2. the CUDA sources that run those kernels do not include the headers;
#   3. a shared header is missing, has a kernel without PL_HD, or (when a
#      C++ compiler is given) does not compile as C++, which is what nvcc's
#      host pass makes of it.
# It first checks its own detector on small examples, so that it cannot
# pass by detecting nothing.
set -u
src=${1:?usage: one_copy.sh SOURCE_DIR [CXX]}
cxx=${2:-}
status=0
fail() {
    echo "one_copy: FAIL: $*" >&2
    status=1
}

# Names of kernel functions (lower case, awk ERE).
KERNEL_NAMES='svd|hestenes|jacobi|polar|sort_columns|left_vectors|any_orthogonal|scale_exponent|eigen|sv_eval|sv_pair|piola|dpdf|psi_hat|local_solve|solve_singular|newton_direction|objective|keep_norm|ncp|fischer|minmap|friction|^normal$|^bounded$|^bilateral$|complementarity|row_residual|project_row|project_contact'

# scan FILE...: prints FILE:LINE: NAME for every definition of a kernel
# function.  A definition is a line that starts with type words and then
# the name and "(" (return, else, ... excluded: calls), or a line that
# starts with the name and "(" followed by a parameter type (the return
# type on the line above), or a function-like #define of the name.
scan() {
    awk -v names="$KERNEL_NAMES" '
    function report(name) {
        n = tolower(name)
        sub(/.*::/, "", n)
        # the CPU entry points over the headers (plugin-private: hyper_, ncpc_,
        # ncp_eval_ and the solver functions of ncp.h; SDK: pl_)
        if (n ~ /^(pl_|hyper_|ncpc_|ncp_eval_)/) return
        if (n ~ /^ncp_(cr|line_search|operator_apply|params_default|project|residual_eval|residual_fc3d|scaling|solve_fc3d|solve_opts_default|step|work_create|work_destroy)$/) return
        if (n ~ names) printf "%s:%d: %s\n", FILENAME, FNR, name
    }
    {
        line = $0
        sub(/\/\/.*/, "", line)
        if (line ~ /^[ \t]*(\*|\/\*)/) next
        if (match(line, /^[ \t]*#[ \t]*define[ \t]+[A-Za-z_][A-Za-z_0-9]*\(/)) {
            d = substr(line, RSTART, RLENGTH - 1)
            sub(/^[ \t]*#[ \t]*define[ \t]+/, "", d)
            report(d)
            next
        }
        if (match(line, /^[ \t]*(template[ \t]*<[^>]*>[ \t]*)?([A-Za-z_][A-Za-z_0-9:]*[ \t*&]+)+[A-Za-z_][A-Za-z_0-9:]*[ \t]*(<[^>(]*>)?[ \t]*\(/)) {
            pre = substr(line, RSTART, RLENGTH - 1)
            sub(/^[ \t]*template[ \t]*<[^>]*>/, "", pre)
            sub(/<[^>(]*>[ \t]*$/, "", pre)
            gsub(/[*&]/, " ", pre)
            k = split(pre, w, /[ \t]+/)
            first = w[1] == "" ? w[2] : w[1]
            if (first ~ /^(return|else|if|while|for|switch|case|do|goto|sizeof|new|delete|throw)$/) next
            report(w[k])
            next
        }
        if (match(line, /^[ \t]*[A-Za-z_][A-Za-z_0-9:]*[ \t]*\([ \t]*(const[ \t]+)?(int|double|float|bool|unsigned|long|char|void|size_t|[A-Za-z_]+_t|pl_[A-Za-z_]+)[ \t*&]/)) {
            d = substr(line, RSTART, RLENGTH)
            sub(/^[ \t]*/, "", d)
            sub(/[ \t]*\(.*/, "", d)
            report(d)
        }
    }' "$@"
}

# ---- 0. the detector on examples -----------------------------------------
tmp=$(mktemp -d "${TMPDIR:-/tmp}/one_copy.XXXXXX") || exit 1
trap 'rm -rf "$tmp"' EXIT INT TERM
cat >"$tmp/copy.cuh" <<'EOF'
namespace hcu {
__device__ inline void svd3(const double *F, double *U, double *s, double *V)
template <int D>
__device__ inline int sv_eval_d(int material, double mu, double la, const double *s)
__device__ __forceinline__ double friction_compliance(int fn, double a)
template <int i, int j> __device__ __forceinline__ void jacobi_pair(double *A)
static __host__ __device__ inline void ncp_normal(int fn, double delta)
__device__ inline int
solve_singular_values3(int mat, double mu)
#define NEWTON_DIRECTION(H, r) do_it(H, r)
}
#define PLIANT_NCP_CUDA_KERNELS_CUH
EOF
cat >"$tmp/calls.cu" <<'EOF'
#include "local_solve.h"
// __device__ inline void svd3(const double *F) in a comment
/* static double neohookean_psi(double s) in a comment */
__global__ void k_project(int n, const double *z, double *p)
{
    const int it = hm_local_solve(3, 0, 1.0, 1.0, 2.0, z, p);
    ncp_normal(P.fn, d, l, R.r[j], P.fb_eps,
               &V.phi[j], &V.omega[j], &V.e[j]);
    if (k == PL_ROW_NORMAL) ncp_bounded(d, l, lo, hi, r, &phi, &om, &e);
    else ncp_friction(fn, nt, y, lf, ln, mu, rho, phi, &om, &e);
    return hm_svd3(z, U, s, V);
}
EOF
found=$(scan "$tmp/copy.cuh" | wc -l)
[ "$found" -eq 7 ] || fail "the detector finds $found of the 7 definitions in its example: $(scan "$tmp/copy.cuh")"
[ -z "$(scan "$tmp/calls.cu")" ] || fail "the detector takes calls for definitions: $(scan "$tmp/calls.cu")"

# ---- 1. no second copy ----------------------------------------------------
files=$(find "$src" \( -name '.git' -o -name 'build*' -o -name 'out' \) -prune -o \
    \( -name '*.cu' -o -name '*.cuh' \) -type f -print | sort)
files="$files $(ls "$src"/plugins/hyperelastic/*.c "$src"/plugins/ncp_contact/*.c)"
ncu=$(echo "$files" | tr ' ' '\n' | grep -c '\.cuh\?$')
[ "$ncu" -gt 0 ] || fail "no .cu file found under $src"
copies=$(scan $files)
[ -z "$copies" ] || fail "kernels defined outside the shared headers (include the header instead):
$copies"

# ---- 2. the CUDA sources use the shared headers ---------------------------
uses() { # FILE HEADER...
    f=$src/$1
    shift
    [ -f "$f" ] || { fail "$f is missing"; return; }
    for h in "$@"; do
        grep -q "^#include \"$h\"" "$f" || fail "$f does not include $h"
    done
}
uses plugins/hyperelastic/cuda/hyper_cuda.cu local_solve.h
uses plugins/hyperelastic/cuda/stencil_cuda.cu keep_norm.h
# the NCP phases' device code: one header, compiled by the phase kernels and the fused update
uses plugins/ncp_contact/ncp_cuda_phases.cuh ncp_functions.h ncp_residual.h ncp_project.h
uses plugins/ncp_contact/ncp_cuda_step.cu ncp_cuda_phases.cuh
uses plugins/ncp_contact/ncp_cuda_fused.cu ncp_cuda_phases.cuh

# ---- 3. the shared headers ------------------------------------------------
headers="plugins/hyperelastic/small_matrix.h plugins/hyperelastic/svd.h
plugins/hyperelastic/sym_eigen.h plugins/hyperelastic/material_law.h
plugins/hyperelastic/local_solve.h plugins/hyperelastic/keep_norm.h
plugins/ncp_contact/ncp_functions.h plugins/ncp_contact/ncp_residual.h
plugins/ncp_contact/ncp_project.h"
for h in $headers; do
    f=$src/$h
    [ -f "$f" ] || { fail "$f is missing"; continue; }
    # every function defined at the start of a line is PL_HD
    bad=$(grep -nE '^(static|inline|__device__|__host__|void|int|double|bool)[ a-z_*]*\(' "$f")
    [ -z "$bad" ] || fail "$f: functions without PL_HD:
$bad"
    grep -q '^PL_HD ' "$f" || fail "$f defines no PL_HD function"
    if [ -n "$cxx" ]; then
        "$cxx" -std=c++17 -fsyntax-only -Wall -Wextra -Werror -Wno-unused-parameter -x c++ \
            -I"$src/core/include" -I"$src/plugins/hyperelastic" -I"$src/plugins/ncp_contact" "$f" \
            >"$tmp/cxx.log" 2>&1 || fail "$f does not compile as C++: $(cat "$tmp/cxx.log")"
    fi
done

[ "$status" -eq 0 ] && echo "one_copy: the kernels are defined once, in the shared headers ($ncu CUDA files checked)"
exit "$status"
