#!/usr/bin/env bash
# Writes the speed/accuracy, stability and scaling charts (CSV + PNG) into Resources/Charts/.
# Every configuration is measured side by side in this one run (the machines are noisy: compare
# ratios within a run). Takes a few minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/deps.sh
bash tools/build.sh
bash tools/deps.sh python3-matplotlib  # the plots
mkdir -p Resources/Charts
./build/Tests/jawari-accuracy Resources/Charts/accuracy.csv
./build/Tests/jawari-stability Resources/Charts/stability.csv
./build/Tests/jawari-scaling Resources/Charts/scaling.csv
./build/Tests/jawari-polyphony Resources/Charts/polyphony.csv
/usr/bin/python3 tools/plot_charts.py Resources/Charts
