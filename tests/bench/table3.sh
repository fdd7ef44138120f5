#!/usr/bin/env bash
# tests/bench/table3.sh - the paper's Table 3 at every size (issue 16 item 7):
# every row of the paper (twisting bar, cloth extension, cloth on knives, sharp
# corner, squeezing ball, pulling through gap, gingerbread man, grabbing raptor,
# at the paper's sizes) run with `pliant run SCENE -n STEPS --timings F.json`,
# on the GPU (--device auto) and on the CPU (--device cpu -j THREADS), then
# the tables (tests/bench/table3.py table).  Made for the GPU machine (bash and
# python3 only); from the repository root:
#   bash tests/bench/table3.sh BUILD_DIR half1      # GPU runs + first CPU half (~8 min)
#   bash tests/bench/table3.sh BUILD_DIR half2 table  # second CPU half (~8 min), tables
# PARTS (any order, several allowed): gpu, cpu1, cpu2 (the runs), half1 (= gpu cpu1),
#   half2 (= cpu2), all (every run), cpu2t (the 2-thread CPU table: the smaller
#   sizes, each run pinned to 2 cores, PAIRS at once), table (the tables from what RES holds),
#   plan (the runs and their estimated times), clean (empties RES: results of
#   earlier calls stay there and enter the tables until then).
# Environment (optional):
#   RES        results folder (default out/table3: an ignored folder outside the carried
#              build, kept between calls on a warm machine); each file is also copied to
#              $OUT/table3 as soon as written when OUT is set (a call cut short keeps its runs)
#   FRAMES     frames of 0.01 s per scene (default 150); RAPTOR_FRAMES for the
#              raptors (default 100: 400 steps of 2.5 ms)
#   THREADS    CPU threads (default: this host's cores)
#   PAIRS      runs of part cpu2t at once, each on its own 2 cores (default: cores / 2 - 1)
#   SCENES     comma-separated filters of the scene names (e.g. "_small,knives": tests)
#   LIMIT_S    seconds this call may take (default 560): runs that would pass it
#              are skipped and listed ("table" shows them as not run)
#   GPU_LIBS   folder whose lib/ holds the CUDA bundle (default BUILD_DIR)
#   COMMIT     the commit to name (default: git rev-parse, where .git exists)
#   DOC        file whose generated section "table" rewrites (default docs/benchmarks.md;
#              DOC=none: only RES/table3.md)
# Every run: `--set solver.computeResidual=off` (the paper computes no force
# residual; it would cost a gradient per step on the CPU), exporters once at the
# end (`--export-every` of the whole run), OMP_WAIT_POLICY=PASSIVE.  The scenes
# keep their own settings: 5 local-global and 10 CR iterations, h = 0.01 s, no
# tolerance (all iterations run), except the raptors (h = 0.0025 s, 10 iterations:
# the grasp slips at larger steps, tests/gripper/README.md), which are run a
# second time with the paper's settings (rows NAME@paper: table3.py VARIANTS).
set -u
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
cd "$ROOT"
B=${1:?usage: table3.sh BUILD_DIR PART...}
shift
[ $# -gt 0 ] || set -- plan
case "$B" in /*) ;; *) B="$ROOT/$B" ;; esac
RES=${RES:-$ROOT/out/table3}
PY="python3 $ROOT/tests/bench/table3.py"
LIMIT_S=${LIMIT_S:-560}
NCPU=$(getconf _NPROCESSORS_ONLN 2>/dev/null || nproc)
THREADS=${THREADS:-$NCPU}
PAIRS=${PAIRS:-$(( NCPU / 2 > 1 ? NCPU / 2 - 1 : 1 ))}
DOC=${DOC:-$ROOT/docs/benchmarks.md}
export LD_LIBRARY_PATH="${GPU_LIBS:-$B}/lib:$B/lib:/usr/local/cuda/lib64:${LD_LIBRARY_PATH:-}"
export PLIANT_PLUGIN_PATH="$B/plugins"
export OMP_WAIT_POLICY=PASSIVE
unset PLIANT_DEVICE
P=$B/bin/pliant
mkdir -p "$RES/out"
t0=$(date +%s)
status=0
save() { # copies files of RES to $OUT/table3 (the device machine's returned folder)
    [ -n "${OUT:-}" ] && [ -d "$OUT" ] || return 0
    mkdir -p "$OUT/table3" && for f in "$@"; do [ -f "$f" ] && cp "$f" "$OUT/table3/"; done
    return 0
}

meta() { # the run's context, once per call
    date -u '+%Y-%m-%d %H:%M UTC' > "$RES/meta_date.txt"
    echo "${COMMIT:-$(git rev-parse --short HEAD 2>/dev/null || echo "?")}" > "$RES/meta_commit.txt"
    gpu=$(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1)
    [ -n "$gpu" ] && echo "$gpu (driver)" > "$RES/meta_gpu.txt"
    echo "$(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1), $NCPU cores, -j $THREADS" \
        > "$RES/meta_cpu.txt"
    echo "FRAMES=${FRAMES:-150} RAPTOR_FRAMES=${RAPTOR_FRAMES:-100}, --set solver.computeResidual=off, first frame left out" \
        > "$RES/meta_settings.txt"
    save "$RES"/meta_*.txt
}

run_part() { # the runs of part $1
    $PY jobs "$1" "${SCENES:-}" > "$RES/jobs_$1.txt" || return 1
    while read -r dev scene steps tmo file sets; do
        left=$(( LIMIT_S - ($(date +%s) - t0) ))
        if [ "$left" -lt $(( (tmo - 60) / 3 + 5 )) ]; then
            echo "skipped (time limit): $dev $scene" | tee -a "$RES/skipped.txt"
            status=1
            continue
        fi
        [ "$tmo" -gt "$left" ] && tmo=$left
        name=${dev}_${scene%.xml}
        if [ "$dev" = cpu2t ]; then
            : # below
        elif [ "$dev" = gpu ]; then
            args=(--device auto)
            echo "${P#"$ROOT"/} run scenes/SCENE -n STEPS --device auto --timings F.json --set solver.computeResidual=off" > "$RES/meta_command_gpu.txt"
        else
            args=(--device cpu -j "$THREADS")
            echo "${P#"$ROOT"/} run scenes/SCENE -n STEPS --device cpu -j $THREADS --timings F.json --set solver.computeResidual=off" > "$RES/meta_command_cpu.txt"
        fi
        if [ "$dev" = cpu2t ]; then # 2 threads pinned to a free pair of cores, PAIRS at once
            args=(--device cpu -j 2)
            echo "taskset -c 2k,2k+1 ${P#"$ROOT"/} run scenes/SCENE -n STEPS --device cpu -j 2 --timings F.json --set solver.computeResidual=off ($PAIRS runs at once)" > "$RES/meta_command_cpu2t.txt"
            while [ "$(jobs -rp | wc -l)" -ge "$PAIRS" ]; do wait -n; done
            slot=$(free_slot)
            touch "$RES/slot$slot"
            ( one_run taskset -c $((2 * slot)),$((2 * slot + 1)) < /dev/null; rm -f "$RES/slot$slot" ) &
            sleep 1
            continue
        fi
        one_run
    done < "$RES/jobs_$1.txt"
    wait
    [ -f "$RES/failed" ] && status=1
    rm -rf "$RES/out" "$RES"/slot* "$RES/failed"; mkdir -p "$RES/out"
}

one_run() { # one run of the loop's job ($dev $scene $steps $tmo $name $file $sets args), prefixed by "$@"
    local s0 rc ovr=()
    s0=$(date +%s)
    for v in $sets; do ovr+=(--set "$v"); done # a row's own overrides (table3.py VARIANTS)
    timeout "$tmo" "$@" "$P" run "scenes/$file" -n "$steps" "${args[@]}" "${ovr[@]}" --timings "$RES/$name.json" \
        --set solver.computeResidual=off --export-every "$steps" -o "$RES/out/$name" --progress 0 \
        > "$RES/$name.log" 2>&1
    rc=$?
    [ "$rc" = 0 ] || { touch "$RES/failed"; status=1; rm -f "$RES/$name.json"; }
    echo "$dev $scene: $steps steps, exit $rc, $(( $(date +%s) - s0 )) s [$(( $(date +%s) - t0 )) s]"
    save "$RES/$name.json" "$RES/$name.log" "$RES"/meta_command_*.txt
}

free_slot() { # the first pair of cores no run holds
    local k=0
    while [ -f "$RES/slot$k" ]; do k=$((k + 1)); done
    echo $k
}

for part in "$@"; do
    case "$part" in
        plan) FRAMES=${FRAMES:-150} $PY plan ;;
        clean) rm -rf "$RES"; mkdir -p "$RES/out" ;;
        gpu|cpu1|cpu2|half1|half2|all|cpu|cpu2t)
            [ -x "$P" ] || { echo "table3.sh: no $P (build first)" >&2; exit 2; }
            if [ "$part" = cpu2t ]; then # the other tables' context stays as it is
                echo "$(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1), $NCPU cores; each run on 2 of them, $PAIRS runs at once; $(date -u '+%Y-%m-%d %H:%M UTC'), ${COMMIT:-$(git rev-parse --short HEAD 2>/dev/null || echo "?")}" > "$RES/meta_cpu2t.txt"
                save "$RES/meta_cpu2t.txt"
            else meta; fi
            echo "== $part (results in $RES)"
            run_part "$part" ;;
        table)
            echo "== tables"
            if [ "$DOC" = none ]; then $PY table "$RES" --out "$RES/table3.md"
            else $PY table "$RES" --out "$RES/table3.md" --doc "$DOC"; fi || status=1
            save "$RES/table3.md" "$DOC"
            cat "$RES/table3.md" ;;
        *) echo "table3.sh: unknown part '$part'" >&2; exit 2 ;;
    esac
done
save "$RES/skipped.txt"
echo "table3.sh: $(( $(date +%s) - t0 )) s, status $status"
exit $status
