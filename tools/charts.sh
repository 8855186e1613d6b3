#!/usr/bin/env bash
# Writes the speed/accuracy, block load, stability and scaling charts (CSV + PNG) into Resources/Charts/.
# Every configuration is measured side by side in this one run (the machines are noisy: compare
# ratios within a run). Takes a few minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/deps.sh
bash tools/build.sh
bash tools/deps.sh python3-matplotlib  # the plots
mkdir -p Resources/Charts
./build/Tests/jawari-accuracy Resources/Charts/accuracy.csv
./build/Tests/jawari-accuracy Resources/Charts/accuracy-body.csv --body
./build/Tests/jawari-stability Resources/Charts/stability.csv
./build/Tests/jawari-scaling Resources/Charts/scaling.csv
./build/Tests/jawari-polyphony Resources/Charts/polyphony.csv
# Twelve strings at standard (the drone and eight notes plucked again in turn every 0.25 s), 15 s per
# block size and host rate: each block's CPU time against its budget.
rm -f Resources/Charts/block-load.csv
for rate in 44100 48000 96000; do
    for block in 32 64 128 256 512; do
        ./build/Tests/jawari-soak --minutes 0.25 --polyphony 8 --replay 0.25 --rate "$rate" --block "$block" \
            --csv Resources/Charts/block-load.csv > /dev/null
    done
done
/usr/bin/python3 tools/plot_charts.py Resources/Charts
