#!/usr/bin/env bash
# Builds the scene-reader fuzz target with clang (libFuzzer + AddressSanitizer + UBSan) in build-fuzz/ and runs
# it for a bounded time (default 120 s) on a seed corpus of the example scenes. Prints executions and findings.
#   bash tests/fuzz/run_fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-120}
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
      -DVITRUM_BUILD_FUZZ=ON -DVITRUM_BUILD_TESTS=OFF -DVITRUM_BUILD_BENCH=OFF > /dev/null
cmake --build build-fuzz -j "$(nproc)" --target fuzz_scene_reader
corpus=build-fuzz/corpus
mkdir -p "$corpus" build-fuzz/findings
cp examples/*.toml "$corpus"/
./build-fuzz/fuzz_scene_reader "$corpus" -max_total_time="$seconds" -max_len=4096 -timeout=10 \
    -artifact_prefix=build-fuzz/findings/ -print_final_stats=1 2>&1 | tail -25
echo "findings: $(ls build-fuzz/findings | wc -l) (in build-fuzz/findings/)"
