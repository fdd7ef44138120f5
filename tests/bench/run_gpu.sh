#!/usr/bin/env bash
# tests/bench/run_gpu.sh - the GPU tables of docs/benchmarks.md in one go on
# the GPU machine (LocalGlobalSolver device="cuda": the whole local-global
# loop, contact included, on the device); logs and tables go to $OUT
# (default /tmp/gpu_out).
#   bash tests/bench/run_gpu.sh [BUILD_DIR]          (from the repository root)
#   PARTS="check table" FRAMES=30 bash tests/bench/run_gpu.sh .gpu3
# BUILD_DIR holds bin/ (pliant, gpu_scenes, gpu_table, stick_slip_sweep, test_gripper) and
# plugins/ of a CUDA build; the bundled libraries (gpu-bundle) are taken from
# $GPU_LIBS/lib (default BUILD_DIR/lib).  Parts:
#   ctest     `ctest -L gpu` in BUILD_DIR: gpu_check's small bar, gpu_scenes'
#             checks of the small scenes and gpu_graph (the loop's CUDA graph
#             kept across 100 constrained steps; each says "skipped: no GPU"
#             without one)
#   check     gpu_scenes: CPU vs GPU one frame from identical states, every scene
#             with a device path (bars, cloth, cloth with bending/targets/forces,
#             contact scenes), float64 within 1e-9, float32 S within 1e-4
#   table     gpu_table: the paper's Table 3 columns for every scene that runs on
#             the device, with the paper's RTX 4090 figures, and float32 vs float64
#   sweep     stick_slip_sweep on the CPU and on the GPU (same thresholds?)
#   grasp     tests/gripper's grasp criteria on both raptor scenes (small and
#             the paper-size full variant) with the loop on the device
#             (GRASP_SCENES="grabbing_raptor_10k ..." for others, in parallel)
#   delassus  gpu_table of the contact scenes with W explicit (built on the
#             device) and matrix-free, forced (DELASSUS_SCENES to choose)
#   cpubench  the CPU benchmark of the collision scenes on this host's cores
#             (bench_contact-like frame tables through `pliant run --timings`)
#   medium    tests/collision's scene checks on medium sizes, in parallel
#             (MEDIUM_SCENES="scene:case ...", CPU; needs the source tree at the
#             path the test was built with)
#   memcheck  compute-sanitizer memcheck on the checks of resting_box and cloth_terms
set -u
B=${1:-build-gpu}
OUT=${OUT:-/tmp/gpu_out}
FRAMES=${FRAMES:-30}
PARTS=${PARTS:-ctest check table sweep grasp memcheck}
mkdir -p "$OUT"
export LD_LIBRARY_PATH="$PWD/${GPU_LIBS:-$B}/lib:$PWD/$B/lib:/usr/local/cuda/lib64:${LD_LIBRARY_PATH:-}"
export PLIANT_PLUGIN_PATH="$PWD/$B/plugins"
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-$(nproc)}
# scenes without a declared CudaDevice are the CPU side of every comparison
# (the loader would otherwise add one: sim.h, device policy)
export PLIANT_DEVICE=${PLIANT_DEVICE:-cpu}
CS=$(command -v compute-sanitizer || echo /usr/local/cuda/bin/compute-sanitizer)
SWEEP=$B/bin/stick_slip_sweep
[ -x "$SWEEP" ] || SWEEP=$B/bench/stick_slip_sweep
status=0
has() { case " $PARTS " in *" $1 "*) return 0 ;; esac; return 1; }
t0=$(date +%s)

echo "== device" | tee "$OUT/run_gpu.log"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>&1 | tee -a "$OUT/run_gpu.log"

if has ctest; then
  echo "== ctest -L gpu"
  CTEST=$(command -v ctest || echo ctest)
  timeout ${T_CTEST:-1800} "$CTEST" --test-dir "$B" -L gpu --output-on-failure > "$OUT/ctest_gpu.log" 2>&1
  rc=$?; [ "$rc" = 0 ] || status=1
  grep -E "tests passed|Skipped|Failed|skipped: no GPU" "$OUT/ctest_gpu.log"
  echo "ctest -L gpu exit $rc ($(( $(date +%s) - t0 )) s)"
