#!/usr/bin/env bash
# Installs svc into a temporary prefix, builds samples/embed against the installed
# CMake package and checks the pkg-config file, then runs the example on a small
# database: by first cell and by world position.
set -euo pipefail
build_dir=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cmake --install "$build_dir" --prefix "$work/prefix" >/dev/null
cmake -S "$source_dir/samples/embed" -B "$work/embed" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/embed" >/dev/null

PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig:${PKG_CONFIG_PATH:-}" pkg-config --cflags --libs svc | grep -q -- "-lsvc"

"$build_dir/bin/svc-scene" "$work/db" --grid 2,1,2 --face-size 32 --quiet
"$build_dir/bin/svc" encode "$work/db" -o "$work/db.svc" --quiet
out=$("$work/embed/svc-embed-example" "$work/db.svc")
echo "$out"
[[ "$out" == "cell 0,0,0: 6 faces of 32x32, checksum "* ]]
# Cell lookup by world position through the installed library: the centre of cell
# (1,0,1) from the grid origin and spacing that `svc info` prints.
grid=$("$build_dir/bin/svc" info "$work/db.svc" | grep -o 'origin [^ ]*, spacing [^ ]*,')
IFS=', ' read -r _ ox oy oz _ sx sy sz <<<"$(echo "$grid" | tr ',' ' ')"
x=$(awk "BEGIN{print $ox + $sx}"); y=$oy; z=$(awk "BEGIN{print $oz + $sz}")
out=$("$work/embed/svc-embed-example" "$work/db.svc" "$x" "$y" "$z")
echo "$out"
[[ "$out" == "cell 1,0,1: 6 faces of 32x32, checksum "* ]]
# The installed tool works too.
"$work/prefix/bin/svc" verify "$work/db.svc" --quiet
echo "install test passed"
