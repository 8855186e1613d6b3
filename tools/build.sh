#!/usr/bin/env bash
# Configures and builds Jawari (Release, this machine's vector units) into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$(nproc)"
