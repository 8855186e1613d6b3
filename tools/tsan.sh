#!/usr/bin/env bash
# The second core's hand-over under ThreadSanitizer: builds the real-time engine and
# jawari-second-core-tests with -fsanitize=thread (build-tsan/, without JUCE) and runs them. Any
# data race reported fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/deps.sh
flags="-fsanitize=thread -fno-omit-frame-pointer"
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DJAWARI_BUILD_RENDERER=OFF -DJAWARI_LTO=OFF \
      -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" > /dev/null
cmake --build build-tsan -j "$(nproc)" --target jawari-second-core-tests
TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" ./build-tsan/Tests/jawari-second-core-tests
