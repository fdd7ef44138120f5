#!/bin/sh
# ptxas_usage.sh [SOURCE_DIR] [NVCC] - registers, stack and spills of the
# kernels that run the shared numerical kernels (local step, stencil rows,
# contact-solver phases), compiled for sm_90 with the flags of the default
# build (RelWithDebInfo).  Not a test: a table to compare two trees, e.g.
#   sh tests/numerics/ptxas_usage.sh /path/to/main > before.txt
#   sh tests/numerics/ptxas_usage.sh . > after.txt
# Needs only nvcc (no GPU).
set -eu
src=${1:-.}
nvcc=${2:-/usr/local/cuda/bin/nvcc}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/ptxas_usage.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM
flags="-O2 -g -DNDEBUG --generate-code=arch=compute_90,code=[compute_90,sm_90] -std=c++17
  -Xcompiler=-fPIC -D_GNU_SOURCE -DPLIANT_HAVE_CUDA=1 -Xptxas -v -I$src/core/include
  -I$src/components -I$src/plugins/hyperelastic -I$src/plugins/hyperelastic/cuda
  -I$src/plugins/ncp_contact"
echo "| kernel | registers | stack frame [bytes] | spill stores / loads [bytes] |"
echo "|---|--:|--:|--:|"
for f in plugins/hyperelastic/cuda/hyper_cuda.cu plugins/hyperelastic/cuda/stencil_cuda.cu \
    plugins/ncp_contact/ncp_cuda_step.cu; do
    # shellcheck disable=SC2086
    "$nvcc" $flags -c "$src/$f" -o "$tmp/k.o" >"$tmp/log" 2>&1 || { cat "$tmp/log" >&2; exit 1; }
    awk -v file="$(basename "$f")" '
    /Compiling entry function/ {
        k = $0
        sub(/.*function .*_cu_[0-9a-f]*[0-9]*/, "", k)
        sub(/'"'"' for .*/, "", k)
        sub(/E.*/, "", k)
        sub(/ILi.*/, "", k)
        if (match($0, /k_project[^E]*E/)) k = k (index($0, "ILi4ELi3") ? "<4,3> (tetrahedra)" : index($0, "ILi3ELi2") ? "<3,2> (membranes)" : "")
    }
    /stack frame/ { stack = $1; spills = $5 " / " $9 }
    /Used [0-9]+ registers/ { match($0, /Used [0-9]+/); printf "| %s %s | %s | %s | %s |\n", file, k, substr($0, RSTART + 5, RLENGTH - 5), stack, spills }
    ' "$tmp/log"
done
