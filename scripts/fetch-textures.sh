#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Extracts a set of game textures into a folder for `svc-scene --textures`, installing
# its Debian package when it is missing.
#
#   scripts/fetch-textures.sh [--set openarena|ufoai] [DIR]
#
# Sets:
#   openarena  Debian openarena-081-textures (about 94 MB): the game's textures, many of
#              them dark and soft; default DIR ~/.cache/svc/textures
#   ufoai      Debian ufoai-textures (about 340 MB): the building, street, material,
#              nature, furniture, door and shop folders of UFO: Alien Invasion, detailed
#              realistic materials at 256-1024 pixels; default DIR ~/.cache/svc/textures-ufoai
#
# Prints the folder on the last line. Quick when DIR already holds the extracted set;
# refuses a DIR that exists with other content, since it replaces the folder whole.
# Several runs at once are safe: one extraction wins, the others find it in place.
set -euo pipefail

set_name=openarena
if [[ "${1:-}" == "--set" ]]; then
  set_name="${2:-}"
  shift 2 || { echo "fetch-textures: --set wants openarena or ufoai" >&2; exit 2; }
fi
cache="${XDG_CACHE_HOME:-$HOME/.cache}/svc"
case "$set_name" in
  openarena)
    package=openarena-081-textures
    archive=/usr/share/games/openarena/baseoa/pak4-textures.pk3
    members=('textures/*')
    default_dir="$cache/textures"
    stamp_name=.extracted-from-pak4-textures
    ;;
  ufoai)
    package=ufoai-textures
    archive=/usr/share/games/ufoai/base/0textures.pk3
    members=()
    for folder in buildings streets material nature furniture doors shop terrain dirt; do
      members+=("textures/tex_$folder/*")
    done
    default_dir="$cache/textures-ufoai"
    stamp_name=.extracted-from-ufoai-0textures
    ;;
  *)
    echo "fetch-textures: unknown set \"$set_name\" (openarena or ufoai)" >&2
    exit 2
    ;;
esac

dir="${1:-$default_dir}"
stamp="$dir/$stamp_name"

if [[ -f "$stamp" ]]; then
  echo "$dir"
  exit 0
fi

if [[ -e "$dir" ]] && [[ -n "$(ls -A "$dir" 2>/dev/null)" || ! -d "$dir" ]]; then
  echo "fetch-textures: $dir exists and was not made by this script; give an empty or new folder" >&2
  exit 1
fi

if [[ ! -f "$archive" ]]; then
  echo "installing $package" >&2
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
  unzip -q -o "$archive" "${members[@]}" -d "$staging"
elif command -v bsdtar >/dev/null; then
  bsdtar -x -f "$archive" -C "$staging" "${members[@]}"
else
  echo "fetch-textures: neither unzip nor bsdtar is installed (apt-get install unzip)" >&2
  exit 1
fi
count=$(find "$staging" -type f \( -iname '*.jpg' -o -iname '*.tga' -o -iname '*.png' \) | wc -l)
touch "$staging/$stamp_name"
rmdir "$dir" 2>/dev/null || true
# -T: never move the staging folder into a folder another run has put in place.
if ! mv -T "$staging" "$dir" 2>/dev/null; then
  if [[ -f "$stamp" ]]; then
    echo "$dir"
    exit 0
  fi
  echo "fetch-textures: could not move the extracted set to $dir" >&2
  exit 1
fi
trap - EXIT
echo "extracted $count textures" >&2
echo "$dir"
