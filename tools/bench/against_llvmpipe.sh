#!/usr/bin/env bash
# pelt against the llvmpipe harness (../shared/anchors/llvmpipe in the workplace, not part of
# pelt): the same scene (`pelt bench fps --match-llvmpipe`) drawn by both, one run after the
# other, for a few rounds, so that each round's ratio is measured in one phase of a shared,
# noisy machine. Prints each round's FPS and ratio, then the median ratio of each scene.
#
#   tools/bench/against_llvmpipe.sh HARNESS_DIR [options]
#     HARNESS_DIR     the harness's folder; its build/fur_bench is built with `make` if missing
#     --scenes LIST   box,teapot,teapot2 (default: box)
#     --threads N     threads for both (pelt --threads, llvmpipe LP_NUM_THREADS; default 2)
#     --rounds N      alternations (default 3)
#     --frames N      timed frames a run (default 30; the harness also runs at least 2 s)
#     --width W --height H   image size (default 1024x768)
#     --pelt PATH     the pelt binary (default: build/pelt beside this script's repository)
#     --simd T        pelt's SIMD target (pelt --simd; default: the best this CPU runs). llvmpipe
#                     draws with 256-bit vectors on any CPU, so `--simd avx2` compares the two at
#                     one vector width; each round names the target pelt ran on.
# Exit 2 on a bad argument or a harness that cannot be built or run (its output is shown).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)

fail() {
  echo "against_llvmpipe: $*" >&2
  exit 2
}
positive() {  # positive NAME VALUE
  [[ $2 =~ ^[1-9][0-9]*$ ]] || fail "$1: \`$2\` is not a positive integer"
}

[[ $# -ge 1 ]] || fail "usage: tools/bench/against_llvmpipe.sh HARNESS_DIR [--scenes box,teapot,teapot2] [--threads N] [--rounds N] [--frames N] [--width W] [--height H] [--pelt PATH] [--simd T]"
harness=$1
shift
scenes=box threads=2 rounds=3 frames=30 width=1024 height=768 pelt="$root/build/pelt" simd=auto
while [[ $# -gt 0 ]]; do
  [[ $# -ge 2 ]] || fail "$1: needs a value"
  case $1 in
    --scenes) scenes=$2 ;;
    --threads) positive "$1" "$2"; threads=$2 ;;
    --rounds) positive "$1" "$2"; rounds=$2 ;;
    --frames) positive "$1" "$2"; frames=$2 ;;
    --width) positive "$1" "$2"; width=$2 ;;
    --height) positive "$1" "$2"; height=$2 ;;
    --pelt) pelt=$2 ;;
    --simd) [[ -n $2 ]] || fail "--simd: needs a target"; simd=$2 ;;
    *) fail "unknown option \`$1\`" ;;
  esac
  shift 2
done
IFS=, read -r -a scene_list <<<"$scenes"
[[ ${#scene_list[@]} -gt 0 ]] || fail "--scenes: no scene given (box, teapot, teapot2)"
for s in "${scene_list[@]}"; do
  [[ $s == box || $s == teapot || $s == teapot2 ]] || fail "--scenes: unknown scene \`$s\` (box, teapot, teapot2)"
done
[[ -d $harness ]] || fail "$harness: no such folder (the llvmpipe harness)"
[[ -x $pelt ]] || fail "$pelt: no pelt binary (build pelt first, or give --pelt)"
bench="$harness/build/fur_bench"
if [[ ! -x $bench ]]; then
  make -C "$harness" >&2 || fail "$harness: make failed"
  [[ -x $bench ]] || fail "$bench: make did not build it"
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# pelt's median FPS of one run (its --json fps_median) and the SIMD target it ran on ("simd").
pelt_fps() {
  "$pelt" bench fps --match-llvmpipe --scenes "$1" --threads "$threads" --width "$width" --height "$height" \
    --frames "$frames" --warmup 5 --simd "$simd" --json "$tmp/pelt.json" >"$tmp/pelt.out" 2>&1 || {
    cat "$tmp/pelt.out" >&2
    fail "pelt bench fps failed on $1"
  }
  local fps target
  fps=$(sed -n 's/^ *"fps_median": *\([0-9.eE+-]*\),*$/\1/p' "$tmp/pelt.json" | head -n 1)
  [[ -n $fps ]] || fail "$tmp/pelt.json: no fps_median"
  target=$(sed -n 's/^ *"simd": *"\([a-z0-9]*\)",*$/\1/p' "$tmp/pelt.json" | head -n 1)
  [[ -n $target ]] || fail "$tmp/pelt.json: no simd"
  echo "$fps $target"
}

# The harness's median FPS of one run (median_fps of its RESULT line).
llvmpipe_fps() {
  # The teapots are tessellated from the patches pelt ships (the same file as the harness's data folder,
  # which a copied harness no longer finds beside its binary).
  LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=llvmpipe LP_NUM_THREADS=$threads "$bench" bench --scene "$1" \
    --width "$width" --height "$height" --warmup 5 --frames "$frames" --min-seconds 2 --reps 3 \
    --bpt "$root/tools/data/teapot.bpt" >"$tmp/gl.out" 2>&1 || {
    cat "$tmp/gl.out" >&2
    fail "$bench failed on $1"
  }
  local fps
  fps=$(sed -n 's/^RESULT .*median_fps=\([0-9.]*\).*$/\1/p' "$tmp/gl.out" | tail -n 1)
  [[ -n $fps ]] || { cat "$tmp/gl.out" >&2; fail "$bench printed no RESULT line with median_fps"; }
  awk -v g="$fps" 'BEGIN { exit !(g > 0) }' || { cat "$tmp/gl.out" >&2; fail "$bench reported $fps FPS on $1"; }
  echo "$fps"
}

echo "pelt against llvmpipe: ${width}x${height}, $threads thread(s), $frames frames a run, $rounds round(s)"
for s in "${scene_list[@]}"; do
  ratios=()
  for ((r = 1; r <= rounds; r++)); do
    pt=$(pelt_fps "$s")
    p=${pt% *} target=${pt#* }
    g=$(llvmpipe_fps "$s")
    ratio=$(awk -v p="$p" -v g="$g" 'BEGIN { printf "%.2f", p / g }')
    ratios+=("$ratio")
    printf '%s round %d: pelt %.1f FPS (%s), llvmpipe %.2f FPS: %sx\n' "$s" "$r" "$p" "$target" "$g" "$ratio"
  done
  printf '%s\n' "${ratios[@]}" | sort -g | awk -v s="$s" '{ v[NR] = $1 }
    END { m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
          printf "%s: median %.2fx (from %.2fx to %.2fx over %d rounds)\n", s, m, v[1], v[NR], NR }'
done
