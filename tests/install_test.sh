#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Installs svc to a prefix with spaces in its name and moves the installed tree; then
# builds samples/embed and samples/embed_c against it both ways, running the recipe in README ("Embedding")
# exactly as written (CMake component `decoder`, pkg-config `svc-decoder`), runs both
# builds on a real .svc, and checks that neither pulls in OpenImageIO, OpenEXR or FFmpeg.
# A program linked against the full library through pkg-config alone must encode the
# same bytes as the build tree's tool.
set -euo pipefail
build_dir=$1
source_dir=$2
test_name="install test"
source "$source_dir/tests/support/script_test.sh"
image_libs='OpenImageIO|OpenEXR|Imath|Iex|IlmThread|avcodec|avformat|avutil|swscale|swresample'

cmake --install "$build_dir" --prefix "$work/first prefix" >/dev/null
mkdir "$work/moved"
mv "$work/first prefix" "$work/moved/svc install"
export SVC_PREFIX="$work/moved/svc install"
# The tools come with the libraries, and run from the moved prefix.
for tool in svc svc-scene svc-walkthrough; do
  [[ -x "$SVC_PREFIX/bin/$tool" ]] || fail "the install lacks bin/$tool"
  "$SVC_PREFIX/bin/$tool" --help >/dev/null || fail "the installed $tool does not run"
done

# The shared decoder is there to be loaded at run time (ctypes, plugins), exporting its
# API alone, without the link that would make -lsvc_decoder pick it.
shared="$SVC_PREFIX/lib/libsvc_decoder.so.0"
[[ -f "$shared" ]] || fail "the install lacks lib/libsvc_decoder.so.0"
[[ ! -e "$SVC_PREFIX/lib/libsvc_decoder.so" ]] || fail "the install links lib/libsvc_decoder.so"
"$source_dir/tests/decoder_exports_test.sh" "$shared" >/dev/null || fail "the installed shared decoder's exports"
abi=$(/usr/bin/python3 -c "import ctypes, sys; print(ctypes.CDLL(sys.argv[1]).svc_abi_version())" "$shared") ||
  fail "ctypes cannot load $shared"
grep -q "#define SVC_ABI_VERSION $abi\b" "$SVC_PREFIX/include/svc/svc.h" ||
  fail "the shared decoder's ABI version $abi is not the installed header's"

# The license travels with the libraries: the text, and the SPDX name in the metadata.
cmp "$source_dir/LICENSE" "$SVC_PREFIX/share/doc/svc/LICENSE" || fail "share/doc/svc/LICENSE is not LICENSE"
for pc in svc-decoder svc; do
  grep -qx 'License: BSD-2-Clause' "$SVC_PREFIX/lib/pkgconfig/$pc.pc" || fail "$pc.pc names no license"
done
grep -q 'set(svc_LICENSE "BSD-2-Clause")' "$SVC_PREFIX/lib/cmake/svc/svcConfig.cmake" ||
  fail "the CMake package names no license"

