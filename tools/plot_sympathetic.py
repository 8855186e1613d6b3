#!/usr/bin/env python3
"""The sympathetic strings heard: a phrase in Kafi for the Sitar preset, and the spectrograms of its
renders with and without them (tools/sympathetic.sh runs both).

    /usr/bin/python3 tools/plot_sympathetic.py phrase OUT.mid
    /usr/bin/python3 tools/plot_sympathetic.py plot WITH.wav WITHOUT.wav OUT.png

The phrase (Sa at C#3, the preset's): C#4 D#4 E4 F#4 G#4 at 100 beats a minute, a quarter each, then
C#4 held for two beats; then four seconds of nothing, in which the sympathetic strings ring on.
Needs Debian's python3-matplotlib (and its numpy).
"""
import struct
import sys
import wave

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

TICKS = 480  # per quarter


def variable_length(n):
    out = [n & 0x7F]
    n >>= 7
    while n:
        out.append((n & 0x7F) | 0x80)
        n >>= 7
    return bytes(reversed(out))


def write_phrase(path):
    notes = [(61, 1), (63, 1), (64, 1), (66, 1), (68, 1), (61, 2)]  # (key, quarters)
    events, t = [], 0
    for key, quarters in notes:
        events.append((t, bytes([0x90, key, 96])))
        t += quarters * TICKS
        events.append((t - 10, bytes([0x80, key, 0])))
    events.sort(key=lambda e: e[0])
    tempo = 600000  # microseconds a quarter: 100 beats a minute
    track, last = variable_length(0) + b"\xff\x51\x03" + tempo.to_bytes(3, "big"), 0
    for tick, message in events:
        track += variable_length(tick - last) + message
        last = tick
    track += variable_length(4 * TICKS * 10 // 6) + b"\xff\x2f\x00"  # the end: 4 s later
    with open(path, "wb") as f:
        f.write(b"MThd" + struct.pack(">IHHH", 6, 0, 1, TICKS) + b"MTrk" + struct.pack(">I", len(track)) + track)


def read_left(path):
    with wave.open(path) as w:
        rate, width, channels = w.getframerate(), w.getsampwidth(), w.getnchannels()
        raw = np.frombuffer(w.readframes(w.getnframes()), dtype=np.uint8)
    if width != 3:
        sys.exit(f"{path}: expected 24-bit samples")
    frames = raw.reshape(-1, channels, 3)[:, 0, :].astype(np.int32)
    value = frames[:, 0] | (frames[:, 1] << 8) | (frames[:, 2] << 16)
    value = np.where(value >= 1 << 23, value - (1 << 24), value)
    return value / float(1 << 23), rate


def plot(with_path, without_path, out):
    fig, axes = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    for ax, path, title in ((axes[0], with_path, "Sitar preset: 13 sympathetic strings in Kafi"),
                            (axes[1], without_path, "the same without them (--set sympathetic=0)")):
        y, rate = read_left(path)
        y = y + 1e-9 * np.random.default_rng(0).standard_normal(len(y))  # a floor far below the colours' for digital silence
        ax.specgram(y, NFFT=4096, Fs=rate, noverlap=3072, cmap="magma", vmin=-150, vmax=-40)
        ax.set_ylim(0, 3000)
        ax.axvline(7 * 0.6, color="w", ls="--", lw=0.8)  # the last note released, 7 quarters in
        ax.set_title(title, fontsize=10)
        ax.set_ylabel("Hz")
    axes[1].set_xlabel("s (dashed: the last note released)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "phrase":
        write_phrase(sys.argv[2])
    elif len(sys.argv) == 5 and sys.argv[1] == "plot":
        plot(*sys.argv[2:])
    else:
        sys.exit(__doc__)
