#!/usr/bin/env bash
# Configures (Release) and builds Tumble into ${TUMBLE_BUILD:-build}.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${TUMBLE_BUILD:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release > "$build.configure.log" 2>&1 || { cat "$build.configure.log"; exit 1; }
cmake --build "$build" -j "$(nproc)"
