#!/usr/bin/env bash
# Screenshot of the standalone app's editor under a virtual X server (for the README):
#   bash tools/screenshot.sh [output.png, default Resources/Screenshots/standalone.png]
# Installs xvfb, xdotool and imagemagick from Debian when missing; needs the build (tools/build.sh).
# There is no sound card: ALSA's null device (set as the default in the private HOME) stands in,
# so the app runs audio (faster than real time). For the picture two computer-keyboard keys (A and
# D: C3 and E3) and the Pluck button (C#3) are held, so it shows the on-screen keyboard taking the
# computer keyboard's notes and the strings sounding.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-Resources/Screenshots/standalone.png}"
bash tools/deps.sh xvfb xdotool imagemagick
app=$(pwd)/build/Source/Jawari_artefacts/Release/Standalone/Jawari
[ -x "$app" ] || { echo "screenshot: build first (bash tools/build.sh)" >&2; exit 1; }
mkdir -p "$(dirname "$out")"
out=$(realpath "$out")
# A private HOME keeps the user's own settings out of it.
home=$(mktemp -d)
trap 'rm -rf "$home"' EXIT
echo 'pcm.!default { type null }' > "$home/.asoundrc"
cat > "$home/shoot.sh" <<SHOOT
set -u
HOME='$home' '$app' &
pid=\$!
sleep 6
win=\$(xdotool search --onlyvisible --name '^Jawari\$' | head -1 || true)
if [ -z "\$win" ]; then echo "screenshot: no Jawari window" >&2; kill \$pid; exit 1; fi
xdotool windowmove --sync "\$win" 0 0
xdotool windowfocus --sync "\$win"
eval "\$(xdotool getwindowgeometry --shell "\$win")"
sleep 1
xdotool keydown a keydown d mousemove 60 \$((HEIGHT - 60)) mousedown 1
sleep 0.4
import -window root -crop "\${WIDTH}x\${HEIGHT}+0+0" +repage '$out'
xdotool mouseup 1 keyup a keyup d
kill \$pid
SHOOT
xvfb-run -a -s "-screen 0 1600x1000x24" bash "$home/shoot.sh"
echo "screenshot: wrote $out"
