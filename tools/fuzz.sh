#!/usr/bin/env bash
# libFuzzer (clang from Debian, with AddressSanitizer and UndefinedBehaviorSanitizer), each target
# for a bounded time:
#   scene: the scene parser, seeded with the scene corpus and the paper scenes;
#   state: the plugin's state reader (setStateInformation, and setStateFromXml as user presets and
#          jawari-render --state read files), seeded with a valid state;
#   midi:  jawari-render's MIDI file reading (MidiScore), seeded with valid type 0, type 1 and SMPTE
#          files and a dictionary of MIDI tokens.
#   state and midi build the plugin's code and JUCE with clang and the sanitizers in
#   build-fuzz/plugin: about ten minutes the first time.
#   bash tools/fuzz.sh [seconds per target, default 60] [scene|state|midi|all, default all]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
which="${2:-all}"
bash tools/deps.sh
bash tools/deps.sh clang libclang-rt-14-dev  # libFuzzer and the sanitizers' runtime
if [ "$which" = scene ] || [ "$which" = all ]; then
    mkdir -p build-fuzz/corpus
    cp Tests/scenes/corpus/*.json Resources/Scenes/*.json build-fuzz/corpus/
    clang++ -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
        -IEngine Tests/Fuzz/SceneParserFuzzer.cpp Engine/offline/Scene.cpp Engine/physics/contact/Obstacle.cpp \
        Engine/physics/string/StringModel.cpp \
        -o build-fuzz/scene-parser-fuzzer
    ./build-fuzz/scene-parser-fuzzer -max_total_time="$seconds" -max_len=4096 -artifact_prefix=build-fuzz/ \
        build-fuzz/corpus
fi
# The plugin's code and JUCE built with clang and the sanitizers, and the fuzzer targets given.
build_plugin_fuzzers() {
    # UBSan without its alignment check: clang 14 crashes on the engine's `omp simd` kernels with it.
    local flags="-O1 -g -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize=alignment -fno-sanitize-recover=undefined"
    # Debug: -O1 from the flags alone.
    cmake -S . -B build-fuzz/plugin -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_COMPILER=clang \
        -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" \
        -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DJAWARI_NATIVE=OFF -DJAWARI_BUILD_FUZZERS=ON
    cmake --build build-fuzz/plugin -j "$(nproc)" --target "$@"
}
if [ "$which" = state ] || [ "$which" = all ]; then
    build_plugin_fuzzers jawari-state-fuzzer
    mkdir -p build-fuzz/state-corpus
    JAWARI_STATE_SEED=build-fuzz/state-corpus/valid-state.bin \
        ./build-fuzz/plugin/Tests/jawari-state-fuzzer -max_total_time="$seconds" -max_len=8192 -timeout=5 \
        -artifact_prefix=build-fuzz/ build-fuzz/state-corpus Tests/Fuzz/regressions
    # (new inputs go to the first folder; the regressions are read only)
fi
if [ "$which" = midi ] || [ "$which" = all ]; then
    build_plugin_fuzzers jawari-midi-fuzzer
    mkdir -p build-fuzz/midi-corpus
    JAWARI_MIDI_SEEDS=build-fuzz/midi-corpus \
        ./build-fuzz/plugin/Tests/jawari-midi-fuzzer -max_total_time="$seconds" -max_len=8192 -timeout=5 \
        -dict=Tests/Fuzz/midi.dict -artifact_prefix=build-fuzz/ build-fuzz/midi-corpus
fi
