#!/usr/bin/env bash
# tests/gpu/run.sh - every GPU check and benchmark of the CUDA backend, in one
# go on the GPU machine; logs and tables go to $OUT (default /tmp/gpu_out).
#   bash tests/gpu/run.sh [BUILD_DIR]        (from the repository root)
#   PARTS="scenes check_small" bash tests/gpu/run.sh build-gpu   (a selection)
# Parts: check (gpu_check, both bars; check_small: the small bar only),
# bench (gpu_bench), cli (the twisting bars through `pliant run`, global step
# on the device through host copies), scenes (gpu_scenes: the whole loop on
# the device, LocalGlobalSolver device="cuda"), sanitize (compute-sanitizer
# memcheck / racecheck on gpu_check, small bar), sanitize_scenes (memcheck on
# gpu_scenes' checks of the small scenes).
# Needs the CUDA build (cmake -DPLIANT_CUDA=ON) and, where SuiteSparse is
# missing, the libraries bundled by /work/shared/tools/gpu-bundle in .gpu/lib
# (or $GPU_LIBS).
set -u
B=${1:-build-gpu}
OUT=${OUT:-/tmp/gpu_out}
PARTS=${PARTS:-check bench cli scenes sanitize}
mkdir -p "$OUT"
export LD_LIBRARY_PATH="$PWD/${GPU_LIBS:-.gpu}/lib:$PWD/$B/lib:/usr/local/cuda/lib64:${LD_LIBRARY_PATH:-}"
export PLIANT_PLUGIN_PATH="$PWD/$B/plugins"
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-$(nproc)}
# scenes without a declared CudaDevice are the CPU side of the comparisons
export PLIANT_DEVICE=${PLIANT_DEVICE:-cpu}
CS=$(command -v compute-sanitizer || echo /usr/local/cuda/bin/compute-sanitizer)
status=0
has() { case " $PARTS " in *" $1 "*) return 0 ;; esac; return 1; }

echo "== device" | tee "$OUT/bench.log"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem \
  --format=csv 2>&1 | tee -a "$OUT/bench.log"

if has check || has check_small; then
  echo "== gpu_check (CPU vs GPU from identical inputs)"
  small=""; has check || small=small
  timeout 300 "$B/bin/gpu_check" "$OUT/check.md" scenes/twisting_bar.xml $small 2>&1 | tee "$OUT/check.log"
  rc=${PIPESTATUS[0]}; [ "$rc" = 0 ] || status=1
  echo "gpu_check exit $rc"
fi

if has bench; then
  echo "== gpu_bench"
  timeout 300 "$B/bin/gpu_bench" "$OUT/bench.md" 100 2>&1 | tee -a "$OUT/bench.log"
  [ "${PIPESTATUS[0]}" = 0 ] || status=1
fi

if has cli; then
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
fi

if has scenes; then
  echo "== gpu_scenes (the whole local-global loop on the device)"
  timeout 400 "$B/bin/gpu_scenes" "$OUT/scenes_check.md" "$OUT/scenes_timing.md" 100 2>&1 \
    | tee "$OUT/gpu_scenes.log"
  rc=${PIPESTATUS[0]}; [ "$rc" = 0 ] || status=1
  echo "gpu_scenes exit $rc"
fi

if has sanitize; then
  echo "== compute-sanitizer memcheck, small bar"
  timeout 240 "$CS" --tool memcheck --leak-check no "$B/bin/gpu_check" /tmp/gpu_sanitize.md \
    scenes/twisting_bar.xml small > "$OUT/sanitize.log" 2>&1
  echo "memcheck exit $?" | tee -a "$OUT/sanitize.log"
  echo "== compute-sanitizer racecheck (shared memory), small bar" | tee -a "$OUT/sanitize.log"
  timeout 240 "$CS" --tool racecheck "$B/bin/gpu_check" /tmp/gpu_sanitize.md \
    scenes/twisting_bar.xml small >> "$OUT/sanitize.log" 2>&1
  echo "racecheck exit $?" | tee -a "$OUT/sanitize.log"
  tail -5 "$OUT/sanitize.log"
fi

if has sanitize_scenes; then
  echo "== compute-sanitizer memcheck, gpu_scenes checks of the small scenes"
  timeout 150 "$CS" --tool memcheck --leak-check no "$B/bin/gpu_scenes" /tmp/gpu_ss.md \
    /tmp/gpu_ss_t.md 0 small > "$OUT/sanitize_scenes.log" 2>&1
  echo "memcheck exit $?" | tee -a "$OUT/sanitize_scenes.log"
  tail -4 "$OUT/sanitize_scenes.log"
fi

echo "== tables"
for f in bench.md scenes_timing.md; do [ -f "$OUT/$f" ] && cat "$OUT/$f"; done
for f in check.md scenes_check.md; do
  [ -f "$OUT/$f" ] && grep -c FAIL "$OUT/$f" | sed "s/^/failed checks in $f: /"
done
exit $status
