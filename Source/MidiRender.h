#pragma once
// A MIDI score played through the plugin's own AudioProcessor, offline (jawari-render --midi): the
// score's events reach processBlock at their exact samples, so presets, state, the drone, sustain,
// pitch bend and all-notes-off behave as in a host. OFF: it drives the processor as a host's audio
// thread would, and allocates around it.

#include "MidiScore.h"
#include "PluginProcessor.h"

#include <functional>
#include <optional>

namespace jawari::midi
{

struct MidiRenderSettings
{
    double rateHz = 48000.0;
    int blockSize = 512;
    // Exactly this many samples; without it, until the output has stayed below silenceLevel for
    // silenceSeconds after the last event, and at most tailCapSeconds after it.
    std::optional<long long> lengthSamples;
    double silenceLevel = 1e-5;  // -100 dBFS
    double silenceSeconds = 0.5;
    double tailCapSeconds = 60.0;
    std::function<void(double fraction)> progress;  // optional
};

struct MidiRenderStats
{
    long long samples = 0;
    int latencySamples = 0;   // the processor's, removed from the output
    bool tailCapped = false;  // the output never fell silent: stopped tailCapSeconds after the last event
};

// Receives each block of the output, latency removed: left, right, count.
using StereoSink = std::function<void(const float*, const float*, int)>;

// Prepares the processor at the settings' rate, plays the score through it from sample 0 (an event
// at t seconds lands on output sample round(t x rate)) and releases it.
MidiRenderStats renderScore(plugin::JawariAudioProcessor& processor, const MidiScore& score,
                            const MidiRenderSettings& settings, const StereoSink& sink);

}  // namespace jawari::midi
