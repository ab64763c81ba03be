#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang++-14 (-fsanitize=fuzzer,address,undefined)
# in their own build directory and runs each for a fixed number of inputs.
#
#   bash cmake/run-fuzzers.sh [RUNS]        RUNS inputs per target (default 20000)
#
# Environment: TESSERA_FUZZ_BUILD_DIR (default build/fuzz), TESSERA_FUZZ_SEED (libFuzzer -seed,
# default 1, so a run is reproducible), TESSERA_FUZZ_MAX_TIME (seconds per target, default 900:
# a safety cap; a target stopped by it is reported, not failed), TESSERA_FUZZ_TARGETS (subset).
# The shipped seed corpora (tests/fuzz/corpus/<name>/) are read only; inputs the fuzzer finds
# interesting go to <build>/corpus/<target>/ and crashing inputs to <build>/findings/.
# Exit status: non-zero when any target reports a crash, sanitizer error, timeout or leak.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
runs="${1:-20000}"
[[ "$runs" =~ ^[0-9]+$ ]] || { echo "run-fuzzers: RUNS must be a non-negative integer, got '$runs'" >&2; exit 2; }
build="${TESSERA_FUZZ_BUILD_DIR:-$root/build/fuzz}"
seed="${TESSERA_FUZZ_SEED:-1}"
max_time="${TESSERA_FUZZ_MAX_TIME:-900}"
targets=(${TESSERA_FUZZ_TARGETS:-fuzz_tess_reader fuzz_tessellation fuzz_clip fuzz_cli})

bash "$root/cmake/install-deps.sh" --fuzz
CXX=clang++-14 cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTESSERA_BUILD_TESTS=OFF -DTESSERA_BUILD_EXAMPLES=OFF -DTESSERA_BUILD_BENCHMARKS=OFF \
  -DTESSERA_USE_OPENMP=OFF -DTESSERA_BUILD_FUZZERS=ON >/dev/null
cmake --build "$build" --target "${targets[@]}" -j2

declare -A corpus=([fuzz_tess_reader]=tess [fuzz_tessellation]=tessellation [fuzz_clip]=clip [fuzz_cli]=cli)
mkdir -p "$build/findings"
failed=()
for t in "${targets[@]}"; do
  work="$build/corpus/$t"
  mkdir -p "$work"
  log="$build/$t.log"
  echo "run-fuzzers: $t: $runs runs (seed $seed, cap ${max_time}s), log $log"
  start=$SECONDS
  set +e
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ASAN_OPTIONS=detect_leaks=1 \
    "$build/tests/fuzz/$t" -runs="$runs" -seed="$seed" -max_total_time="$max_time" -timeout=20 \
    -rss_limit_mb=2048 -max_len=8192 -print_final_stats=1 -artifact_prefix="$build/findings/$t-" \
    "$work" "$root/tests/fuzz/corpus/${corpus[$t]}" >"$log" 2>&1
  rc=$?
  set -e
  done_runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  echo "run-fuzzers: $t: exit $rc, $done_runs inputs executed in $((SECONDS - start)) s"
  if ((rc != 0)); then
    failed+=("$t")
    grep -E 'ERROR|runtime error|tessera fuzz finding|Test unit written|deadly signal|uncaught' "$log" | head -20 >&2 || true
  elif [[ "$done_runs" != "?" ]] && ((done_runs < runs)); then
    echo "run-fuzzers: $t: stopped by the ${max_time}s cap before $runs runs" >&2
  fi
done
if ((${#failed[@]})); then
  echo "run-fuzzers: findings in ${failed[*]} (inputs in $build/findings/)" >&2
  exit 1
fi
echo "run-fuzzers: no findings"
