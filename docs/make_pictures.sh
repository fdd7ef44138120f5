#!/bin/sh
# make_pictures.sh BUILD_DIR: `make pictures`.  Renders one frame of every
# scene of scenes/ (the small variant of the heavy ones: a picture stands for
# its family, the finer meshes look the same) with pliant render, off screen,
# into docs/pictures/<scene>.png (480 x 360, no overlay), shown by
# docs/scenes.md.  Each line it prints gives the seconds the picture took.
set -eu
BUILD=${1:-build}
PLIANT=$BUILD/bin/pliant
OUT=docs/pictures
TMP=$(mktemp -d "${TMPDIR:-/tmp}/pliant_pictures.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
# picture name, scene file, step drawn
while read -r name scene steps; do
  [ -z "$name" ] && continue
  start=$(date +%s)
  "$PLIANT" render "scenes/$scene" -n "$steps" --from "$steps" --png "$TMP/$name" \
    --size 480x360 --no-overlay --out "$TMP/out" --quiet > "$TMP/log" 2>&1 ||
    { cat "$TMP/log"; echo "make pictures: $scene failed" >&2; exit 1; }
  mv "$TMP/$name/"*_0000.png "$OUT/$name.png"
  echo "$OUT/$name.png: $scene at step $steps ($(( $(date +%s) - start )) s)"
done <<'END'
ball_on_plane ball_on_plane.xml 60
cable_finger cable_finger_small.xml 40
cantilever cantilever_small.xml 50
cloth_extension_arap cloth_extension_arap_small.xml 40
cloth_extension_corotational cloth_extension_corotational_small.xml 40
cloth_extension_neohookean cloth_extension_neohookean_small.xml 40
cloth_on_knives cloth_on_knives_small.xml 60
gingerbread gingerbread_small.xml 80
grabbing_raptor grabbing_raptor_small.xml 60
hanging_bar hanging_bar_small.xml 50
pulling_through_gap pulling_through_gap_small.xml 80
resting_box resting_box.xml 40
sharp_corner sharp_corner_small.xml 80
sliding_box sliding_box.xml 40
squeezing_ball squeezing_ball_small.xml 50
stick_slip stick_slip.xml 40
template_constraint template_constraint.xml 30
twisting_bar twisting_bar_small.xml 50
END
