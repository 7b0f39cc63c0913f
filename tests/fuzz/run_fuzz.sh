#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (libFuzzer + AddressSanitizer + UBSan) in build-fuzz/ and runs one or
# all of them for a bounded time each (default 120 s), starting from the committed corpus and regression inputs
# (tests/fuzz/corpus/<target>, tests/fuzz/regressions/<target>; the scene reader also gets examples/*.toml).
# Prints executions and findings per target and appends them to build-fuzz/fuzz-summary.txt; a finding's input
# is saved in build-fuzz/findings/<target>/ (commit it under tests/fuzz/regressions/<target>/ once fixed).
#   bash tests/fuzz/run_fuzz.sh [TARGET|all] [SECONDS]      e.g.  bash tests/fuzz/run_fuzz.sh packing_file 300
#   bash tests/fuzz/run_fuzz.sh SECONDS                     (the scene reader alone, as before)
# JOBS (default 1) sets the build's parallelism; the build and the runs are nice'd.
set -euo pipefail
cd "$(dirname "$0")/../.."
targets_all="scene_reader packing_file checkpoint_file calibration_file set_override measure_inputs restart_outputs"
if [[ "${1:-}" =~ ^[0-9]+$ ]]; then
    which=scene_reader
    seconds=$1
else
    which=${1:-all}
    seconds=${2:-120}
fi
[ "$which" = all ] && targets=$targets_all || targets=$which
for t in $targets; do
    [[ " $targets_all " == *" $t "* ]] || { echo "run_fuzz.sh: unknown target '$t' (expected one of: $targets_all, all)"; exit 2; }
done

export CMAKE_CXX_COMPILER_LAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER:-$(command -v ccache || true)}
export CMAKE_C_COMPILER_LAUNCHER=${CMAKE_C_COMPILER_LAUNCHER:-$(command -v ccache || true)}
nice -n 10 cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
      -DVITRUM_BUILD_FUZZ=ON -DVITRUM_BUILD_TESTS=OFF -DVITRUM_BUILD_BENCH=OFF > /dev/null
for t in $targets; do
    nice -n 10 cmake --build build-fuzz -j "${JOBS:-1}" --target "fuzz_$t"
done

for t in $targets; do
    corpus=build-fuzz/corpus/$t
    findings=build-fuzz/findings/$t
    mkdir -p "$corpus" "$findings"
    cp -n tests/fuzz/corpus/"$t"/* "$corpus"/ 2>/dev/null || true
    cp -n tests/fuzz/regressions/"$t"/* "$corpus"/ 2>/dev/null || true
    [ "$t" = scene_reader ] && cp -n examples/*.toml "$corpus"/
    dict=()
    [ -f tests/fuzz/"$t".dict ] && dict=(-dict=tests/fuzz/"$t".dict)
    # A recipe uses at most 64 edits of a few bytes each: short inputs, at full length from the start.
    size=(-max_len=8192)
    case $t in packing_file|checkpoint_file) size=(-max_len=512 -len_control=0) ;; esac
    before=$(ls "$findings" | wc -l)
    log=build-fuzz/fuzz-$t.log
    # -rss_limit_mb: a reader that asks for gigabytes on a corrupt size is a finding (out-of-memory). UBSan
    # reports stop the run (halt_on_error), so they are findings too, not lines in the log.
    UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1} OMP_NUM_THREADS=1 nice -n 10 ./build-fuzz/fuzz_"$t" "$corpus" "${dict[@]}" "${size[@]}" -max_total_time="$seconds" \
        -timeout=20 -rss_limit_mb=2560 -artifact_prefix="$findings"/ -print_final_stats=1 \
        > "$log" 2>&1 || true
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
    found=$(( $(ls "$findings" | wc -l) - before ))
    line="$(date -u +%Y-%m-%dT%H:%MZ) $(git rev-parse --short HEAD) $t: ${seconds} s, $runs executions, $found new findings"
    echo "$line" | tee -a build-fuzz/fuzz-summary.txt
    grep -h "FUZZ FINDING\|ERROR: \|SUMMARY: " "$log" | head -5 || true
done