# The README's recipe, run from a copy of the tree's samples/embed.
recipe=$(awk '/<!-- embed-recipe/ {found = 1; next}
              found && /^```sh/ {inside = 1; next}
              inside && /^```/ {exit}
              inside {print}' "$source_dir/README.md")
[[ -n "$recipe" ]] || fail "no embed recipe found in README.md"
mkdir -p "$work/tree/samples"
cp -r "$source_dir/samples/embed" "$work/tree/samples/embed"
cp -r "$source_dir/samples/embed_c" "$work/tree/samples/embed_c"
if ! (cd "$work/tree" && bash -e -u -o pipefail -c "$recipe") >"$work/recipe.log" 2>&1; then
  cat "$work/recipe.log" >&2
  fail "the README's embed recipe failed"
fi
embed_dir="$work/tree/build-embed"

# Neither build links an image or FFmpeg library: not at run time, not on the link line.
# Both link the static decoder: the shared one is installed for loading at run time only.
for exe in svc-embed-example svc-embed-pc; do
  [[ -x "$embed_dir/$exe" ]] || fail "$exe was not built"
  if ldd "$embed_dir/$exe" | grep -Ei "$image_libs|libsvc"; then fail "$exe loads the libraries above"; fi
done
pc_libs=$(PKG_CONFIG_PATH="$SVC_PREFIX/lib/pkgconfig" pkg-config --libs svc-decoder)
[[ "$pc_libs" == *-lsvc_decoder* ]] || fail "pkg-config --libs svc-decoder lacks -lsvc_decoder: $pc_libs"
if grep -Eiq "$image_libs" <<<"$pc_libs"; then fail "pkg-config --libs svc-decoder: $pc_libs"; fi
cmake_links=$(find "$embed_dir" -name link.txt -o -name build.ninja)
grep -q libsvc_decoder $cmake_links || fail "the CMake build does not link libsvc_decoder"
if grep -Ei "$image_libs" $cmake_links; then fail "the CMake build links the libraries above"; fi

# The decoder component is found where the full library's image libraries are not.
cmake -S "$source_dir/samples/embed" -B "$work/embed-no-images" -DCMAKE_PREFIX_PATH="$SVC_PREFIX" \
      -DCMAKE_DISABLE_FIND_PACKAGE_OpenImageIO=ON -DCMAKE_DISABLE_FIND_PACKAGE_OpenEXR=ON >/dev/null 2>&1 ||
  fail "find_package(svc COMPONENTS decoder) needs OpenImageIO or OpenEXR"

# Both builds decode the same cell of a real file: the first, then (1,0,1) by the world
# position of its centre, from the grid origin and spacing that `svc info` prints.
"$build_dir/bin/svc-scene" "$work/db" --grid 2,1,2 --face-size 32 --quiet
"$build_dir/bin/svc" encode "$work/db" -o "$work/db.svc" -q 75 --quiet
read -r x y z <<<"$(cell_position "$build_dir/bin/svc" "$work/db.svc" 1 0 1)"
for exe in svc-embed-example svc-embed-pc; do
  out=$("$embed_dir/$exe" "$work/db.svc")
  echo "$exe: $out"
  [[ "$out" == "cell 0,0,0: 6 faces of 32x32, checksum "* ]] || fail "$exe: $out"
  out_at=$("$embed_dir/$exe" "$work/db.svc" "$x" "$y" "$z")
  echo "$exe: $out_at"
  [[ "$out_at" == "cell 1,0,1: 6 faces of 32x32, checksum "* ]] || fail "$exe: $out_at"
  [[ "$out_at" != "${out/cell 0,0,0/cell 1,0,1}" ]] || fail "$exe: cells 0,0,0 and 1,0,1 decode alike"
  outputs+=("$out $out_at")
done
[[ "${outputs[0]}" == "${outputs[1]}" ]] || fail "the CMake and pkg-config builds decode differently"

# The C example, built both ways against the moved install, writes the cube the build
# tree's copy writes (itself checked against the C++ reader by tests/svc_c_api_test.cc).
embed_c_dir="$work/tree/build-embed-c"
"$build_dir/bin/svc-embed-c" "$work/db.svc" "$work/cube-tree.rgba" "$x" "$y" "$z" >/dev/null
for exe in svc-embed-c svc-embed-c-pc; do
  [[ -x "$embed_c_dir/$exe" ]] || fail "$exe was not built"
  if ldd "$embed_c_dir/$exe" | grep -Ei "$image_libs"; then fail "$exe loads the libraries above"; fi
  out=$("$embed_c_dir/$exe" "$work/db.svc" "$work/cube-$exe.rgba" "$x" "$y" "$z")
  [[ "$out" == "cell 1,0,1: 6 faces of 32x32" ]] || fail "$exe: $out"
  cmp "$work/cube-tree.rgba" "$work/cube-$exe.rgba" || fail "$exe decodes differently from the build tree's"
done

# The full library through pkg-config alone (no --static): encodes what the tool encodes.
cat >"$work/encode.cc" <<'EOF'
#include <cstdio>
#include <svc/encoder.h>
int main(int argc, char** argv) {
  if (argc != 3) return 2;
  svc::EncoderSettings settings;
  settings.quality = 75;
  auto summary = svc::encode_database(argv[1], argv[2], settings);
  if (!summary.ok()) std::fprintf(stderr, "%s\n", summary.status().to_string().c_str());
  return summary.ok() ? 0 : 1;
}
EOF
eval "c++ -O2 \"$work/encode.cc\" -o \"$work/encode\" $(PKG_CONFIG_PATH="$SVC_PREFIX/lib/pkgconfig" pkg-config --cflags --libs svc)"
"$work/encode" "$work/db" "$work/db-installed.svc"
cmp "$work/db.svc" "$work/db-installed.svc" || fail "the installed libsvc encodes different bytes"
# The check above would see the image libraries: the full library does load them.
# grep reads all of ldd's output: with -q it could stop early and fail the pipe (pipefail).
ldd "$work/encode" | grep OpenImageIO >/dev/null || fail "ldd shows no OpenImageIO in a libsvc program"

# The installed, moved tool works too.
"$SVC_PREFIX/bin/svc" verify "$work/db.svc" --quiet
echo "install test passed"
