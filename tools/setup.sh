#!/usr/bin/env bash
# The first command of the README: installs what is missing, builds, and renders the default
# scene (the paper's centre obstacle) to out/paper-centre.wav with its energy log.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/deps.sh
bash tools/build.sh
mkdir -p out
./build/bin/jawari-render Resources/Scenes/paper-centre.json -o out/paper-centre.wav --energy out/paper-centre-energy.csv
echo "rendered out/paper-centre.wav"
