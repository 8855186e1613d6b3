#!/usr/bin/env bash
# Checks the engine's layering in its sources (docs/design.md section 6): physics/ includes nothing
# of realtime/ or offline/, realtime/ nothing of offline/; within physics/ nothing but body/ includes
# body/ (the string steps the same on rigid supports); within realtime/, voice/ (one string) includes
# nothing of instrument/, playing/ or sympathetic/. Prints each include that points the wrong way;
# exits 1 if there is one.
set -euo pipefail
engine="${1:-$(dirname "$0")/../Engine}"
bad=0
check() {  # a folder under Engine, then the folders it must not include
    local folder="$1"; shift
    local files
    files=$(find "$engine/$folder" -name '*.h' -o -name '*.cpp')
    for upper in "$@"; do
        if grep -n "#include \"$upper/" $files; then
            bad=1
        fi
    done
}
check physics realtime offline
check realtime offline
for part in modes string contact; do
    check "physics/$part" physics/body
done
check realtime/voice realtime/instrument realtime/playing realtime/sympathetic
files=$(find "$engine/physics" "$engine/realtime" "$engine/offline" -name '*.h' -o -name '*.cpp' | wc -l)
if [ "$bad" -ne 0 ]; then
    echo "layers: an engine file includes a layer it must not (listed above)"
    exit 1
fi
echo "layers: $files engine files, every include points to its own layer or one it may use"
