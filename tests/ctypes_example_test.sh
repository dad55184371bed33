#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# docs/embedding.md's Python ctypes example, run as written against the build tree's
# shared decoder library: the face it decodes into a NumPy array must be the one
# samples/embed_c decodes through the C API's read callbacks (itself checked against the
# C++ reader by tests/svc_c_api_test.cc).
# Usage: ctypes_example_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build_dir=$1
source_dir=$2
test_name="ctypes example"
source "$source_dir/tests/support/script_test.sh"
python=/usr/bin/python3  # Debian's, with python3-numpy (scripts/install-deps.sh)

example=$(awk '/<!-- ctypes-example -->/ {found = 1; next}
               found && /^```python/ {inside = 1; next}
               inside && /^```/ {exit}
               inside {print}' "$source_dir/docs/embedding.md")
[[ -n "$example" ]] || fail "no ctypes example in docs/embedding.md"

"$build_dir/bin/svc-scene" "$work/db" --grid 2,1,2 --face-size 32 --quiet
"$build_dir/bin/svc" encode "$work/db" -o "$work/db.svc" -q 60 --quiet
"$build_dir/bin/svc-embed-c" "$work/db.svc" "$work/cube.rgba" >/dev/null

for face in 0 3 5; do
  {
    echo "LIBRARY = '$build_dir/lib/libsvc_decoder.so'"
    echo "FILE = '$work/db.svc'"
    echo "CELL = (0, 0, 0)"
    echo "FACE = $face"
    echo "$example"
    cat <<CHECK
cube = np.fromfile('$work/cube.rgba', dtype=np.uint8).reshape(6, 32, 32, 4)
if not np.array_equal(face, cube[FACE]):
    raise SystemExit('face %d differs from the C example\'s' % FACE)
CHECK
  } >"$work/example.py"
  out=$("$python" "$work/example.py") || fail "the example failed on face $face"
  [[ "$out" == "(32, 32, 4) uint8" ]] || fail "the example printed: $out"
done
# Its errors come back as exceptions with the library's message.
sed -i "s|^FILE = .*|FILE = '$work/absent.svc'|" "$work/example.py"
if err=$("$python" "$work/example.py" 2>&1); then fail "an absent file decoded"; fi
[[ "$err" == *"cannot open $work/absent.svc"* ]] || fail "the error for an absent file: $err"
echo "$test_name: faces 0, 3 and 5 as the C example decodes them"
