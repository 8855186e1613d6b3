#!/usr/bin/env bash
# Screenshot of the standalone app's editor under a virtual X server (for the README):
#   bash tools/screenshot.sh [output.png, default Resources/Screenshots/standalone.png]
# Installs xvfb, xdotool and imagemagick from Debian when missing; needs the build (tools/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-Resources/Screenshots/standalone.png}"
missing=()
for p in xvfb xdotool imagemagick; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
app=build/Source/Jawari_artefacts/Release/Standalone/Jawari
[ -x "$app" ] || { echo "screenshot: build first (bash tools/build.sh)" >&2; exit 1; }
mkdir -p "$(dirname "$out")"
# The app plays its default patch; the drone is switched on from the saved settings below so the
# string is drawn moving. A private HOME keeps the user's own settings out of it.
home=$(mktemp -d)
trap 'rm -rf "$home"' EXIT
xvfb-run -a -s "-screen 0 1280x800x24" bash -c "
    HOME='$home' '$app' &
    pid=\$!
    sleep 6
    win=\$(xdotool search --name Jawari | head -1 || true)
    [ -n \"\$win\" ] && xdotool windowmove \"\$win\" 0 0 || true
    sleep 2
    import -window root '$out'
    kill \$pid
"
echo "screenshot: wrote $out"
