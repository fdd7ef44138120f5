#!/bin/sh
# run_fuzz.sh BUILD SECONDS [TARGET...] - runs each libFuzzer target of
# BUILD/fuzz (make fuzz) for SECONDS, one after the other, on a corpus that
# starts from tests/fuzz/seeds/<target> and the project's scenes and meshes
# and grows in BUILD/fuzz/corpus/<target>.  Crashes, timeouts and
# out-of-memory inputs land in BUILD/fuzz/artifacts/<target>/; once fixed,
# copy them to tests/fuzz/regressions/<target>/ (make test replays them).
# Writes BUILD/fuzz/summary.txt (target, executions, seconds, result) and
# exits non-zero when a target found something.
set -u
BUILD=$1
SECONDS_EACH=$2
shift 2
SRC=$(cd "$(dirname "$0")/../.." && pwd)
TARGETS=${*:-scene vtk_legacy vtu gmsh obj stl_ascii stl_binary state_file regression_list checkpoint}
OUT="$BUILD/fuzz"
SUMMARY="$OUT/summary.txt"
printf '%-16s %12s %8s  %s\n' target executions seconds result > "$SUMMARY"
# one thread: the machine is shared, and OpenMP spin-up would dominate tiny steps
export OMP_NUM_THREADS=1 OMP_WAIT_POLICY=PASSIVE
export ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
found=0

seed() { # seed TARGET FILES...: copies existing files into the corpus
  t=$1
  shift
  for f in "$@"; do [ -f "$f" ] && cp "$f" "$OUT/corpus/$t/"; done
}

for t in $TARGETS; do
  bin="$OUT/fuzz_$t"
  [ -x "$bin" ] || { echo "run_fuzz: no $bin (make fuzz-build)"; exit 2; }
  mkdir -p "$OUT/corpus/$t" "$OUT/artifacts/$t"
  seed "$t" "$SRC/tests/fuzz/seeds/$t"/* "$SRC/tests/fuzz/regressions/$t"/*
  max_len=65536
  case $t in
    scene) seed scene "$SRC"/scenes/*_small.xml "$SRC"/scenes/template_constraint.xml \
             "$SRC"/scenes/ball_on_plane.xml ;;
    vtk_legacy) seed vtk_legacy "$SRC"/scenes/meshes/*.vtk ;;
    vtu) seed vtu "$SRC"/scenes/meshes/*.vtu "$SRC"/tests/loaders/data/*.vtk ;;
    gmsh) seed gmsh "$SRC"/scenes/meshes/*.msh ;;
    obj) seed obj "$SRC"/scenes/meshes/*.obj ;;
    stl_ascii | stl_binary) seed "$t" "$SRC"/scenes/meshes/*.stl ;;
    state_file) seed state_file "$SRC"/tests/export/data/*.gz \
                  "$SRC"/tests/regression/references/*.gz ;;
    regression_list) seed regression_list "$SRC"/tests/regression/list.txt ;;
    checkpoint) PL_FUZZ_SEED_DIR="$OUT/corpus/checkpoint" "$bin" -runs=0 "$OUT/corpus/checkpoint" \
                  > /dev/null 2>&1 ;;
  esac
  log="$OUT/fuzz_$t.log"
  echo "run_fuzz: $t for $SECONDS_EACH s ($(ls "$OUT/corpus/$t" | wc -l) inputs to start)"
  start=$(date +%s)
  "$bin" "$OUT/corpus/$t" -max_total_time="$SECONDS_EACH" -timeout=20 -rss_limit_mb=2048 \
    -max_len=$max_len -artifact_prefix="$OUT/artifacts/$t/" -print_final_stats=1 \
    > "$log" 2>&1
  rc=$?
  secs=$(( $(date +%s) - start ))
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  result=ok
  slow=$(ls "$OUT/artifacts/$t" | grep -c '^slow-unit-')
  [ "$slow" -gt 0 ] && result="ok ($slow slow inputs, over 10 s each)"
  # crashes, timeouts, out-of-memory, leaks (slow units are only reported)
  bad=$(ls "$OUT/artifacts/$t" | grep -v '^slow-unit-' | tr '\n' ' ')
  if [ $rc -ne 0 ] || [ -n "$bad" ]; then
    result="FOUND: $bad(see $log)"
    found=1
  fi
  printf '%-16s %12s %8s  %s\n' "$t" "${execs:-?}" "$secs" "$result" | tee -a "$SUMMARY"
done
cat "$SUMMARY"
exit $found
