#!/bin/sh
# tests/bench/run.sh BUILD_DIR - `make bench`: builds the benchmark programs,
# runs them, prints the tables and rewrites the generated section of
# docs/benchmarks.md (text outside its markers is kept), with the plot
# docs/convergence.png.  Not part of `make test`.
#
# Environment (all optional):
#   BENCH_FRAMES       frames per scene (default 100)
#   BENCH_SCENES       filters or scene files for bench_scenes (default: all its scenes)
#   BENCH_MODES        global-solver modes (default sparse,direct)
#   BENCH_CONV_SCENE   scene of the convergence study (default scenes/twisting_bar.xml)
#   BENCH_CONV_FRAMES  run-up frames before the studied step (default 100)
#   BENCH_CONV_JACOBI  iterations of the JacobiSolver baseline in that study (default 1000; 0: none)
#   BENCH_SKIP         parts to skip (and their tables in the doc): scenes, convergence, contact,
#                      pressure (Lame's thick sphere at three mesh levels, finest within 2%)
#   BENCH_CONTACT_STEPS  steps per contact scene (default 60; the pulling scenes twice that)
#   BENCH_W_STEPS      steps of the explicit vs matrix-free W runs of the sharp corner (default 25)
#   OMP_NUM_THREADS    threads of the local step and S^T S b (default 1, see below)
#   JOBS               build jobs (default: nproc)
#   PLIANT_DEVICE      cpu (default here), auto (a GPU where the device=auto cost model predicts it
#                      faster) or gpu-always (a GPU whenever one is usable)
#   BENCH_PARALLEL     1: run the parts (contact, W comparison, pressure, scenes, convergence)
#                      at the same time, one thread each: for an idle machine with cores to
#                      spare (e.g. the GPU machine's 16-core host, whose commands are limited
#                      to 10 minutes); the whole bench then takes as long as its longest part
#   BENCH_COMMIT       the commit to name in the doc (default: git's; for a tree without .git)
#   BENCH_NO_BUILD     1: do not build; BUILD_DIR already holds the programs (a build carried
#                      to another machine)
set -eu

