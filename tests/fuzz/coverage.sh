#!/bin/sh
# coverage.sh COV_BUILD FUZZ_BUILD [TARGET...] - line coverage of each fuzz
# target's reader: the replay driver of COV_BUILD (clang source-based
# coverage, make fuzz-coverage) runs over the corpus that `make fuzz` grew in
# FUZZ_BUILD/fuzz/corpus/<target> (plus the seeds and regression inputs),
# and llvm-cov counts the lines of the reader's functions.  Writes
# COV_BUILD/fuzz/coverage.txt.
set -u
COV=$1
FUZZ=$2
shift 2
SRC=$(cd "$(dirname "$0")/../.." && pwd)
TARGETS=${*:-scene vtk_legacy vtu gmsh obj stl_ascii stl_binary state_file regression_list checkpoint}
LLVM_COV=$(command -v llvm-cov || command -v llvm-cov-14)
LLVM_PROFDATA=$(command -v llvm-profdata || command -v llvm-profdata-14)
OUT="$COV/fuzz"
REPORT="$OUT/coverage.txt"
mkdir -p "$OUT/prof"
printf '%-16s %8s %8s %7s  %s\n' target lines missed cover reader > "$REPORT"
export OMP_NUM_THREADS=1

# The reader of each target: files, and (after ':') the functions counted
# when a file holds more than that reader (empty: every function).
reader() {
  case $1 in
    scene) echo "core/src/scene_xml.c: core/src/xml_guard.c:" ;;
    vtk_legacy) echo "components/io/vtk_legacy.c:" ;;
    vtu) echo "components/io/vtu.c: components/io/vtu_data.c: core/src/xml_guard.c:" ;;
    gmsh) echo "components/io/gmsh.c: components/io/gmsh4.c: components/io/gmsh_nodes.c:" ;;
    obj) echo "components/io/obj.c:" ;;
    stl_ascii) echo "components/io/stl.c:pl_io_load_stl_ascii,read_facet,expect,weld,hash_point" ;;
    stl_binary) echo "components/io/stl.c:pl_io_load_stl_binary,weld,hash_point" ;;
    state_file) echo "components/export/state_file_read.c:" ;;
    regression_list) echo "components/export/regression_list.c:" ;;
    checkpoint) echo "core/src/model.c:pl_data_load,load_slots,read_slot,size_allowed,pl_slot_check_finite,resize,pl_data_copy,pl_data_create,pl_data_free" ;;
  esac
}

for t in $TARGETS; do
  bin="$OUT/fuzz_replay_$t"
  rm -f "$OUT/prof/$t"-*.profraw
  seeds=""
  if [ "$t" = checkpoint ]; then
    seeds="$OUT/checkpoint_seeds"
    mkdir -p "$seeds"
    export PL_FUZZ_SEED_DIR="$seeds"
  fi
  LLVM_PROFILE_FILE="$OUT/prof/$t-%p.profraw" "$bin" "$FUZZ/fuzz/corpus/$t" \
    "$SRC/tests/fuzz/seeds/$t" "$SRC/tests/fuzz/regressions/$t" $seeds > "$OUT/replay_$t.log" 2>&1
  unset PL_FUZZ_SEED_DIR
  "$LLVM_PROFDATA" merge -sparse "$OUT/prof/$t"-*.profraw -o "$OUT/prof/$t.profdata"
  objects="-object $COV/lib/libpliant.so"
  for p in "$COV"/plugins/*.so; do objects="$objects -object $p"; done
  total=0
  missed=0
  for spec in $(reader "$t"); do
    file=${spec%%:*}
    funcs=${spec#*:}
    # per-function lines of the file: "name regions miss cover lines miss cover ..."
    # shellcheck disable=SC2086
    counts=$("$LLVM_COV" report "$bin" $objects -instr-profile="$OUT/prof/$t.profdata" \
               -show-functions "$SRC/$file" 2>/dev/null |
             awk -v funcs=",$funcs," '
               $1 != "TOTAL" && $1 ~ /^[A-Za-z_][A-Za-z0-9_.:]*$/ && NF >= 7 && $5 ~ /^[0-9]+$/ {
                 name = $1; sub(/^.*:/, "", name)
                 if (funcs == ",," || index(funcs, "," name ",")) { l += $5; m += $6 }
               }
               END { printf "%d %d\n", l, m }')
    total=$((total + ${counts% *}))
    missed=$((missed + ${counts#* }))
  done
  cover=$(awk -v l="$total" -v m="$missed" 'BEGIN { printf "%.1f%%", l ? 100 * (l - m) / l : 0 }')
  printf '%-16s %8d %8d %7s  %s\n' "$t" "$total" "$missed" "$cover" "$(reader "$t")" |
    tee -a "$REPORT"
done
