#!/usr/bin/env bash
# Regenerates the "What accuracy costs" section of README.md: rebuilds pelt (Release), runs
# `pelt tradeoff` on the fur benchmark box and teapot2 and the skin head into docs/tradeoff/<scene>/,
# and splices each tradeoff.md between its marker lines in README.md.
#   tools/tradeoff/regenerate.sh [extra pelt tradeoff options, e.g. --width 512 --height 384]
# PELT_BUILD_DIR picks the build folder (default: build). Takes minutes: the reference
# renders 64 samples a pixel in double precision.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$root"
build="${PELT_BUILD_DIR:-build}"

# Keep an existing build folder's generator; a new one uses Ninja when it is installed.
if [[ -f "$build/CMakeCache.txt" ]]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
elif command -v ninja > /dev/null; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
else
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build" -j"$(nproc)" --target pelt

for scene in box_fur teapot2_fur head_skin; do
  grep -qx "<!-- tradeoff:$scene -->" README.md && grep -qx "<!-- /tradeoff:$scene -->" README.md || {
    echo "regenerate.sh: README.md lacks the marker lines <!-- tradeoff:$scene --> / <!-- /tradeoff:$scene -->" >&2
    exit 2
  }
done

for scene in box_fur teapot2_fur head_skin; do
  echo "regenerate.sh: pelt tradeoff tools/scenes/$scene.json" >&2
  "$build/pelt" tradeoff "tools/scenes/$scene.json" -o "docs/tradeoff/$scene" "$@" > /dev/null
done

# Replace what lies between each pair of markers with the scene's tradeoff.md.
tmp="README.md.regenerate-$$"  # beside README.md, so the final mv is a rename
trap 'rm -f "$tmp"' EXIT
awk '
  function splice(scene,   file, line) {
    file = "docs/tradeoff/" scene "/tradeoff.md"
    while ((getline line < file) > 0) print line
    close(file)
  }
  /^<!-- tradeoff:[a-z_]+ -->$/ {
    print
    scene = $0
    sub(/^<!-- tradeoff:/, "", scene)
    sub(/ -->$/, "", scene)
    print ""
    splice(scene)
    print ""
    skipping = 1
    next
  }
  /^<!-- \/tradeoff:[a-z_]+ -->$/ { skipping = 0 }
  !skipping { print }
' README.md > "$tmp"
chmod --reference=README.md "$tmp"
mv "$tmp" README.md
trap - EXIT
echo "regenerate.sh: README.md updated from docs/tradeoff/box_fur, teapot2_fur and head_skin" >&2