fi

if has check; then
  echo "== gpu_scenes checks (CPU vs GPU from identical states)"
  timeout ${T_CHECK:-400} "$B/bin/gpu_scenes" "$OUT/scenes_check.md" /dev/null 0 2>&1 | grep -v "^pliant: info" \
    > "$OUT/gpu_scenes.log"
  rc=${PIPESTATUS[0]}; [ "$rc" = 0 ] || status=1
  grep -E "FAIL|failed" "$OUT/gpu_scenes.log" | tail -20
  echo "gpu_scenes exit $rc ($(( $(date +%s) - t0 )) s)"
fi

if has table; then
  echo "== gpu_table ($FRAMES frames a scene)"
  timeout ${T_TABLE:-260} "$B/bin/gpu_table" "$OUT/table.md" "$OUT/precision.md" "$FRAMES" \
    > "$OUT/gpu_table.log" 2>&1
  rc=$?; [ "$rc" = 0 ] || status=1
  tail -3 "$OUT/gpu_table.log"
  echo "gpu_table exit $rc ($(( $(date +%s) - t0 )) s)"
fi

if has delassus; then
  echo "== delassus: W explicit on the device against matrix-free ($FRAMES frames a scene)"
  DS=${DELASSUS_SCENES:-scenes/cloth_on_knives_small.xml scenes/squeezing_ball_small.xml scenes/cloth_on_knives.xml scenes/squeezing_ball.xml scenes/gingerbread.xml scenes/sharp_corner.xml}
  for mode in explicit matrix-free; do
    GPU_TABLE_SET="contact.delassus=$mode" timeout ${T_DELASSUS:-150} "$B/bin/gpu_table" \
      "$OUT/delassus_$mode.md" /dev/null "$FRAMES" $DS > "$OUT/delassus_$mode.log" 2>&1 || status=1
    echo "-- delassus=$mode"; cat "$OUT/delassus_$mode.md"
  done
  echo "delassus ($(( $(date +%s) - t0 )) s)"
fi

if has cpubench; then
  echo "== cpubench: bench_contact on ${CPU_THREADS:-$(nproc)} CPU cores (PLIANT_DEVICE=cpu)"
  BC=$B/bin/bench_contact
  [ -x "$BC" ] || BC=$B/bench/bench_contact
  export OMP_NUM_THREADS=${CPU_THREADS:-$(nproc)}
  { timeout ${T_CPUBENCH:-200} "$BC" --steps 60 scenes/cloth_on_knives_small.xml scenes/cloth_on_knives.xml \
      scenes/sharp_corner_small.xml scenes/sharp_corner.xml scenes/squeezing_ball_small.xml \
      scenes/squeezing_ball.xml scenes/gingerbread_small.xml scenes/gingerbread.xml
    timeout ${T_CPUBENCH:-200} "$BC" --steps 120 scenes/pulling_through_gap_small.xml scenes/pulling_through_gap.xml
  } > "$OUT/cpubench.md" 2> "$OUT/cpubench.log" || status=1
  cat "$OUT/cpubench.md"
  echo "cpubench ($(( $(date +%s) - t0 )) s)"
fi

if has medium; then
  echo "== medium: tests/collision's scene checks on the medium sizes (CPU, $(nproc) cores)"
  TC=$B/bin/test_collision_pipeline_scenes
  for sc in ${MEDIUM_SCENES:-squeezing_ball:ball sharp_corner:corner cloth_on_knives:knives}; do
    OMP_NUM_THREADS=$(( $(nproc) / 3 )) COLLISION_SCENE="${sc%%:*}.xml" CK_RUN_CASE="${sc##*:}" CK_DEFAULT_TIMEOUT=0 \
      timeout ${T_MEDIUM:-300} "$TC" > "$OUT/medium_${sc%%:*}.log" 2>&1 &
  done
  wait
  for sc in ${MEDIUM_SCENES:-squeezing_ball:ball sharp_corner:corner cloth_on_knives:knives}; do
    echo "-- ${sc%%:*}"; grep -v "^pliant: info" "$OUT/medium_${sc%%:*}.log" | tail -6
  done
  echo "medium ($(( $(date +%s) - t0 )) s)"
