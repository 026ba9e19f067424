#!/usr/bin/env bash
# Builds Tumble and its tests with AddressSanitizer and UndefinedBehaviorSanitizer into
# ${TUMBLE_BUILD:-build-asan} and runs the test binaries under them: the serial unit tests, then
# the MPI ones on 2 ranks. With ALL=1 the whole ctest suite follows (the CLI and campaign scripts
# then drive the sanitized `tumble`). Exit 0 when no sanitizer said anything; each binary's log is
# kept in the build folder (sanitize_<name>.log).
#
# Not part of .ci/run: on this project's 2-core VM the build takes ~25 min and the tests run 2-20x
# slower than the Release build's (docs/guarantees.md, "Sanitizers", has the last run's figures).
# LeakSanitizer is off: Open MPI and HDF5 keep allocations until exit by design, and their
# reports (thousands of frames without symbols) would hide Tumble's own.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${TUMBLE_BUILD:-build-asan}
export ASAN_OPTIONS=detect_leaks=0:halt_on_error=0:abort_on_error=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=0
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -O1 -g"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > "$build.configure.log" 2>&1 ||
  { cat "$build.configure.log"; exit 1; }
# (gtest_discover_tests runs each test binary at build time: ASAN_OPTIONS above keeps its leak
# report from failing the build)
cmake --build "$build" -j "$(nproc)"

said=0
check() {  # name, then the command; counts the sanitizer reports in its log
  local name=$1 log="$build/sanitize_$1.log" rc=0
  shift
  local t0=$SECONDS
  "$@" > "$log" 2>&1 || rc=$?
  local n
  n=$(grep -c "ERROR: AddressSanitizer\|runtime error:" "$log" || true)
  echo "[sanitize] $name: exit $rc, $n sanitizer reports, $((SECONDS - t0)) s ($log)"
  if [ "$n" -gt 0 ]; then
    grep -m 5 -A 3 "ERROR: AddressSanitizer\|runtime error:" "$log"
    said=1
  fi
  [ "$rc" -eq 0 ] || said=1
}
check campaign "$build/tests/campaign/test_campaign"
check analysis "$build/tests/analysis/test_analysis"
check cm "$build/tests/cm/test_cm"
check dem "$build/tests/test_dem"
check parallel_mpi2 mpiexec -n 2 "$build/tests/parallel/test_parallel"
check extra_field_mpi2 mpiexec -n 2 "$build/tests/parallel/test_extra_field"
if [ "${ALL:-0}" = 1 ]; then
  check ctest ctest --test-dir "$build" --output-on-failure -j 2
fi
exit "$said"
