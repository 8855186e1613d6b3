#!/usr/bin/env bash
# The built plugin in real hosts, repeatably (not run by CI; needs the build, tools/build.sh):
#   bash tools/validate.sh                               the LV2 checks; pluginval SKIPPED
#   PLUGINVAL=path/to/pluginval bash tools/validate.sh   and pluginval on the VST3, once per seed
#   bash tools/validate.sh [options] path/to/pluginval   the same, the path as the argument
# Options:
#   --pluginval-only  pluginval alone, without the LV2 checks
#   --seeds LIST      these seeds (comma-separated, hex 0x... or decimal) instead of the fixed list
#   --random N        N seeds drawn at random besides the others (their logs name them)
#   --jobs 1|2        pluginval runs at a time (default 1; each is CPU-heavy)
#   --lock FILE       holds FILE (flock) during each pluginval run: a shared machine's CPU lock
#   --logs DIR        the folder of pluginval's logs (default build/validate/pluginval)
# Checks:
#   pluginval  strictness 10 on the VST3, its editor tests included, under xvfb-run, once for each
#              seed: the fixed list in this script, then any --random ones. A line for each seed, PASS or
#              FAIL with the first failure line of its log, then the tally. Only with a pluginval
#              given: nothing in this project builds one.
#   lv2info    lilv finds the LV2 bundle (LV2_PATH: the bundle's folder and /usr/lib/lv2 for the
#              spec bundles) and describes an instrument with its ports, every parameter of
#              Source/Parameters.h, 5 presets, the author's mail and homepage.
#   jalv       jalv runs the LV2 on a dummy JACK server (no sound card): its outputs are silent
#              for a second with no notes; then jack_midiseq sends A3 (220 Hz) for half a second
#              every second into its MIDI input, and jack_rec records 3 s of its outputs: the
#              peak level, and the first note's pitch within 1 % of 220 Hz.
# Installs what it needs from Debian when missing. One line per check (per seed for pluginval),
# PASS, FAIL or SKIPPED; exits 1 when a check fails, 2 on bad options.
set -uo pipefail

# Four seeds named in reports of exceptions and stalls reaching pluginval, then 20 drawn once at
# random in pluginval's own range (1 to 0x7ffffff), fixed so that every run repeats them.
fixed_seeds=(0x6349302 0x6733ba9 0x22b84563 0x9adbc3
    0x66a9640 0x35f41db 0x5a37ce 0x2a75831 0x4b1956d 0x7773404 0x699c71 0x1cb73a2 0x544917b 0x77938ad
    0x5ab9f0f 0x602f8ab 0x2a312cf 0x4177993 0x4799016 0x69eb4ee 0x8bf3ac 0xacc0a4 0x7f13bcf 0x2d11612)

usage() {
    sed -n '2,/^set -uo/{/^#/s/^# \{0,1\}//p}' "$0"
}

no_pluginval="no pluginval given: build pluginval against Debian's JUCE and pass its path"

fail_usage() {
    echo "validate: $1 (bash tools/validate.sh --help)" >&2
    exit 2
}

pluginval=${PLUGINVAL:-}
pluginval_only=0
seeds=("${fixed_seeds[@]}")
random_count=0
jobs=1
lock=""
logs=build/validate/pluginval
while [ $# -gt 0 ]; do
    case $1 in
        --pluginval-only) pluginval_only=1; shift; continue ;;
        -h | --help) usage; exit 0 ;;
        -*) [ $# -ge 2 ] || fail_usage "$1 wants a value" ;;
    esac
    case $1 in
        --seeds) IFS=', ' read -ra seeds <<< "$2" ;;
        --random) random_count=$2 ;;
        --jobs) jobs=$2 ;;
        --lock) lock=$(realpath -m "$2") ;;
        --logs) logs=$(realpath -m "$2") ;;
        -*) fail_usage "unknown option $1" ;;
        *) pluginval=$1; shift; continue ;;
    esac
    shift 2
