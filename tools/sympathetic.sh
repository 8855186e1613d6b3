#!/usr/bin/env bash
# The sympathetic strings heard: renders Resources/Midi/sitar-kafi.mid through the Sitar preset with
# and without its sympathetic strings (out/sitar-kafi.wav, out/sitar-kafi-dry.wav) and draws their
# spectrograms (Resources/Charts/sympathetic.png). Needs the build (tools/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/deps.sh python3-matplotlib
mkdir -p out Resources/Charts
render=./build/bin/jawari-render
"$render" --midi Resources/Midi/sitar-kafi.mid --preset Sitar --duration 8 -o out/sitar-kafi.wav --quiet
"$render" --midi Resources/Midi/sitar-kafi.mid --preset Sitar --set sympathetic=0 --duration 8 -o out/sitar-kafi-dry.wav --quiet
/usr/bin/python3 tools/plot_sympathetic.py plot out/sitar-kafi.wav out/sitar-kafi-dry.wav Resources/Charts/sympathetic.png
echo "sympathetic: out/sitar-kafi.wav, out/sitar-kafi-dry.wav, Resources/Charts/sympathetic.png"
