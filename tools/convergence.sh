#!/usr/bin/env bash
# The reference's refinement study on bridges (docs/measurements.md, "The reference's convergence on
# bridges"): jawari-convergence on sitar-bridge, tanpura-thread and parabola-bridge, every ladder,
# into Resources/Charts/convergence.csv (the successive pairs and the floors), and its chart
# convergence.png. About two CPU hours, each study's renders side by side on every core; renders
# are cached in build/convergence-cache (by scene file and its text), so a second run (or one
# stopped halfway) only renders what is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/deps.sh
bash tools/build.sh
bash tools/deps.sh python3-matplotlib  # the plot
study=./build/Tests/jawari-convergence
cache=(--cache build/convergence-cache)
out=$(mktemp)
# The study's rows without the per-render columns (contact points, path, CPU, Newton, penetration).
run() { "$study" "${cache[@]}" "$@" | grep -E '^(kind|pair|floor),' | cut -d, -f1-6,12-17 >> "$out"; }
for scene in sitar-bridge parabola-bridge tanpura-thread; do
    run --scene "Resources/Scenes/$scene.json" --knobs modes,rate,spacing,modes-fine --extend
    run --scene "Resources/Scenes/$scene.json" --knobs all --no-floor
done
# The modes at L/16032 one rung further (8003), charted with that ladder.
run --scene Resources/Scenes/sitar-bridge.json --knobs '' --no-floor --ladder 4001:2e6:16032,8003:2e6:16032
sed -i '$ s/^pair,sitar-bridge,custom,/pair,sitar-bridge,modes-fine,/' "$out"
run --scene Resources/Scenes/sitar-bridge.json --knobs '' --no-floor --ladder 4001:2e6:16032,4001:4e6:16032,4001:8e6:16032
run --scene Resources/Scenes/tanpura-thread.json --knobs '' --no-floor --ladder 4001:2e6:1002,4001:4e6:1002,4001:8e6:1002,4001:16e6:1002
# The modes and the rate together (the rate as M^2) on the point contacts, and sitar-bridge's
# converged configuration refined once in each knob.
run --scene Resources/Scenes/paper-tanpura.json --knobs joint --no-floor
run --scene Resources/Scenes/tanpura-thread.json --knobs '' --no-floor --ladder 4001:32e6:1002,4001:64e6:1002,8003:128e6:1002
# The rate extrapolated: the point contact settles (tanpura-thread's converged configuration), the plain parabola not.
run --scene Resources/Scenes/tanpura-thread.json --knobs extrapolated --no-floor
run --scene Resources/Scenes/parabola-bridge.json --knobs extrapolated --no-floor --extend
# parabola-bridge's points halved at (2003, 16 MHz) extrapolated: the points settle there, the modes and rate do not.
run --scene Resources/Scenes/parabola-bridge.json --knobs '' --no-floor --ladder 2003:16e6:16032:x,2003:16e6:32064:x
run --scene Resources/Scenes/sitar-bridge.json --knobs '' --no-floor --ladder 4001:4e6:16032,8003:4e6:16032
run --scene Resources/Scenes/sitar-bridge.json --knobs '' --no-floor --ladder 4001:4e6:16032,4001:8e6:16032
run --scene Resources/Scenes/sitar-bridge.json --knobs '' --no-floor --ladder 4001:4e6:16032,4001:4e6:32064
# The static-exact forcing (a scene's "forcing": "static-exact"), each knob from (2003, 2 MHz, L/16032).
for scene in sitar-bridge parabola-bridge tanpura-thread; do
    run --scene "Resources/Scenes/$scene.json" --knobs static-modes,static-rate,static-spacing --no-floor
done
# One header, then the pairs and floors by scene, ladder and rung, coarse to fine.
{ grep -m1 '^kind,' "$out"; grep -v '^kind,' "$out" | sort -t, -k2,2 -k3,3 -k7,7n -k8,8g -k9,9n; } \
    | sed 's/$/\r/' > Resources/Charts/convergence.csv
rm -f "$out"
/usr/bin/python3 tools/plot_charts.py Resources/Charts convergence
