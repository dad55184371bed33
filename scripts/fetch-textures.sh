#!/usr/bin/env bash
# Extracts the OpenArena game textures (Debian package openarena-081-textures) into a
# folder for `svc-scene --textures`, installing the package when it is missing.
#
#   scripts/fetch-textures.sh [DIR]     (default: ~/.cache/svc/textures)
#
# Prints the folder on the last line. Quick when DIR already holds the extracted set;
# refuses a DIR that exists with other content, since it replaces the folder whole.
set -euo pipefail

dir="${1:-${XDG_CACHE_HOME:-$HOME/.cache}/svc/textures}"
package=openarena-081-textures
archive=/usr/share/games/openarena/baseoa/pak4-textures.pk3
stamp="$dir/.extracted-from-pak4-textures"

if [[ -f "$stamp" ]]; then
  echo "$dir"
  exit 0
fi

if [[ -e "$dir" ]] && [[ -n "$(ls -A "$dir" 2>/dev/null)" || ! -d "$dir" ]]; then
  echo "fetch-textures: $dir exists and was not made by this script; give an empty or new folder" >&2
  exit 1
fi

if [[ ! -f "$archive" ]]; then
  echo "installing $package (about 94 MB)" >&2
  sudo=""
  if [[ $(id -u) != 0 ]]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq "$package" >/dev/null
fi
if [[ ! -f "$archive" ]]; then
  echo "fetch-textures: $archive is missing after installing $package" >&2
  exit 1
fi

# Extract beside the target and rename at the end, so an interrupted run leaves no
# half-filled folder that looks complete.
parent="$(dirname "$dir")"
mkdir -p "$parent"
staging="$(mktemp -d "$parent/.textures-XXXXXX")"
trap 'rm -rf "$staging"' EXIT
if command -v unzip >/dev/null; then
  unzip -q -o "$archive" 'textures/*' -d "$staging"
elif command -v bsdtar >/dev/null; then
  bsdtar -x -f "$archive" -C "$staging" 'textures/*'
else
  echo "fetch-textures: neither unzip nor bsdtar is installed (apt-get install unzip)" >&2
  exit 1
fi
count=$(find "$staging" -type f \( -iname '*.jpg' -o -iname '*.tga' \) | wc -l)
touch "$staging/$(basename "$stamp")"
rmdir "$dir" 2>/dev/null || true
mv "$staging" "$dir"
trap - EXIT
echo "extracted $count textures" >&2
echo "$dir"
