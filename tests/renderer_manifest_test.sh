#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Runs docs/input-format.md's manifest writer (the block after "<!-- renderer-manifest")
# on svc-scene's images renamed to the renderer layout it describes (X_Y_Z_FACE.png and
# .exr in one folder), then checks that it wrote svc-scene's own cameras and that svc
# accepts the result (check, encode).
set -euo pipefail
build_dir=$1
source_dir=$2
test_name="renderer manifest test"
source "$source_dir/tests/support/script_test.sh"

awk '/<!-- renderer-manifest/ {found = 1; next}
     found && /^```python/ {inside = 1; next}
     inside && /^```/ {exit}
     inside {print}' "$source_dir/docs/input-format.md" >"$work/write_manifest.py"
[[ -s "$work/write_manifest.py" ]] || fail "no renderer-manifest snippet in docs/input-format.md"

# The snippet's settings: origin -1,1.6,-1, spacing 0.5,1,0.5, 256-pixel faces.
"$build_dir/bin/svc-scene" "$work/scene" --grid 2,1,2 --origin -1,1.6,-1 --face-size 256 --quiet
mkdir "$work/renders"
for dir in "$work"/scene/cells/*; do
  cell=$(basename "$dir")
  for face in px nx py ny pz nz; do
    cp "$dir/$face.png" "$work/renders/${cell}_$face.png"
    cp "$dir/$face.exr" "$work/renders/${cell}_$face.exr"
  done
done
python3 "$work/write_manifest.py" "$work/renders" || fail "the snippet failed"

python3 - "$work/scene/manifest.json" "$work/renders/manifest.json" <<'PY' || fail "the cameras differ from svc-scene's"
import json, sys
scene, written = (json.load(open(p)) for p in sys.argv[1:])
cells = {tuple(c["index"]): c for c in written["cells"]}
assert len(cells) == len(scene["cells"]) == 4, "cell count"
for cell in scene["cells"]:
    other = cells[tuple(cell["index"])]
    assert max(abs(a - b) for a, b in zip(cell["position"], other["position"])) < 1e-9, "position"
    for face, entry in cell["faces"].items():
        got = other["faces"][face]["world_to_camera"]
        assert max(abs(a - b) for a, b in zip(entry["world_to_camera"], got)) < 1e-9, face
PY
"$build_dir/bin/svc" check "$work/renders" >/dev/null || fail "svc check refuses the manifest"
"$build_dir/bin/svc" encode --quiet "$work/renders" -o "$work/renders.svc" || fail "svc encode refuses it"
