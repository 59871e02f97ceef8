#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan, coverage on every pelt library) in
# build-fuzz and runs each for SECONDS (default 60) on its seed corpus. A crash stops that
# target and leaves its input as build-fuzz/fuzz/crash-* / leak-* / timeout-*; copy it into
# tests/fuzz/regressions/<target>/ so fuzz_replay_test replays it (see docs/robustness.md).
# Usage: tools/fuzz.sh [SECONDS] [TARGET...]   (targets: obj fur gltf scene raster sampler)
set -euo pipefail
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(obj fur gltf scene raster sampler)
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build-fuzz
jobs=${PELT_FUZZ_JOBS:-2}

command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ not found (apt-get install clang libfuzzer-14-dev)" >&2; exit 2; }
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link" \
  -DPELT_SANITIZE=address,undefined -DPELT_FUZZ=ON -DPELT_BUILD_TESTS=OFF -DPELT_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build" -j"$jobs" --target $(printf 'fuzz_%s ' "${targets[@]}")

# Seed corpora: the shipped scenes and meshes plus the small hand-made seeds and every
# regression input. The corpus folders persist, so later runs start where earlier ones ended.
seed() {  # seed TARGET FILE...
  mkdir -p "$build/corpus/$1"
  shift_target=$1; shift
  for f in "$@"; do [ -f "$f" ] && cp -n "$f" "$build/corpus/$shift_target/" || true; done
}
seed obj "$root"/tools/data/bunny.obj "$root"/tests/fuzz/seeds/obj/* "$root"/tests/fuzz/regressions/obj/*
seed fur "$root"/tools/data/bunny.obj "$root"/tests/fuzz/seeds/obj/* "$root"/tests/fuzz/regressions/fur/*
seed gltf "$root"/tools/data/BoxTextured.glb "$root"/tests/fuzz/seeds/gltf/* "$root"/tests/fuzz/regressions/gltf/*
seed scene "$root"/tools/scenes/*.json "$root"/tests/fuzz/regressions/scene/*
seed raster "$root"/tests/fuzz/seeds/raster/* "$root"/tests/fuzz/regressions/raster/*
seed sampler "$root"/tests/fuzz/seeds/sampler/* "$root"/tests/fuzz/regressions/sampler/*

status=0
for t in "${targets[@]}"; do
  echo "== fuzz_$t: ${seconds} s"
  log=$build/fuzz/fuzz_$t.log
  # -max_len bounds the mutated inputs (bunny.obj alone is 110 KB); -rss_limit_mb catches blow-ups.
  # PELT_FUZZ_ARGS adds libFuzzer flags, e.g. "-fork=1 -ignore_crashes=1" to keep going past a crash.
  if (cd "$build/fuzz" && ./fuzz_$t -max_total_time="$seconds" -max_len=16384 -rss_limit_mb=2048 ${PELT_FUZZ_ARGS:-} \
        -timeout=20 -print_final_stats=1 "$build/corpus/$t" >"$log" 2>&1); then
    grep -E '^stat::number_of_executed_units|^stat::peak_rss_mb' "$log" | tr '\n' ' '; echo
  else
    status=1
    echo "fuzz_$t FAILED: see $log"; grep -E 'ERROR|==[0-9]+==|Test unit written' "$log" | head -5
  fi
done
exit $status
