#!/usr/bin/env bash
# The built plugin in real hosts, repeatably (not run by CI; needs the build, tools/build.sh):
#   bash tools/validate.sh                               the LV2 checks; pluginval SKIPPED
#   PLUGINVAL=path/to/pluginval bash tools/validate.sh   and pluginval on the VST3
# Checks:
#   pluginval  strictness 10 on the VST3, its editor tests included, under xvfb-run. Only with a
#              pluginval given: nothing in this project builds one.
#   lv2info    lilv finds the LV2 bundle (LV2_PATH: the bundle's folder and /usr/lib/lv2 for the
#              spec bundles) and describes an instrument with its ports, every parameter of
#              Source/Parameters.h, 5 presets, the author's mail and homepage.
#   jalv       jalv runs the LV2 on a dummy JACK server (no sound card): its outputs are silent
#              for a second with no notes; then jack_midiseq sends A3 (220 Hz) for half a second
#              every second into its MIDI input, and jack_rec records 3 s of its outputs: the
#              peak level, and the first note's pitch within 1 % of 220 Hz.
# Installs what it needs from Debian when missing. One line per check, PASS, FAIL or SKIPPED;
# exits 1 when a check fails.
set -uo pipefail
cd "$(dirname "$0")/.."
release=build/Source/Jawari_artefacts/Release
uri=https://jawari.org/plugins/jawari
work=$(mktemp -d)
started=()  # the processes this script starts, ended on exit
cleanup() {
    for pid in "${started[@]}"; do kill "$pid" 2>/dev/null; done
    wait 2>/dev/null
    rm -rf "$work"
}
trap cleanup EXIT
failed=0
report() {  # check, PASS|FAIL|SKIPPED, detail
    printf '%-10s %-7s %s\n' "$1" "$2" "$3"
    [ "$2" = FAIL ] && failed=1
    return 0
}

check_pluginval() {
    if [ -z "${PLUGINVAL:-}" ]; then
        report pluginval SKIPPED "no PLUGINVAL=path/to/pluginval given"
        return
    fi
    local log=$work/pluginval.log
    xvfb-run -a "$PLUGINVAL" --strictness-level 10 --validate-in-process "$release/VST3/Jawari.vst3" > "$log" 2>&1
    local status=$? groups
    groups=$(grep -c "^Starting tests in: pluginval" "$log")
    if [ $status -eq 0 ] && grep -qx "SUCCESS" "$log"; then
        report pluginval PASS "SUCCESS at strictness 10, $groups test groups"
    else
        cp "$log" build/validate-pluginval.log
        report pluginval FAIL "exit $status after $groups test groups (log: build/validate-pluginval.log)"
    fi
}

check_lv2info() {
    local info ports presets parameters expected email homepage class
    if ! lv2ls | grep -qx "$uri"; then
        report lv2info FAIL "lv2ls does not list $uri"
        return
    fi
    info=$(lv2info "$uri")
    class=$(sed -n 's/^\s*Class:\s*//p' <<< "$info" | head -1)
    ports=$(grep -c "^\s*Port [0-9]*:" <<< "$info")
    presets=$(sed -n '/^\s*Presets:/,/^\s*$/p' <<< "$info" | grep -vc "Presets:\|^\s*$")
    parameters=$(grep -c "a lv2:Parameter" "$release/LV2/Jawari.lv2/dsp.ttl")
    # Every parameter of the source's list (kParameterIds) is in the bundle.
    expected=$(sed -n '/kParameterIds\[\] = {/,/};/p' Source/Parameters.h | grep -o "ids::[A-Za-z0-9_]*" | wc -l)
    email=$(sed -n 's/^\s*Author Email:\s*//p' <<< "$info")
    homepage=$(sed -n 's/^\s*Author Homepage:\s*//p' <<< "$info")
    local detail="$class, $ports ports, $parameters of $expected parameters, $presets presets, $email, $homepage"
    if [ "$class" = "Instrument Plugin" ] && [ "$ports" -ge 4 ] && [ "$parameters" -eq "$expected" ] && [ "$presets" -eq 5 ] \
        && [ "$email" = "mailto:dev@jawari.org" ] && [ "$homepage" = "https://jawari.org" ]; then
        report lv2info PASS "$detail"
    else
        report lv2info FAIL "$detail"
    fi
}

