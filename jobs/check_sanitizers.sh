#!/usr/bin/env bash
# Every test against a build with AddressSanitizer and UndefinedBehaviorSanitizer (GCC's), in
# ${TUMBLE_ASAN_BUILD:-build-asan}: a read or write out of bounds, a use after free, signed
# overflow or a misaligned load anywhere a test reaches stops that test with the sanitizer's report.
# Not part of .ci/run (a second full build and ~2-3x slower tests do not fit its 25 minutes on 2
# cores); run it after a change to memory handling, MPI buffers or the command line:
#   bash jobs/check_sanitizers.sh [ctest arguments, e.g. -R cli]
# Leak checking is off: Open MPI and HDF5 keep allocations until exit by design, thousands of
# reports that would hide Tumble's own. cli.cm_robustness is left out: it asserts that the memory
# estimates cover what a run adds, which the sanitizers' shadow memory breaks by construction. A
# test that times out under the sanitizers' slowdown is not a finding; the log is searched for
# "ERROR: AddressSanitizer" and "runtime error:". Exit 0: every test passed, no report.
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/install_deps.sh
build=${TUMBLE_ASAN_BUILD:-build-asan}
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
export ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > "$build.configure.log" 2>&1 ||
  { cat "$build.configure.log"; exit 1; }
cmake --build "$build" -j "$(nproc)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd "$build"
status=0
ctest --output-on-failure --timeout 1500 -j "$(nproc)" -E '^cli\.cm_robustness$' "$@" 2>&1 |
  tee ctest-sanitizers.log ||
  status=$?
reports=$(grep -c "ERROR: AddressSanitizer\|runtime error:" ctest-sanitizers.log || true)
echo "sanitizer reports in $build/ctest-sanitizers.log: $reports"
[ "$reports" -eq 0 ] || exit 1
exit "$status"
