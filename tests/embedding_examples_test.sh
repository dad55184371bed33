#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# The three ways an embedder decodes, on one cell of a sample database, in every pixel
# format and both row orders: the C example (samples/embed_c, through read callbacks),
# the C++ example (samples/embed, through decode_cube_into) and docs/embedding.md's
# Python ctypes example, run as written against the build tree's shared decoder library.
# All three must give the same bytes for every face.
# Usage: embedding_examples_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build_dir=$1
source_dir=$2
test_name="embedding examples"
source "$source_dir/tests/support/script_test.sh"
python=/usr/bin/python3  # Debian's, with python3-numpy (scripts/install-deps.sh)

example=$(awk '/<!-- ctypes-example -->/ {found = 1; next}
               found && /^```python/ {inside = 1; next}
               inside && /^```/ {exit}
               inside {print}' "$source_dir/docs/embedding.md")
[[ -n "$example" ]] || fail "no ctypes example in docs/embedding.md"

# Cell (1,0,1) of a 2x1x2 grid, a B-cube: found by the examples from its centre's position.
"$build_dir/bin/svc-scene" "$work/db" --grid 2,1,2 --face-size 34 --quiet
"$build_dir/bin/svc" encode "$work/db" -o "$work/db.svc" -q 60 --quiet
read -r -a position <<<"$(cell_position "$build_dir/bin/svc" "$work/db.svc" 1 0 1)"

write_example() {  # FORMAT_NUMBER ROWS_NUMBER FILE
  {
    echo "LIBRARY = '$build_dir/lib/libsvc_decoder.so'"
    echo "FILE = '$3'"
    echo "CELL = (1, 0, 1)"
    echo "FACE = 0"
    echo "FORMAT = $1"
    echo "ROWS = $2"
    echo "$example"
    cat <<CHECK
with open('$work/ctypes.bin', 'wb') as out:
    for f in range(6):
        planes = decode_face(FILE, CELL, f, FORMAT, ROWS)
        for plane in (planes if FORMAT == SVC_PIXEL_YCBCR420 else [planes]):
            out.write(plane.tobytes())
CHECK
  } >"$work/example.py"
}

formats=(rgba8 bgra8 rgb8 ycbcr420)
for number in 0 1 2 3; do
  format=${formats[$number]}
  for rows in 0 1; do
    order=(); [[ $rows == 1 ]] && order=(--bottom-up)
    what="$format, ${order[*]:-top-down}"
    "$build_dir/bin/svc-embed-c" --format "$format" "${order[@]}" "$work/db.svc" "$work/c.bin" "${position[@]}" \
      >"$work/c.out" || fail "the C example failed ($what)"
    [[ "$(cat "$work/c.out")" == "cell 1,0,1: 6 faces of 34x34" ]] || fail "the C example printed: $(cat "$work/c.out")"
    "$build_dir/bin/svc-embed-example" --format "$format" "${order[@]}" --out "$work/cpp.bin" "$work/db.svc" \
      "${position[@]}" >/dev/null || fail "the C++ example failed ($what)"
    write_example "$number" "$rows" "$work/db.svc"
    out=$("$python" "$work/example.py") || fail "the ctypes example failed ($what)"
    case $format in
      ycbcr420) expected="[(34, 34), (17, 17), (17, 17)]" ;;
      rgb8) expected="[(34, 34, 3)]" ;;
      *) expected="[(34, 34, 4)]" ;;
    esac
    [[ "$out" == "$expected" ]] || fail "the ctypes example printed $out ($what)"
    cmp -s "$work/c.bin" "$work/cpp.bin" || fail "the C and C++ examples decode differently ($what)"
    cmp -s "$work/c.bin" "$work/ctypes.bin" || fail "the C and ctypes examples decode differently ($what)"
    cp "$work/c.bin" "$work/$format-$rows.bin"
  done
done
# The row orders differ by the order of rows alone, and the formats by their channels.
"$python" - "$work" <<'CHECK' || fail "the formats or row orders do not agree with each other"
import sys
import numpy as np
work = sys.argv[1]
def faces(name, channels):
    return np.fromfile('%s/%s.bin' % (work, name), np.uint8).reshape(6, 34, 34, channels)
rgba = faces('rgba8-0', 4)
assert np.array_equal(faces('rgba8-1', 4), rgba[:, ::-1])
assert np.array_equal(faces('bgra8-0', 4), rgba[..., [2, 1, 0, 3]])
assert np.array_equal(faces('rgb8-0', 3), rgba[..., :3])
assert (rgba[..., 3] == 255).all()
CHECK
# The example's errors come back as exceptions with the library's message.
write_example 0 0 "$work/absent.svc"
if err=$("$python" "$work/example.py" 2>&1); then fail "an absent file decoded"; fi
[[ "$err" == *"cannot open $work/absent.svc"* ]] || fail "the error for an absent file: $err"
echo "$test_name: the C, C++ and ctypes examples agree on every face in 4 formats and 2 row orders"
