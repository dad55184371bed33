#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# svc-viewer's frames, rendered offscreen (--screenshot) in a virtual X server with Mesa's
# software renderer, against frames computed on the CPU from the decoded faces and their
# cameras (tests/viewer_reference.cc): fixed viewpoints looking at every face and across
# the cube's edges and corners. A frame matches when the mean absolute difference of its
# samples is below 1 level and their 99th percentile below 8: what the GPU's bilinear
# weights (a few fractional bits) and its seamless filtering at the cube's corners may
# move. The same frames computed from mirrored faces must fail that tolerance, so a
# viewer that orients a face wrongly fails the test. Halfway between two cells, the
# cell's faces reprojected with their depth must come nearer the view from there than
# its plain cube map (PSNR). Also: the overlay, a walk along a path with prefetch hits,
# the errors for a missing or damaged file and for --reprojection without depth. Skipped (exit 77) where Xvfb or an OpenGL 3.3 context cannot start.
# Usage: viewer_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
bin=$1/bin
test_name="viewer test"
source "$2/tests/support/script_test.sh"

if ! command -v Xvfb >/dev/null; then
  echo "SKIPPED: Xvfb is not installed (apt-get install xvfb)"
  exit 77
fi
# -displayfd: Xvfb picks a free display and writes its number once it accepts clients.
Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3>"$work/display" 2>"$work/xvfb.log" &
xvfb=$!
trap 'kill "$xvfb" 2>/dev/null; wait "$xvfb" 2>/dev/null; rm -rf "$work"' EXIT
for _ in $(seq 100); do
  [[ -s "$work/display" ]] && break
  sleep 0.1
done
if [[ ! -s "$work/display" ]]; then
  echo "SKIPPED: Xvfb did not start:"
  cat "$work/xvfb.log"
  exit 77
fi
export DISPLAY=":$(head -n 1 "$work/display")" LIBGL_ALWAYS_SOFTWARE=1
if ! gl=$(timeout 60 "$bin/svc-viewer" --gl-info 2>&1); then
  echo "SKIPPED: no OpenGL 3.3 core context: $gl"
  exit 77
fi
echo "rendering with $gl"

viewer() { timeout 120 "$bin/svc-viewer" "$@"; }
within_tolerance() { awk -v m="$mean" -v p="$p99" 'BEGIN { exit !(m < 1.0 && p < 8) }'; }
# "X,Y,Z" of cell I J K's centre, moved by DX DY DZ (the grid is 0.5 m apart).
eye_of() { awk -v c="$corner" -v d="$1,$2,$3,$4,$5,$6" 'BEGIN { split(c, o, " "); split(d, a, ",")
  printf "%g,%g,%g", o[1] + 0.5 * a[1] + a[4], o[2] + a[2] + a[5], o[3] + 0.5 * a[3] + a[6] }'; }

"$bin/svc-scene" "$work/db" --kind house --grid 3,1,3 --face-size 64 --quiet
"$bin/svc" encode "$work/db" -o "$work/db.svc" --quiet
corner=$(cell_position "$bin/svc" "$work/db.svc" 0 0 0)

# Cell (1,0,1) in every direction of the faces and across edges and corners; another
# cell seen from off its centre (the cell's cube map is still drawn at infinity).
views=()
for look in 0,0 90,0 180,0 270,0 45,30 -30,-60 10,85; do views+=("$(eye_of 1 0 1 0 0 0) $look"); done
views+=("$(eye_of 2 0 0 0.1 0.05 -0.1) 300,10")
frame=(--size 160x120 --fov 90)
for k in "${!views[@]}"; do echo "${views[$k]} $work/viewer-$k.png"; done >"$work/views.txt"
viewer "$work/db.svc" --no-reprojection --views "$work/views.txt" "${frame[@]}" >/dev/null ||
  fail "svc-viewer failed to render $(cat "$work/views.txt")"
for k in "${!views[@]}"; do
  read -r at look <<<"${views[$k]}"
  "$bin/svc-viewer-reference" render "$work/db.svc" --at "$at" --look "$look" "${frame[@]}" \
    --against "$work/viewer-$k.png" >"$work/differences"
  read -r _ mean _ p99 _ _ _ psnr <"$work/differences"
  echo "at $at looking $look: against the CPU's frame mean $mean p99 $p99 (PSNR $psnr dB)"
  within_tolerance || fail "at $at looking $look the viewer's frame differs from the CPU's: mean $mean, p99 $p99"
  read -r _ _ mean _ p99 _ <<<"$(tail -n 1 "$work/differences")"
  echo "  against the frame of mirrored faces mean $mean p99 $p99"
  ! within_tolerance || fail "at $at looking $look a frame of mirrored faces passes for the viewer's"
done

# The overlay covers the top left corner and leaves the rest of the frame alone.
viewer "$work/db.svc" --screenshot "$work/overlay.png" --overlay --at "$(eye_of 1 0 1 0 0 0)" --look 0,0 \
  --size 320x240 >/dev/null
viewer "$work/db.svc" --screenshot "$work/plain.png" --at "$(eye_of 1 0 1 0 0 0)" --look 0,0 --size 320x240 >/dev/null
"$bin/svc-viewer-reference" compare "$work/overlay.png" "$work/plain.png" --region 160,120,160,120 |
  grep -q "^mean_abs 0.000 " || fail "the overlay reaches into the bottom right quarter of the frame"
