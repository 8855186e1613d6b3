#!/usr/bin/env bash
# The second command of the README: installs what is missing, builds, and runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/deps.sh
bash tools/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
bash tools/tsan.sh  # the second core's hand-over under ThreadSanitizer
