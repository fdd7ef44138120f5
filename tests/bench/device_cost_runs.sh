#!/usr/bin/env bash
# tests/bench/device_cost_runs.sh - the calibration runs of device=auto's cost
# model (core/src/device_cost.c): every scene of scenes/ on the CPU and on the
# GPU (--device gpu-always: the GPU whatever the model says), step medians and
# the sizes the model reads ("cost: ..." statistics) in one timings file per
# run, then the fit (tests/bench/device_cost_fit.py) on them.  On the GPU
# machine, from the repository root:
#   bash tests/bench/device_cost_runs.sh [BUILD_DIR]      (default build-gpu)
#   SCENES="hanging_bar sliding_box" THREADS=16 bash tests/bench/device_cost_runs.sh
# Writes $OUT/device_cost/<scene>_cpu.json, <scene>_gpu-always.json, their logs,
# fit.txt (the table) and device_cost_fitted.c (device_cost.c with the fitted
# constants: copy it over core/src/device_cost.c when the table is right).
# Steps per scene: 40 (pulling_through_gap* 100, grabbing_raptor* 60); LIMIT
# seconds in all (default 540): the scenes not reached are said.
set -u
B=${1:-build-gpu}
O=${OUT:-/tmp/out}/device_cost
mkdir -p "$O"
THREADS=${THREADS:-$(nproc)}
LIMIT=${LIMIT:-540}
export OMP_WAIT_POLICY=PASSIVE
# the bundled libraries as in run_gpu.sh: $GPU_LIBS/lib (default BUILD_DIR/lib)
export LD_LIBRARY_PATH="$PWD/${GPU_LIBS:-$B}/lib:$PWD/$B/lib:/usr/local/cuda/lib64:${LD_LIBRARY_PATH:-}"
export PLIANT_PLUGIN_PATH=${PLIANT_PLUGIN_PATH:-$PWD/$B/plugins}
t0=$(date +%s)
{ nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null; echo "$THREADS threads";
  lscpu | grep 'Model name'; git log -1 --format='%h %cd' 2>/dev/null; } > "$O/machine.txt"
scenes=${SCENES:-$(ls scenes/*.xml | xargs -n1 basename | sed 's/\.xml$//' | grep -v '^template_')}
for s in $scenes; do
  n=40
  case $s in pulling*) n=100 ;; grabbing_raptor*) n=60 ;; esac
  for dev in cpu gpu-always; do
    if [ $(($(date +%s) - t0)) -gt "$LIMIT" ]; then echo "time up before $s $dev"; break 2; fi
    timeout 60 "$B/bin/pliant" run "scenes/$s.xml" -n $n -q -o "/tmp/device_cost_out/$s" \
      --device $dev -j "$THREADS" --timings "$O/${s}_$dev.json" > "$O/${s}_$dev.log" 2>&1
    echo "$s $dev exit $? $(tail -1 "$O/${s}_$dev.log" | cut -c1-150)"
  done
done
cp core/src/device_cost.c "$O/device_cost_fitted.c"
python3 tests/bench/device_cost_fit.py "$O" --threads "$THREADS" --write "$O/device_cost_fitted.c" \
  | tee "$O/fit.txt"
echo "[$(($(date +%s) - t0)) s] done: $O"
