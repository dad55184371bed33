# SPDX-License-Identifier: BSD-2-Clause
# Sourced by the shell tests (bash, set -euo pipefail): `work`, a scratch folder removed
# on exit, and `fail`, which prefixes its message with $test_name (set it first).
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() {
  echo "$test_name: $*" >&2
  exit 1
}

# Writes $work/flaky-svc: runs $1 (the real svc) and logs each call's arguments to
# $work/runs.log, but fails shard 2 of 3 while $work/broken exists.
write_flaky_svc() {
  cat >"$work/flaky-svc" <<FLAKY
#!/usr/bin/env bash
echo "\$*" >>"$work/runs.log"
if [[ -e "$work/broken" && " \$* " == *" --shard 2/3 "* ]]; then echo "shard 2 broke" >&2; exit 1; fi
exec "$1" "\$@"
FLAKY
  chmod +x "$work/flaky-svc"
}

# Prints "X Y Z", the world position of the centre of grid cell (I, J, K) of FILE.svc, from
# the grid origin and spacing that `svc info` prints. Usage: cell_position SVC FILE I J K
cell_position() {
  local grid ox oy oz sx sy sz
  grid=$("$1" info "$2" | grep -o 'origin [^ ]*, spacing [^ ]*,')
  IFS=', ' read -r _ ox oy oz _ sx sy sz <<<"$(echo "$grid" | tr ',' ' ')"
  awk "BEGIN{print $ox + $3 * $sx, $oy + $4 * $sy, $oz + $5 * $sz}"
}