"$bin/svc-viewer-reference" compare "$work/overlay.png" "$work/plain.png" --region 0,0,100,30 |
  awk '{ exit !($2 > 20) }' || fail "the overlay does not show in the top left corner"

# A walk along a row of cells: every cell shown, and prefetch ahead of the eye.
for i in 0 1 2; do eye_of "$i" 0 1 0 0 0 | tr , ' ' && echo; done >"$work/path.txt"
summary=$(viewer "$work/db.svc" --path "$work/path.txt" --speed 2 --size 160x120) || fail "the walk failed"
echo "$summary"
[[ "$summary" == *", 3 cells shown;"* ]] || fail "the walk did not show the path's 3 cells"
hits=$(echo "$summary" | sed -n 's/.*face cache \([0-9]*\) hits.*/\1/p')
((hits >= 6)) || fail "the walk found no prefetched cell in the face cache ($hits hits)"

# Halfway between cells (0,0,1) and (1,0,1), the faces of the cell reprojected with their
# depth come nearer the view from that point (svc-scene --eye, drawn at infinity by the
# viewer, which is exact at the cube map's own centre) than the cell's plain cube map.
"$bin/svc" encode "$work/db" -o "$work/depth.svc" --depth --quiet
middle=$(eye_of 0 0 1 0.25 0 0)
"$bin/svc-scene" "$work/truth" --kind house --grid 3,1,3 --face-size 64 --eye "$middle" --quiet
"$bin/svc" encode "$work/truth" -o "$work/truth.svc" -q 95 --quiet
looks=(0,0 90,0 45,-30)
pairs=()
for look in "${looks[@]}"; do
  for kind in truth nearest reprojected; do echo "$middle $look $work/$kind-$look.png" >>"$work/$kind.txt"; done
  pairs+=("$work/reprojected-$look.png" "$work/truth-$look.png" "$work/nearest-$look.png" "$work/truth-$look.png")
done
frame=(--size 320x240 --fov 90)
viewer "$work/truth.svc" --views "$work/truth.txt" --no-reprojection "${frame[@]}" >/dev/null
viewer "$work/depth.svc" --views "$work/nearest.txt" --no-reprojection "${frame[@]}" >/dev/null
viewer "$work/depth.svc" --views "$work/reprojected.txt" --reprojection "${frame[@]}" >/dev/null
"$bin/svc-viewer-reference" compare "${pairs[@]}" >"$work/psnr"
for k in "${!looks[@]}"; do
  reprojected=$(sed -n "$((2 * k + 1))s/.*psnr //p" "$work/psnr")
  nearest=$(sed -n "$((2 * k + 2))s/.*psnr //p" "$work/psnr")
  echo "at $middle looking ${looks[$k]}: PSNR against the view from there: reprojected $reprojected dB," \
    "nearest cell's cube map $nearest dB"
  awk -v r="$reprojected" -v n="$nearest" 'BEGIN { exit !(r > n) }' ||
    fail "looking ${looks[$k]} between cells the reprojected frame ($reprojected dB) is no better than the cube map"
done

# Keyboard and mouse mode, no key pressed: the eye stays in the middle cell.
summary=$(viewer "$work/db.svc" --frames 20 --size 160x120) || fail "the viewer failed in keyboard mode"
[[ "$summary" == "svc-viewer: 20 frames in "*", 1 cells shown;"* ]] || fail "keyboard mode without keys: $summary"

# Errors name what is wrong.
if viewer "$work/missing.svc" --screenshot "$work/x.png" --at 0,0,0 2>"$work/err"; then fail "a missing file rendered"; fi
grep -q "missing.svc" "$work/err" || fail "the error for a missing file does not name it: $(cat "$work/err")"
printf '0,1.6,0 0,0 %s\n0,1.6,0 0 %s\n' "$work/v1.png" "$work/v2.png" >"$work/bad-views.txt"
status=0
viewer "$work/db.svc" --views "$work/bad-views.txt" 2>"$work/err" || status=$?
((status == 2)) || fail "a views file with a bad line exited $status, not 2"
grep -q "bad-views.txt:2: expected" "$work/err" || fail "the error for a bad view does not name its line: $(cat "$work/err")"
[[ ! -e "$work/v1.png" ]] || fail "a views file with a bad line rendered its first view"
head -c 3000 "$work/db.svc" >"$work/damaged.svc"
status=0
viewer "$work/damaged.svc" --screenshot "$work/x.png" --at 0,0,0 2>"$work/err" || status=$?
((status == 3)) || fail "a damaged file exited $status, not 3"
grep -q "^svc-viewer: corrupt data: .*damaged.svc" "$work/err" || fail "the error for a damaged file: $(cat "$work/err")"
status=0
viewer "$work/db.svc" --reprojection --screenshot "$work/x.png" 2>"$work/err" || status=$?
((status == 2)) || fail "--reprojection on a file without depth exited $status, not 2"
grep -q "db.svc holds no depth" "$work/err" || fail "the error for a file without depth: $(cat "$work/err")"
[[ ! -e "$work/x.png" ]] || fail "a failed screenshot left a file"
echo "viewer test: passed"
