#!/usr/bin/env bash
# ICL-NUIM livingroom1 held-out view synthesis: train on frames 0, 2, 4 with `vigs map`, render
# the held-out frames 1 and 3 with `vigs render`, score them with `vigs eval image`.
# Usage: tests/mapping/icl_nuim/run_benchmark.sh [BUILD_DIR] [ITERATIONS] [DATA_DIR]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
build="${1:-$root/build}"
iters="${2:-3000}"
data="${3:-$root/../shared/data/icl_nuim_livingroom1}"
vigs="$build/bin/vigs"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# trajectory.log: per frame a header line, then the 4x4 camera-to-world matrix. Convert each
# rotation to a quaternion (Shepperd) and write "t colour depth tx ty tz qx qy qz qw".
awk -v data="$data" '
  function q_from_r(   tr, s) {
    tr = r[0,0] + r[1,1] + r[2,2]
    if (tr > 0) { s = sqrt(tr + 1) * 2; qw = s / 4; qx = (r[2,1] - r[1,2]) / s; qy = (r[0,2] - r[2,0]) / s; qz = (r[1,0] - r[0,1]) / s }
    else if (r[0,0] > r[1,1] && r[0,0] > r[2,2]) { s = sqrt(1 + r[0,0] - r[1,1] - r[2,2]) * 2; qw = (r[2,1] - r[1,2]) / s; qx = s / 4; qy = (r[0,1] + r[1,0]) / s; qz = (r[0,2] + r[2,0]) / s }
    else if (r[1,1] > r[2,2]) { s = sqrt(1 + r[1,1] - r[0,0] - r[2,2]) * 2; qw = (r[0,2] - r[2,0]) / s; qx = (r[0,1] + r[1,0]) / s; qy = s / 4; qz = (r[1,2] + r[2,1]) / s }
    else { s = sqrt(1 + r[2,2] - r[0,0] - r[1,1]) * 2; qw = (r[1,0] - r[0,1]) / s; qx = (r[0,2] + r[2,0]) / s; qy = (r[1,2] + r[2,1]) / s; qz = s / 4 }
  }
  NR % 5 == 1 { frame = $1; row = 0; next }
  { for (c = 0; c < 4; c++) r[row, c] = $(c + 1); row++
    if (row == 4) {
      q_from_r()
      printf "%d %s/color_%05d.jpg %s/depth_%05d.png %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", frame, data, frame, data, frame, r[0,3], r[1,3], r[2,3], qx, qy, qz, qw
    } }' "$data/trajectory.log" > "$work/all.txt"

awk '$1 == 0 || $1 == 2 || $1 == 4' "$work/all.txt" > "$work/train.txt"
"$vigs" map --camera "$here/camera.yaml" --frames "$work/train.txt" --iterations "$iters" \
  --out "$work/map.ply" --quiet
for f in 1 3; do
  pose="$(awk -v f="$f" '$1 == f { print $4, $5, $6, $7, $8, $9, $10 }' "$work/all.txt")"
  "$vigs" render --map "$work/map.ply" --camera "$here/camera.yaml" --pose "$pose" \
    --out "$work/render_$f.png" > /dev/null
  # the colour frames are JPEG; compare against them as decoded
  "$vigs" eval image --ref "$(printf '%s/color_%05d.jpg' "$data" "$f")" --test "$work/render_$f.png"
done
if [ -n "${KEEP_DIR:-}" ]; then mkdir -p "$KEEP_DIR" && cp "$work"/*.png "$work"/*.ply "$work"/*.txt "$KEEP_DIR"/; fi