done
[[ $random_count =~ ^[0-9]+$ ]] || fail_usage "--random wants a count"
[[ $jobs =~ ^[12]$ ]] || fail_usage "--jobs is 1 or 2"
[ ${#seeds[@]} -gt 0 ] || [ "$random_count" -gt 0 ] || fail_usage "no seeds"
for seed in "${seeds[@]}"; do
    [[ $seed =~ ^(0x[0-9a-fA-F]+|[0-9]+)$ ]] || fail_usage "seed $seed is neither hex (0x...) nor decimal"
done
for _ in $(seq "$random_count"); do
    seeds+=("$(($(od -An -tu4 -N4 /dev/urandom) % 0x7ffffff + 1))")
done
# pluginval reads lower-case hex only.
for i in "${!seeds[@]}"; do seeds[i]=$(printf '0x%x' "${seeds[i]}"); done
[ -z "$pluginval" ] || pluginval=$(realpath -m "$pluginval")

cd "$(dirname "$0")/.."
release=build/Source/Jawari_artefacts/Release
vst3=$release/VST3/Jawari.vst3
uri=https://jawari.org/plugins/jawari
work=$(mktemp -d)
started=()  # the processes this script starts, ended on exit
seed_jobs=()  # the pluginval runs, each in a process group of its own, ended with their children
cleanup() {
    for pid in "${started[@]}"; do kill "$pid" 2>/dev/null; done
    for pid in "${seed_jobs[@]}"; do kill -- "-$pid" 2>/dev/null; done
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

# What failed in a pluginval log: its first failure line (a failed expectation, a timeout, a crash,
# or an uncaught exception with its message), the test group it came in and the audio settings
# last announced in that group; and whether JUCE had killed a thread that would not stop.
first_failure() {
    awk '
        /^Starting tests in: / { group = substr($0, 20); sub(/\.\.\.$/, "", group); setting = "" }
        /^Testing with sample rate/ { setting = $0 }
        /^!! killing thread by force !!/ { killed = 1 }
        /^!!! Test|\*\*\* FAILED|^terminate called/ {
            failure = $0
            if ($0 ~ /^terminate called/ && (getline next_line) > 0 && next_line ~ /what\(\):/) {
                gsub(/ +/, " ", next_line)
                failure = failure ":" next_line
            }
            exit
        }
        END {
            if (failure == "") exit 1
            printf "%s", failure
            if (group != "") printf " [in %s%s]", group, setting == "" ? "" : ", " setting
            if (killed) printf " (after \"!! killing thread by force !!\": a thread did not stop in time)"
        }' "$1"
}

# Runs pluginval with one seed, its log in $logs/<seed>.log, and prints the seed's line (kept in
# $logs/summary.txt too). Holds the lock, when given, for the run alone. $2: the first X display
# number xvfb-run tries, distinct for runs that may overlap.
run_seed() {
    local seed=$1 display=$2 log=$logs/$1.log
    [ -z "$lock" ] || { exec 9> "$lock" && flock 9; }
    local start=$SECONDS
    xvfb-run -a -n "$display" "$pluginval" --strictness-level 10 --random-seed "$seed" "$vst3" > "$log" 2>&1 9>&-
    local status=$? seconds=$((SECONDS - start)) groups failure line
    groups=$(grep -c "^Starting tests in: pluginval" "$log")
    if [ $status -eq 0 ] && grep -qx "SUCCESS" "$log"; then
        line=$(report pluginval PASS "seed $seed: SUCCESS, $groups test groups, $seconds s")
    elif [ $status -eq 0 ] && ! first_failure "$log" > /dev/null \
        && [ "$groups" -gt 0 ] && [ "$(grep -c "^Completed tests in:\{0,1\} pluginval" "$log")" -eq "$groups" ]; then
        # Some pluginval builds end without a SUCCESS line: exit 0, no failure, every group completed.
        line=$(report pluginval PASS "seed $seed: exit 0, $groups test groups completed, no failure line, $seconds s")
    else
        failure=$(first_failure "$log") || failure="no failure line; last: $(tail -n 1 "$log")"
        line=$(report pluginval FAIL "seed $seed: exit $status after $groups test groups, $seconds s: $failure")
    fi
    echo "$line" | tee -a "$logs/summary.txt"
}

check_pluginval() {
    if [ -z "$pluginval" ]; then
        report pluginval SKIPPED "$no_pluginval (PLUGINVAL=path or the argument)"
        return
    fi
    if [ ! -x "$pluginval" ]; then
        report pluginval FAIL "$pluginval is not an executable"
        return
    fi
    mkdir -p "$logs"
    rm -f "$logs"/0x*.log "$logs/summary.txt"
    local index=0 seed running=0
    set -m  # each run in a process group of its own, so that cleanup ends pluginval and Xvfb too
    for seed in "${seeds[@]}"; do
        if [ $running -ge "$jobs" ]; then
            wait -n
            running=$((running - 1))
        fi
        run_seed "$seed" $((100 + index)) &
        seed_jobs+=($!)
        running=$((running + 1))
        index=$((index + 1))
    done
    wait "${seed_jobs[@]}"
    set +m
    seed_jobs=()
    local failures
    failures=$(grep "^pluginval  FAIL" "$logs/summary.txt" | awk '{ sub(":", "", $4); print $4 }' | tr '\n' ' ')
    if [ -z "$failures" ]; then
        report pluginval PASS "all ${#seeds[@]} seeds at strictness 10 (logs: $logs)"
    else
        report pluginval FAIL "$(wc -w <<< "$failures") of ${#seeds[@]} seeds failed: ${failures% } (logs: $logs)"
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
    # Every factory preset of the source's table (Source/Presets.cpp, one entry a line).
    expectedPresets=$(grep -c '^        {"' Source/Presets.cpp)
    email=$(sed -n 's/^\s*Author Email:\s*//p' <<< "$info")
    homepage=$(sed -n 's/^\s*Author Homepage:\s*//p' <<< "$info")
    local detail="$class, $ports ports, $parameters of $expected parameters, $presets of $expectedPresets presets, $email, $homepage"
    if [ "$class" = "Instrument Plugin" ] && [ "$ports" -ge 4 ] && [ "$parameters" -eq "$expected" ] && [ "$presets" -eq "$expectedPresets" ] \
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

if [ $pluginval_only -eq 1 ]; then
    [ -n "$pluginval" ] || { echo "validate: $no_pluginval" >&2; exit 2; }
    [ -d "$vst3" ] || { echo "validate: build first (bash tools/build.sh)" >&2; exit 1; }
    bash tools/deps.sh xvfb xauth > /dev/null
else
    [ -d "$release/LV2/Jawari.lv2" ] || { echo "validate: build first (bash tools/build.sh)" >&2; exit 1; }
    bash tools/deps.sh xvfb xauth lv2-dev lilv-utils jalv jackd2 python3 > /dev/null
    export LV2_PATH="$PWD/$release/LV2:/usr/lib/lv2"
fi
echo "validate: $(git rev-parse --short HEAD 2>/dev/null)$(git diff --quiet 2>/dev/null || echo ' (modified)')"
check_pluginval
if [ $pluginval_only -eq 0 ]; then
    check_lv2info
    check_jalv
fi
exit $failed
