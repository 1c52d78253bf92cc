#!/usr/bin/env bash
# Installs what is missing (every profile of scripts/install-deps.sh), builds,
# and runs the whole test suite:
#  1. the Release build (g++, warnings as errors) and every test, the tests
#     that run a node's threads also against the node library under
#     ThreadSanitizer (label "tsan");
#  2. a clang build with AddressSanitizer and UndefinedBehaviorSanitizer, the
#     unit and loopback integration tests under it, and the protocol fuzzer
#     for a bounded time (RAILCOSIM_FUZZ_SECONDS, default 60);
#  3. clang-tidy with the checks of .clang-tidy over every source of the
#     libraries and programs.
# The benchmarks are not built here (no test runs them; scripts/run-main.sh
# builds them, and not the tests), and the libraries compile in batches
# (RAILCOSIM_UNITY, scripts/build.sh), which keeps the suite inside CI's time. RAILCOSIM_QUICK=1 stops after stage 1.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh --all  # every profile: the suite covers the FE and Green's-function soils
scripts/build.sh -DRAILCOSIM_BUILD_TESTS=ON -DRAILCOSIM_BUILD_BENCH=OFF
(cd build && ctest --output-on-failure -j "$(nproc)")

[[ "${RAILCOSIM_QUICK:-0}" == 1 ]] && exit 0

echo "== sanitizer build (AddressSanitizer, UndefinedBehaviorSanitizer) and fuzzer"
CXX=clang++ cmake -S . -B build-san -DCMAKE_BUILD_TYPE= -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" \
  -DRAILCOSIM_WERROR=ON \
  -DRAILCOSIM_SANITIZE=ON -DRAILCOSIM_FUZZ=ON -DRAILCOSIM_BUILD_BENCH=OFF -DRAILCOSIM_UNITY=ON >/dev/null
# The sanitized tests are listed once, in tests/CMakeLists.txt (label
# "sanitized"); the target sanitized_tests builds them and the programs they start.
cmake --build build-san -j "$(nproc)" --target sanitized_tests session_fuzz
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
# Every sanitized case runs, all nine paper cases over TCP and every case of
# the lock step among them.
(cd build-san && ctest --output-on-failure -j "$(nproc)" -L sanitized)

corpus=$(mktemp -d)
trap 'rm -rf "$corpus"' EXIT
# New corpus entries go to a temporary folder; a failing input is kept in
# build-san/fuzz-artifacts/ and the fuzzer's report is printed in full.
mkdir -p build-san/fuzz-artifacts
if ! build-san/bin/session_fuzz -max_total_time="${RAILCOSIM_FUZZ_SECONDS:-60}" -timeout=25 \
  -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix=build-san/fuzz-artifacts/ \
  "$corpus" tests/fuzz/corpus >build-san/fuzz.log 2>&1; then
  cat build-san/fuzz.log
  echo "fuzzer: FAILED (input kept in build-san/fuzz-artifacts/)"
  exit 1
fi
tail -n 6 build-san/fuzz.log
echo "fuzzer: no crash, leak or timeout in ${RAILCOSIM_FUZZ_SECONDS:-60} s"

echo "== clang-tidy (.clang-tidy) over the libraries and programs"
# On the sanitizer build's compile database (clang's flags; its protocol
# headers are generated): each library's batches, which include its sources,
# so every source is checked with the headers it shares parsed once per
# batch; a finding names the source file and line.
run-clang-tidy -quiet -p build-san -j "$(nproc)" 'Unity/unity_[0-9]+_cxx\.cxx$|/(master|[a-z]+_node)/main\.cpp$' \
  >build-san/tidy.log 2>&1 ||
  { grep -E "(warning|error):" build-san/tidy.log | sort -u; echo "clang-tidy: FAILED"; exit 1; }
echo "clang-tidy: no finding"
