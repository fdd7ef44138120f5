#!/bin/sh
# viewer_cli.sh PLIANT SOURCE_DIR PNG_CHECK [XVFB_RUN]: pliant render and
# pliant view run as a user would.
#  - render writes the expected number of PNGs (steps 0, 2, 4, 6), each of the
#    asked size and not blank;
#  - the MP4 decodes (ffprobe) with the expected number of frames;
#  - bad arguments and a missing display exit 2 with a message;
#  - under Xvfb (required), a --script presses + twice (cable.value = 2 mm), drags the
#    tip and saves a screenshot of the window's size.
set -u
PLIANT=$1; SRC=$2; PNG_CHECK=$3; XVFB_RUN=${4:-}
T=$(mktemp -d "${TMPDIR:-/tmp}/pliant_viewer_cli.XXXXXX")
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
SCENE=$SRC/scenes/cable_finger_small.xml

# make deps installs ffmpeg and xvfb: without them this test fails (it does not
# pass with parts left out)
command -v ffprobe > /dev/null || fail "ffprobe not found (make deps installs ffmpeg)"
[ -n "$XVFB_RUN" ] || fail "xvfb-run not found at configure time (make deps installs xvfb)"

# no overlay: the pictures differ only if the scene drawn differs (the finger
# coloured by displacement: uniform at step 0, the pull bends it by step 6)
"$PLIANT" render "$SCENE" -n 6 --every 2 --png "$T/png" --size 160x120 --out "$T/out" --quiet \
  --no-overlay > "$T/render.log" 2>&1 || { cat "$T/render.log"; fail "pliant render"; }
n=$(ls "$T/png" | grep -c '\.png$')
[ "$n" = 4 ] || fail "expected 4 PNGs (steps 0, 2, 4, 6), found $n"
for f in "$T"/png/*.png; do "$PNG_CHECK" "$f" 160 120 || fail "picture $f"; done
first=$(ls "$T"/png/*.png | head -n 1); last=$(ls "$T"/png/*.png | tail -n 1)
cmp -s "$first" "$last" && fail "the pictures of steps 0 and 6 are the same"

"$PLIANT" render "$SCENE" -n 9 --every 3 --mp4 "$T/film.mp4" --size 160x120 --out "$T/out" \
  --quiet > "$T/mp4.log" 2>&1 || { cat "$T/mp4.log"; fail "pliant render --mp4"; }
frames=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames \
  -of csv=p=0 "$T/film.mp4")
[ "$frames" = 4 ] || fail "the MP4 has $frames frames, expected 4"

"$PLIANT" render "$SCENE" -n 2 --size 160x120 > "$T/e1" 2>&1; rc=$?
[ $rc = 2 ] && grep -q "give --png DIR or --mp4 FILE" "$T/e1" || fail "no output: rc $rc"
"$PLIANT" render "$SCENE" -n 2 --png "$T/x" --size 12x9 > "$T/e2" 2>&1; rc=$?
[ $rc = 2 ] && grep -q -- "--size" "$T/e2" || fail "bad size: rc $rc"
"$PLIANT" render "$SCENE" -n 2 --png "$T/x" --field stress > "$T/e3" 2>&1; rc=$?
[ $rc = 2 ] && grep -q -- "--field" "$T/e3" || fail "bad field: rc $rc"
"$PLIANT" render "$SCENE" -n 2 --png "$T/x" --bogus > "$T/e5" 2>&1; rc=$?
[ $rc = 2 ] && grep -q "unknown option" "$T/e5" && grep -q "pliant render --help" "$T/e5" \
  || fail "unknown option: rc $rc"
"$PLIANT" render "$SCENE" -n 2 --png "$T/x" --every=0 > "$T/e6" 2>&1; rc=$?
[ $rc = 2 ] && grep -q -- "--every expects" "$T/e6" || fail "bad --every: rc $rc"
"$PLIANT" render "$SCENE" "$SCENE" -n 2 --png "$T/x" > "$T/e7" 2>&1; rc=$?
[ $rc = 2 ] && grep -q "more than one scene" "$T/e7" || fail "two scenes: rc $rc"
"$PLIANT" view > "$T/e8" 2>&1; rc=$?
[ $rc = 2 ] && grep -q "no scene given" "$T/e8" || fail "view without a scene: rc $rc"
"$PLIANT" view "$SCENE" --threads=x > "$T/e9" 2>&1; rc=$?
[ $rc = 2 ] && grep -q -- "--threads expects" "$T/e9" || fail "view --threads=x: rc $rc"
env -u DISPLAY -u WAYLAND_DISPLAY "$PLIANT" view "$SCENE" --out "$T/out" > "$T/e4" 2>&1; rc=$?
[ $rc = 2 ] && grep -q "display" "$T/e4" || { cat "$T/e4"; fail "view without a display: rc $rc"; }

cat > "$T/script.txt" <<'END'
# two presses of + pull the cable by 2 mm
key +
key +
print finger/cable.value
drag 60 80 60 40 5
step 2
screenshot SHOT
print finger/keys.step
quit
END
sed -i "s|SHOT|$T/shot.png|" "$T/script.txt"
"$XVFB_RUN" -a -s "-screen 0 1024x768x24" "$PLIANT" view "$SCENE" --script "$T/script.txt" \
  --size 200x150 --out "$T/out" --quiet > "$T/view.log" 2>&1 || { cat "$T/view.log"; fail "view --script"; }
grep -q "finger/cable.value = 0.002" "$T/view.log" || { cat "$T/view.log"; fail "keys"; }
"$PNG_CHECK" "$T/shot.png" 200 150 || fail "screenshot"
echo "viewer_cli: all checks passed"
