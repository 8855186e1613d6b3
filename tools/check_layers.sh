#!/usr/bin/env bash
# Checks the engine's layering in its sources: physics/ includes nothing of realtime/ or offline/,
# realtime/ nothing of offline/. Prints each include that points upwards; exits 1 if there is one.
set -euo pipefail
engine="${1:-$(dirname "$0")/../Engine}"
bad=0
check() {  # folder, then the folders it must not include
    local folder="$1"; shift
    for upper in "$@"; do
        if grep -rn "#include \"$upper/" "$engine/$folder"; then
            bad=1
        fi
    done
}
check physics realtime offline
check realtime offline
files=$(find "$engine/physics" "$engine/realtime" "$engine/offline" -name '*.h' -o -name '*.cpp' | wc -l)
if [ "$bad" -ne 0 ]; then
    echo "layers: an engine file includes a layer above its own (listed above)"
    exit 1
fi
echo "layers: $files engine files, every include points to its own layer or one below"
