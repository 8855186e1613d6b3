#!/usr/bin/env bash
# Installs the Debian/Ubuntu packages Jawari builds against, when any is missing. Nothing is
# downloaded at configure or build time: every dependency is one of these packages.
#   bash tools/deps.sh            the build's packages
#   bash tools/deps.sh PKG...     those packages instead (the tools' own: screenshot, validate)
set -euo pipefail

packages=("$@")
[ ${#packages[@]} -gt 0 ] || packages=(
    cmake g++ make pkg-config
    juce-modules-source        # JUCE 7 modules, CMake config and juceaide
    libeigen3-dev              # small dense solves (the coupled contact Newton)
    libfftw3-dev               # DST-I for the reference, spectra for analysis
    libsoxr-dev                # resampling the internal rate to the output rate
    libliquid-dev              # FIR design (Kaiser window) for the voice's decimator
    nlohmann-json3-dev         # scene files (the engine has no JUCE)
    catch2                     # tests (Catch2 v2)
    libx11-dev libxrandr-dev libxinerama-dev libxcursor-dev libxext-dev  # the plugin editor (X11)
    libfreetype-dev libfontconfig-dev libasound2-dev libgl-dev         # fonts, ALSA (standalone)
)

missing=()
for p in "${packages[@]}"; do
    [ "$p" = "#" ] && continue
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done
if [ ${#missing[@]} -eq 0 ]; then
    echo "deps: all ${#packages[@]} packages present"
    exit 0
fi
echo "deps: installing ${missing[*]}"
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
