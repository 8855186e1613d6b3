#!/usr/bin/env bash
# Fuzzes the scene parser with libFuzzer (clang from Debian, with AddressSanitizer and
# UndefinedBehaviorSanitizer) for a bounded time, seeded with the scene corpus and the paper scenes.
#   bash tools/fuzz.sh [seconds, default 60]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
bash tools/deps.sh
for p in clang libclang-rt-14-dev; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || {
        sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
        DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends clang libclang-rt-14-dev
        break
    }
done
mkdir -p build-fuzz/corpus
cp Tests/scenes/corpus/*.json Resources/Scenes/*.json build-fuzz/corpus/
clang++ -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
    -IEngine Tests/Fuzz/SceneParserFuzzer.cpp Engine/Scene.cpp Engine/Obstacle.cpp Engine/StringModel.cpp \
    -o build-fuzz/scene-parser-fuzzer
./build-fuzz/scene-parser-fuzzer -max_total_time="$seconds" -max_len=4096 build-fuzz/corpus