BUILD=${1:-build}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
cd "$ROOT"
case "$BUILD" in /*) ;; *) BUILD="$ROOT/$BUILD" ;; esac
[ -f "$BUILD/CMakeCache.txt" ] || { echo "run.sh: $BUILD is not a configured build (run make build)" >&2; exit 2; }

FRAMES=${BENCH_FRAMES:-100}
MODES=${BENCH_MODES:-sparse,direct}
SCENES=${BENCH_SCENES:-}
CONV_SCENE=${BENCH_CONV_SCENE:-scenes/twisting_bar.xml}
CONV_FRAMES=${BENCH_CONV_FRAMES:-100}
CONV_JACOBI=${BENCH_CONV_JACOBI:-1000}
SKIP=${BENCH_SKIP:-}
# One thread by default: on a shared machine whose cores are all busy, an
# OpenMP team waits at every barrier for a descheduled thread, and the
# parallel phases measured 10-100x slower with 2 threads than with 1.
# (GNU nproc obeys OMP_NUM_THREADS: count the processors before setting it)
NCPU=$(getconf _NPROCESSORS_ONLN 2>/dev/null || nproc 2>/dev/null || echo 2)
JOBS=${JOBS:-$NCPU}
OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
export OMP_NUM_THREADS
# the CPU benchmark: no implicit CudaDevice where a GPU is present
export PLIANT_DEVICE=${PLIANT_DEVICE:-cpu}
OUT="$BUILD/bench_out"
DOC="$ROOT/docs/benchmarks.md"
PNG="$ROOT/docs/convergence.png"
# each part writes its scenes' outputs (and state files) in its own folder: parts may run at once
mkdir -p "$OUT" "$OUT/contact" "$OUT/contact_w" "$OUT/scenes" "$OUT/convergence" "$ROOT/docs"

skip() { case " $SKIP " in *" $1 "*) return 0 ;; esac; return 1; }
CSTEPS=${BENCH_CONTACT_STEPS:-60}
WSTEPS=${BENCH_W_STEPS:-25}

if [ "${BENCH_NO_BUILD:-0}" = 1 ]; then
    echo "== BENCH_NO_BUILD=1: the benchmark programs already built in $BUILD"
else
    echo "== building the benchmarks in $BUILD"
    cmake --build "$BUILD" --target bench_scenes bench_convergence bench_contact bench_local -j "$JOBS"
fi
BIN="$BUILD/bench"
LOAD_BEFORE=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo "?")

# relative paths in the doc: the commands as a user types them from the repository root
REL_BUILD=${BUILD#"$ROOT"/}
SCENES_CMD="OMP_NUM_THREADS=$OMP_NUM_THREADS $REL_BUILD/bench/bench_scenes --frames $FRAMES --modes $MODES --out-dir $REL_BUILD/bench_out/scenes --csv $REL_BUILD/bench_out/scenes.csv $SCENES"
CONV_CMD="OMP_NUM_THREADS=$OMP_NUM_THREADS $REL_BUILD/bench/bench_convergence --scene $CONV_SCENE --frames $CONV_FRAMES --iterations 20 --jacobi-iterations $CONV_JACOBI --stiffness 1e5,1e7,1e9 --out-dir $REL_BUILD/bench_out/convergence --csv $REL_BUILD/bench_out/convergence.csv"

CONTACT_CMD="OMP_NUM_THREADS=$OMP_NUM_THREADS $REL_BUILD/bench/bench_contact --steps $CSTEPS --out $REL_BUILD/bench_out/contact (the small and medium cloth, ball and gingerbread scenes; the pulling scenes with --steps $((2 * CSTEPS)))"
W_CMD="OMP_NUM_THREADS=$OMP_NUM_THREADS $REL_BUILD/bench/bench_contact --steps $WSTEPS --out $REL_BUILD/bench_out/contact_w --set contact.delassus=explicit|matrix-free scenes/sharp_corner_small.xml scenes/sharp_corner.xml"

# Each part writes its tables under $OUT and says "fail" on error.  With
# BENCH_PARALLEL=1 the parts run at the same time, one thread each (for an
# idle machine with more cores than parts, e.g. the GPU machine's host: the
# whole bench then takes as long as its longest part); their output is then
# printed part by part at the end.
fail() { echo 1 >>"$OUT/failed"; }
rm -f "$OUT/failed"
part_contact() {
    echo "== $CONTACT_CMD"
    S=scenes
    { "$BIN/bench_contact" --steps "$CSTEPS" --out "$OUT/contact" $S/cloth_on_knives_small.xml $S/cloth_on_knives.xml \
          $S/sharp_corner_small.xml $S/sharp_corner.xml $S/squeezing_ball_small.xml $S/squeezing_ball.xml \
          $S/gingerbread_small.xml $S/gingerbread.xml &&
      "$BIN/bench_contact" --steps "$((2 * CSTEPS))" --out "$OUT/contact" $S/pulling_through_gap_small.xml \
          $S/pulling_through_gap.xml | grep '^| pulling'; } >"$OUT/contact.md" 2>"$OUT/contact.log" ||
        { fail; echo "run.sh: bench_contact failed, see $OUT/contact.log" >&2; }
    cat "$OUT/contact.md"
}

part_contact_w() {
    S=scenes
    echo "== $W_CMD"
    for w in explicit matrix-free; do
        "$BIN/bench_contact" --steps "$WSTEPS" --out "$OUT/contact_w" --set contact.delassus=$w \
            $S/sharp_corner_small.xml $S/sharp_corner.xml
    done 2>"$OUT/contact_w.log" | awk 'NR <= 4 || /^\| sharp/' \
        >"$OUT/contact_w.md" || fail
    cat "$OUT/contact_w.md"
}

part_pressure() {
    # make test runs levels 1 and 2; the finest (level 3, 30720 tetrahedra) is here
    echo "== PRESSURE_LEVELS='1 2 3' $REL_BUILD/tests/test_pressure_sphere"
    [ "${BENCH_NO_BUILD:-0}" = 1 ] || cmake --build "$BUILD" --target test_pressure_sphere -j "$JOBS" >/dev/null
    PRESSURE_LEVELS="1 2 3" CK_RUN_CASE=lame "$BUILD/tests/test_pressure_sphere" 2>/dev/null |
        grep -E '^level|%' || fail
}

part_scenes() {
    echo "== $SCENES_CMD"
    # shellcheck disable=SC2086 # SCENES is a list of words
    if "$BIN/bench_scenes" --frames "$FRAMES" --modes "$MODES" --out-dir "$OUT/scenes" \
        --csv "$OUT/scenes.csv" $SCENES >"$OUT/scenes.md" 2>"$OUT/scenes.log"; then :; else
        fail
        echo "run.sh: bench_scenes failed, see $OUT/scenes.log" >&2
        tail -5 "$OUT/scenes.log" >&2
    fi
    cat "$OUT/scenes.md"
}

part_convergence() {
    echo "== $CONV_CMD"
    if "$BIN/bench_convergence" --scene "$CONV_SCENE" --frames "$CONV_FRAMES" --iterations 20 \
        --jacobi-iterations "$CONV_JACOBI" --stiffness 1e5,1e7,1e9 --out-dir "$OUT/convergence" \
        --csv "$OUT/convergence.csv" \
        >"$OUT/convergence.md" 2>"$OUT/convergence.log"; then :; else
        fail
        echo "run.sh: bench_convergence failed, see $OUT/convergence.log" >&2
        tail -5 "$OUT/convergence.log" >&2
    fi
    grep -h "warning" "$OUT/convergence.log" >&2 || true
    cat "$OUT/convergence.md"
}

PARTS_RUN=""
for p in contact pressure scenes convergence; do skip $p || PARTS_RUN="$PARTS_RUN $p"; done
skip contact || PARTS_RUN="$PARTS_RUN contact_w"
if [ "${BENCH_PARALLEL:-0}" = 1 ]; then
    for p in $PARTS_RUN; do part_$p >"$OUT/part_$p.out" 2>&1 & done
    wait
    for p in $PARTS_RUN; do cat "$OUT/part_$p.out"; done
else
    for p in $PARTS_RUN; do part_$p; done
fi
status=0
[ -s "$OUT/failed" ] && status=1
LOAD_AFTER=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo "?")

# ---- the plot: gnuplot, else python3 matplotlib; installed here if missing (never by make test)
have_matplotlib() { python3 -c 'import matplotlib' >/dev/null 2>&1; }
plot_note=""
if [ -s "$OUT/convergence.csv" ]; then
    if ! command -v gnuplot >/dev/null 2>&1 && ! have_matplotlib; then
        echo "== installing gnuplot-nox for the convergence plot"
        SUDO=""
        [ "$(id -u)" = 0 ] || SUDO="sudo"
        if command -v apt-get >/dev/null 2>&1; then
            $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q gnuplot-nox >/dev/null 2>&1 ||
                { $SUDO apt-get update -q >/dev/null 2>&1 &&
                  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q gnuplot-nox >/dev/null 2>&1; } ||
                echo "run.sh: could not install gnuplot-nox" >&2
        fi
    fi
    ncol=$(head -1 "$OUT/convergence.csv" | awk -F, '{print NF}')
    # columns: k, then per solver and stiffness the error and the time [ms] after k iterations
    if command -v gnuplot >/dev/null 2>&1; then
        gnuplot <<EOF
set terminal pngcairo size 1200,520 noenhanced
set output "$PNG"
set datafile separator ","
set multiplot layout 1,2 title "$(basename "$CONV_SCENE"): one step after $CONV_FRAMES frames; complete global step (20 iterations) vs Jacobi ($CONV_JACOBI)"
set logscale xy
set format y "1e%L"
set grid
set key bottom left
set ylabel "relative error (eps(q^k) - eps(q*)) / (eps(q^0) - eps(q*))"
set xlabel "local-global iteration k"
plot for [c=2:$ncol:2] "$OUT/convergence.csv" using 1:c with linespoints lw 2 pt 7 ps 0.4 title columnhead(c)
set xlabel "time [ms] (Local + Assembly + Global, one thread)"
plot for [c=2:$ncol:2] "$OUT/convergence.csv" using (column(c+1)):c with linespoints lw 2 pt 7 ps 0.4 title columnhead(c)
unset multiplot
EOF
    elif have_matplotlib; then
        python3 - "$OUT/convergence.csv" "$PNG" <<'EOF'
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
rows = list(csv.reader(open(sys.argv[1])))
head, data = rows[0], rows[1:]
fig, ax = plt.subplots(1, 2, figsize=(12, 5.2))
for c in range(1, len(head), 2):
    pts = [(float(r[0]), float(r[c + 1]), float(r[c])) for r in data if r[c] and float(r[c]) > 0]
    ax[0].loglog([p[0] for p in pts], [p[2] for p in pts], "o-", ms=2, label=head[c])
    ax[1].loglog([p[1] for p in pts], [p[2] for p in pts], "o-", ms=2, label=head[c])
ax[0].set_xlabel("local-global iteration k")
ax[1].set_xlabel("time [ms]")
for a in ax:
    a.set_ylabel("relative error")
    a.grid(True, which="both", alpha=0.3)
    a.legend(fontsize=8)
fig.suptitle("Twisting bar: one step from the twisted state, complete vs Jacobi global step")
fig.savefig(sys.argv[2], dpi=100)
EOF
    else
        plot_note="(no plot: neither gnuplot nor python3 matplotlib could be installed)"
    fi
    [ -s "$PNG" ] && echo "== plot: docs/convergence.png"
fi

# ---- docs/benchmarks.md: replace the generated section, keep everything else
BEGIN='<!-- BEGIN GENERATED by tests/bench/run.sh: do not edit by hand -->'
END='<!-- END GENERATED by tests/bench/run.sh -->'
GEN="$OUT/generated.md"
# Who measured a part: printed under each part measured by this run.
measured_by() {
    echo "- measured: $(date -u '+%Y-%m-%d %H:%M UTC'), $(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1)," \
         "$NCPU cores available, $(awk '/MemTotal/ {printf "%.0f GiB", $2 / 1048576}' /proc/meminfo) memory;" \
         "load average (1, 5, 15 min) before: $LOAD_BEFORE, after: $LOAD_AFTER"
    echo "- OMP_NUM_THREADS=$OMP_NUM_THREADS$([ "${BENCH_PARALLEL:-0}" = 1 ] && echo ", the parts of this run at the same time (BENCH_PARALLEL=1: $PARTS_RUN), one thread each"), build type" \
         "$(sed -n 's/^CMAKE_BUILD_TYPE:STRING=//p' "$BUILD/CMakeCache.txt"), commit" \
         "${BENCH_COMMIT:-$(git rev-parse --short HEAD 2>/dev/null || echo '?')$(git diff --quiet HEAD -- 2>/dev/null || echo ' + local changes')}"
    echo "- command: \`make bench\` (= \`sh tests/bench/run.sh $REL_BUILD\`), which ran:"
    echo
    for c in "$@"; do echo "      $c"; done
    echo
}
# A skipped part keeps its previous section of the doc (from its "## Measured: TITLE"
# heading to the next one), so that parts can be measured by separate runs.
old_part() {
    [ -f "$DOC" ] || return 0
    awk -v b="$BEGIN" -v e="$END" -v t="## Measured: $1" '
        $0 == b { in_gen = 1; next }
        $0 == e { in_gen = 0 }
        in_gen && /^## Measured: / { keep = (index($0, t) == 1) }
        in_gen && keep { print }' "$DOC"
}
{
    echo "$BEGIN"
    echo
    if skip scenes; then old_part "scenes"; else
        echo "## Measured: scenes and global-solver modes"
        echo
        measured_by "$SCENES_CMD"
        echo "Times are medians per frame over $FRAMES frames in ms (\"/it\": divided by the" \
             "local-global iterations per frame); S+S^T MB is the memory of S and S^T (MB = 2^20 bytes);" \
             "factor and inverse are the precompute times in s. CSV: \`$REL_BUILD/bench_out/scenes.csv\`."
        echo
        cat "$OUT/scenes.md"
        echo
    fi
    if skip contact; then old_part "the contact scenes"; else
        echo "## Measured: the contact scenes (issue 5), small and medium sizes"
        echo
        measured_by "$CONTACT_CMD" "$W_CMD"
        echo "Medians per frame [ms] of the paper's Table 3 phases over the frames in which each ran;"
        echo "Detection is the CollisionPipeline's (the paper's Frame leaves it out)."
        echo
        grep '^|' "$OUT/contact.md"
        echo
        echo "W explicit against matrix-free on the sharp corner ($WSTEPS steps: the cloth lands after"
        echo "about 10), forced with \`--set contact.delassus=...\` (\`delassus=auto\` picks matrix-free"
        echo "for both sizes on the CPU):"
        echo
        grep '^|' "$OUT/contact_w.md"
        echo
    fi
    if skip convergence; then old_part "convergence"; else
        echo "## Measured: convergence of the local-global iterations"
        echo
        measured_by "$CONV_CMD"
        echo "Relative error (eps(q^k) - eps(q*)) / (eps(q^0) - eps(q*)) of one step taken from the"
        echo "state after $CONV_FRAMES frames, eps the incremental potential, q* Newton's solution of the same"
        echo "step, for the scene's complete global step (SparseInverseSolver) and the paper's incomplete"
        echo "baseline (JacobiSolver: one Jacobi sweep per iteration from the current iterate, no Chebyshev),"
        echo "by iterations and by time. CSV: \`$REL_BUILD/bench_out/convergence.csv\`."
        echo
        cat "$OUT/convergence.md"
        echo
        if [ -s "$PNG" ]; then echo "![convergence](convergence.png)"; else echo "$plot_note"; fi
        echo
    fi
    echo "$END"
} >"$GEN"

if [ -f "$DOC" ] && grep -qF "$BEGIN" "$DOC" && grep -qF "$END" "$DOC"; then
    awk -v b="$BEGIN" -v e="$END" -v gen="$GEN" '
        $0 == b { while ((getline line < gen) > 0) print line; skip = 1; next }
        $0 == e { skip = 0; next }
        !skip { print }' "$DOC" >"$DOC.tmp" && mv "$DOC.tmp" "$DOC"
else
    [ -f "$DOC" ] || printf '# Benchmarks\n\n' >"$DOC"
    { echo; cat "$GEN"; } >>"$DOC"
fi
echo "== wrote docs/benchmarks.md"
exit $status
