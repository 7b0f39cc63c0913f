#!/usr/bin/env bash
# Runs the benchmark suite (vitrum_bench, built from bench/*.cpp) and records the results with the machine
# they were measured on. Used by `make bench`; see bench/README.md for the reading of the numbers.
#
#   THREADS    OpenMP threads (default 2)
#   BUILD      build directory (default build); the script builds target vitrum_bench there if it is missing
#   MIN_TIME   --benchmark_min_time in seconds (default 0.2; benchmark 1.7.1 takes a plain number)
#   FILTER     optional --benchmark_filter regex
#   REPS       --benchmark_repetitions (default 1)
#   NAME       result name (default kernels); e.g. NAME=packing FILTER=Pack for the packing benchmarks only
#
# Writes bench/results/${NAME}_${THREADS}t.json (Google Benchmark JSON) and the machine record next to it,
# bench/results/machine_${THREADS}t.txt for NAME=kernels, machine_${NAME}_${THREADS}t.txt otherwise (CPU
# model, core count, compiler, commit, binary date, load average, other processes' CPU share during the run).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

THREADS="${THREADS:-2}"
BUILD="${BUILD:-build}"
MIN_TIME="${MIN_TIME:-0.2}"
FILTER="${FILTER:-}"
REPS="${REPS:-1}"
NAME="${NAME:-kernels}"
BIN="${BUILD}/bench/vitrum_bench"
RESULTS="bench/results"

if [[ ! -x "${BIN}" ]]; then
    cmake -S . -B "${BUILD}" -DCMAKE_BUILD_TYPE=Release > /dev/null
    cmake --build "${BUILD}" -j "$(nproc)" --target vitrum_bench
fi

mkdir -p "${RESULTS}"
json="${RESULTS}/${NAME}_${THREADS}t.json"
if [[ "${NAME}" == kernels ]]; then
    machine="${RESULTS}/machine_${THREADS}t.txt"
else
    machine="${RESULTS}/machine_${NAME}_${THREADS}t.txt"
fi

{
    echo "date:            $(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "commit:          $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$([[ -z "$(git status --porcelain -- kernels solver bench/*.cpp 2>/dev/null)" ]] || echo ' (+ uncommitted changes in kernels/, solver/ or bench/)')"
    echo "binary:          ${BIN}, built $(date -u -r "${BIN}" +%Y-%m-%dT%H:%M:%SZ)"
    echo "nproc:           $(nproc)"
    echo "model name:      $(lscpu | sed -n 's/^Model name:[[:space:]]*//p')"
    echo "cpu MHz:         $(sed -n 's/^cpu MHz[[:space:]]*:[[:space:]]*//p' /proc/cpuinfo | head -n 1)"
    echo "caches:          $(lscpu | sed -n 's/^\(L[123][di]\{0,1\} cache\):[[:space:]]*/\1 /p' | paste -sd ';' -)"
    echo "memory:          $(free -g | awk '/^Mem:/ {print $2 " GiB"}')"
    echo "compiler:        $(c++ --version | head -n 1)"
    echo "build type:      $(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "${BUILD}/CMakeCache.txt" 2>/dev/null)"
    echo "flags:          $(grep -m 1 '"command": .*bench_kernels\.cpp",$' "${BUILD}/compile_commands.json" 2>/dev/null |
        grep -oE ' -(O[0-9s]|march=[^ ]+|DNDEBUG|fopenmp|ffast-math|std=[^ ]+)' | tr -d '\n') (bench_kernels.cpp, compile_commands.json)"
    echo "OMP_NUM_THREADS: ${THREADS}"
    echo "OMP_PROC_BIND:   ${OMP_PROC_BIND:-(unset)}"
    echo "min_time:        ${MIN_TIME} s"
    echo "load before:     $(cut -d ' ' -f 1-3 /proc/loadavg)"
} > "${machine}"

args=(
    "--benchmark_out=${json}"
    "--benchmark_out_format=json"
    "--benchmark_min_time=${MIN_TIME}"
    "--benchmark_repetitions=${REPS}"
)
if [[ -n "${FILTER}" ]]; then
    args+=("--benchmark_filter=${FILTER}")
fi

# OpenMP kernels are very sensitive to other load on the cores (a descheduled thread stalls the barrier):
# warn when the machine is not quiet, so noisy figures are not mistaken for the kernels' own.
load1="$(cut -d ' ' -f 1 /proc/loadavg)"
if awk -v l="${load1}" 'BEGIN { exit !(l > 0.5) }'; then
    echo "run_benchmarks.sh: warning: 1-minute load average is ${load1}; timings may be noisy" >&2
fi

# Busy CPU time of the whole machine (user+nice+system+irq+softirq, and steal separately) around the run,
# minus the benchmark's own user+system time: the CPU time other processes took while the figures were
# measured, as a fraction of (wall time × cores). Recorded so noisy runs can be recognised afterwards.
cpuTicks() { awk '/^cpu / { print $2 + $3 + $4 + $7 + $8, $9 }' /proc/stat; }
read -r busy0 steal0 < <(cpuTicks)
start_ns="$(date +%s%N)"
timing="$(mktemp)"
TIMEFORMAT='%U %S'
{ time OMP_NUM_THREADS="${THREADS}" "${BIN}" "${args[@]}" 2>&3; } 3>&2 2> "${timing}"
end_ns="$(date +%s%N)"
read -r busy1 steal1 < <(cpuTicks)
read -r own_user own_sys < "${timing}"
rm -f "${timing}"
awk -v b0="${busy0}" -v b1="${busy1}" -v s0="${steal0}" -v s1="${steal1}" -v hz="$(getconf CLK_TCK)" \
    -v u="${own_user}" -v s="${own_sys}" -v t0="${start_ns}" -v t1="${end_ns}" -v cores="$(nproc)" 'BEGIN {
        wall = (t1 - t0) / 1e9
        other = (b1 - b0) / hz - u - s
        if (other < 0) other = 0
        printf "run wall time:   %.1f s\n", wall
        printf "benchmark CPU:   %.1f s user + %.1f s system\n", u, s
        printf "other CPU:       %.1f%% of %d cores (other processes during the run)\n", 100 * other / (wall * cores), cores
        printf "steal:           %.1f%% of %d cores (hypervisor)\n", 100 * (s1 - s0) / hz / (wall * cores), cores
        if (wall < 5) print "                 (shares from clock ticks: not meaningful for runs under a few seconds)"
    }' >> "${machine}"
echo "load after:      $(cut -d ' ' -f 1-3 /proc/loadavg)" >> "${machine}"
echo "wrote ${json} and ${machine}"
