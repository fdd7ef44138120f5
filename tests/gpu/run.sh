#!/usr/bin/env bash
# tests/gpu/run.sh - every GPU check and benchmark of the CUDA backend, in one
# go on the GPU machine; logs and tables go to $OUT (default /tmp/gpu_out).
#   sh tests/gpu/run.sh [BUILD_DIR]        (from the repository root)
# Needs the CUDA build (cmake -DPLIANT_CUDA=ON) and, where SuiteSparse is
# missing, the libraries bundled by /work/shared/tools/gpu-bundle in .gpu/lib.
set -u
B=${1:-build-gpu}
OUT=${OUT:-/tmp/gpu_out}
mkdir -p "$OUT"
export LD_LIBRARY_PATH="$PWD/.gpu/lib:$PWD/$B/lib:/usr/local/cuda/lib64:${LD_LIBRARY_PATH:-}"
export PLIANT_PLUGIN_PATH="$PWD/$B/plugins"
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-$(nproc)}
status=0

echo "== device" | tee "$OUT/bench.log"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem \
  --format=csv 2>&1 | tee -a "$OUT/bench.log"

echo "== gpu_check (CPU vs GPU from identical inputs)"
timeout 300 "$B/bin/gpu_check" "$OUT/check.md" scenes/twisting_bar.xml 2>&1 | tee "$OUT/check.log"
rc=${PIPESTATUS[0]}; [ "$rc" = 0 ] || status=1
echo "gpu_check exit $rc"

echo "== gpu_bench"
timeout 300 "$B/bin/gpu_bench" "$OUT/bench.md" 100 2>&1 | tee -a "$OUT/bench.log"
[ "${PIPESTATUS[0]}" = 0 ] || status=1

echo "== scenes: twisting bars, device cpu vs cuda (global step through host copies)"
for scene in twisting_bar twisting_bar_20k; do
  for dev in cpu:float64 cuda:float64 cuda:float32; do
    d=${dev%%:*}; p=${dev##*:}
    echo "-- $scene device=$d precision=$p" >> "$OUT/scenes.log"
    timeout 120 "$B/bin/pliant" run "scenes/$scene.xml" -n 20 --quiet --out /tmp/gpu_scene \
      --set global.device=$d --set global.precision=$p --timings "/tmp/gpu_scene_$scene.$d.$p.json" \
      >> "$OUT/scenes.log" 2>&1 || status=1
    grep -E '"(Local|Global|Frame)"' "/tmp/gpu_scene_$scene.$d.$p.json" >> "$OUT/scenes.log" 2>&1
  done
done

if command -v compute-sanitizer >/dev/null 2>&1 || [ -x /usr/local/cuda/bin/compute-sanitizer ]; then
  echo "== compute-sanitizer memcheck, small bar"
  CS=$(command -v compute-sanitizer || echo /usr/local/cuda/bin/compute-sanitizer)
  timeout 240 "$CS" --tool memcheck --leak-check no "$B/bin/gpu_check" /tmp/gpu_sanitize.md \
    scenes/twisting_bar.xml small > "$OUT/sanitize.log" 2>&1
  echo "memcheck exit $?" | tee -a "$OUT/sanitize.log"
  echo "== compute-sanitizer racecheck (shared memory), small bar" | tee -a "$OUT/sanitize.log"
  timeout 240 "$CS" --tool racecheck "$B/bin/gpu_check" /tmp/gpu_sanitize.md \
    scenes/twisting_bar.xml small >> "$OUT/sanitize.log" 2>&1
  echo "racecheck exit $?" | tee -a "$OUT/sanitize.log"
  tail -5 "$OUT/sanitize.log"
fi
echo "== tables"; cat "$OUT/bench.md"
grep -c FAIL "$OUT/check.md" | sed 's/^/failed checks: /'
exit $status