fi

if has sweep; then
  echo "== stick-slip threshold, CPU and GPU"
  dev=/tmp/stick_slip_cuda.xml
  sed '0,/<Node name="root"[^>]*>/s//&<RequiredPlugin name="cuda"\/><CudaDevice name="gpu"\/>/' \
    scenes/stick_slip.xml > "$dev"
  { echo "CPU:"; timeout ${T_SWEEP:-50} "$SWEEP" --markdown; echo; echo "GPU (solver.device=cuda):";
    timeout ${T_SWEEP:-50} "$SWEEP" --markdown --scene "$dev" --set solver.device=cuda \
      --set global.device=cuda; } > "$OUT/sweep.md" 2>&1 || status=1
  cat "$OUT/sweep.md"
  echo "sweep ($(( $(date +%s) - t0 )) s)"
fi

if has grasp; then
  echo "== grasp: the gripper scenes with the whole loop on the device (tests/gripper criteria)"
  GRIP=$B/bin/test_gripper
  [ -x "$GRIP" ] || GRIP=$B/tests/test_gripper
  for v in ${GRASP_SCENES:-grabbing_raptor_small grabbing_raptor}; do
    # next to the scene (its meshes are relative to it); exports renamed
    sed -e '0,/<Node name="root"[^>]*>/s//&<RequiredPlugin name="cuda"\/><CudaDevice name="gpu"\/>/' \
        -e 's/<LocalGlobalSolver name="solver"/& device="cuda"/' \
        -e 's/<SparseInverseSolver name="global"/& device="cuda" precision="float64"/' \
        -e 's/filename="grabbing_raptor/filename="gpu_grabbing_raptor/' \
        "scenes/$v.xml" > "scenes/.gpu_$v.xml"
    # the scenes run side by side: idle OpenMP threads must sleep, not spin on shared cores
    OMP_WAIT_POLICY=PASSIVE GRASP_SCENE="scenes/.gpu_$v.xml" CK_RUN_CASE=grasp CK_DEFAULT_TIMEOUT=0 \
      timeout ${T_GRASP:-400} "$GRIP" > "$OUT/grasp_$v.log" 2>&1 &
  done
  wait
  for v in ${GRASP_SCENES:-grabbing_raptor_small grabbing_raptor}; do
    rm -f "scenes/.gpu_$v.xml"
    echo "-- $v"; grep -E "^grasp: height|Checks|F:" "$OUT/grasp_$v.log" || status=1
    grep -q "100%: Checks" "$OUT/grasp_$v.log" || status=1
  done
  echo "grasp ($(( $(date +%s) - t0 )) s)"
fi

if has memcheck; then
  echo "== compute-sanitizer memcheck (resting_box, cloth_terms checks)"
  for s in scenes/resting_box.xml tests/gpu/cloth_terms.xml; do
    timeout 150 "$CS" --tool memcheck --leak-check no "$B/bin/gpu_scenes" /tmp/gpu_mc.md /dev/null 0 \
      "$s" 2>&1 | grep -v "^pliant: info" | tail -4 >> "$OUT/memcheck.log"
  done
  cat "$OUT/memcheck.log"
fi

echo "== tables"
for f in table.md precision.md; do [ -f "$OUT/$f" ] && cat "$OUT/$f"; done
[ -f "$OUT/scenes_check.md" ] && grep -c FAIL "$OUT/scenes_check.md" | sed "s/^/failed checks: /"
echo "run_gpu.sh: $(( $(date +%s) - t0 )) s, status $status"
exit $status