# Starts the dummy JACK server and jalv with the plugin; returns non-zero if either fails.
start_jalv() {
    jackd --no-realtime -n "$JACK_DEFAULT_SERVER" -d dummy -r 48000 -p 512 > "$work/jackd.log" 2>&1 &
    started+=($!)
    jack_wait -w -t 10 > /dev/null 2>&1 || return 1
    # jalv runs while its standard input stays open.
    mkfifo "$work/jalv.in"
    jalv -x -n jawari "$uri" < "$work/jalv.in" > "$work/jalv.log" 2>&1 &
    started+=($!)
    exec 3> "$work/jalv.in"
    for _ in $(seq 50); do
        jack_lsp 2> /dev/null | grep -qx "jawari:in" && return 0
        sleep 0.2
    done
    return 1
}

# The peak of a WAV in dBFS; with a second argument, the fundamental of its first note as well.
analyse() {
    python3 - "$@" << 'PY'
import math, struct, sys, wave
w = wave.open(sys.argv[1])
n, channels, rate = w.getnframes(), w.getnchannels(), w.getframerate()
data = struct.unpack('<%dh' % (n * channels), w.readframes(n))
x = [data[i * channels] / 32768.0 for i in range(n)]
peak = max(abs(v) for v in x)
out = ['%.1f' % (20 * math.log10(peak)) if peak > 0 else '-inf']
if len(sys.argv) > 2:
    # Autocorrelation over 0.25 s from 50 ms after the onset; the shortest lag near the best.
    onset = next(i for i, v in enumerate(x) if abs(v) > 0.01 * peak)
    s = x[onset + rate // 20: onset + rate // 20 + rate // 4]
    lags = range(rate // 1000, rate // 100)
    r = {lag: sum(s[i] * s[i + lag] for i in range(len(s) - lag)) for lag in lags}
    best = max(r.values())
    lag = next(l for l in lags if r[l] > 0.9 * best and r[l] >= r[l - 1] and r[l] >= r[l + 1])
    a, b, c = r[lag - 1], r[lag], r[lag + 1]
    out.append('%.1f' % (rate / (lag + 0.5 * (a - c) / (a - 2 * b + c))))
print(' '.join(out))
PY
}

check_jalv() {
    export JACK_DEFAULT_SERVER="jawari-validate-$$"
    if ! start_jalv; then
        report jalv FAIL "jackd or jalv did not start: $(tail -n 2 "$work/jackd.log" "$work/jalv.log" | tr '\n' ' ')"
        return
    fi
    jack_rec -f "$work/silence.wav" -d 1 jawari:audio_out_1 jawari:audio_out_2 > /dev/null 2>&1
    jack_midiseq seq 48000 0 57 24000 > /dev/null 2>&1 &
    started+=($!)
    sleep 0.5
    jack_connect seq:out jawari:in 2> /dev/null
    jack_rec -f "$work/notes.wav" -d 3 jawari:audio_out_1 jawari:audio_out_2 > /dev/null 2>&1
    local silence notes peak f0
    silence=$(analyse "$work/silence.wav")
    notes=$(analyse "$work/notes.wav" pitch)
    read -r peak f0 <<< "$notes"
    local detail="no notes: peak $silence dBFS; A3 each second: peak $peak dBFS, first note ${f0} Hz"
    if [ "$silence" = "-inf" ] && [ "$peak" != "-inf" ] && awk -v p="$peak" -v f="$f0" \
        'BEGIN { exit !(p > -40 && p <= 0 && f > 217.8 && f < 222.2) }'; then
        report jalv PASS "$detail"
    else
        report jalv FAIL "$detail"
    fi
}

[ -d "$release/LV2/Jawari.lv2" ] || { echo "validate: build first (bash tools/build.sh)" >&2; exit 1; }
bash tools/deps.sh xvfb lv2-dev lilv-utils jalv jackd2 python3 > /dev/null
export LV2_PATH="$PWD/$release/LV2:/usr/lib/lv2"
echo "validate: $(git rev-parse --short HEAD 2>/dev/null)$(git diff --quiet 2>/dev/null || echo ' (modified)')"
check_pluginval
check_lv2info
check_jalv
exit $failed
