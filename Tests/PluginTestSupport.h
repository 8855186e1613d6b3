#pragma once
// What the plugin's headless tests share: parameters set as a host sets them, prepareToPlay with its
// pack waited for, renders of a note, and the output's checks.

#include "PluginProcessor.h"

#include <catch2/catch.hpp>

#include <juce_audio_processors/juce_audio_processors.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace jawari::plugin_tests
{
using namespace jawari::plugin;

inline void setParameter(JawariAudioProcessor& p, const char* id, float value)
{
    auto* param = p.parameters().getParameter(id);
    REQUIRE(param != nullptr);
    param->setValueNotifyingHost(param->convertTo0to1(value));
}

// prepareToPlay, and the builder thread's pack for the parameters waited for: the next block plays it.
inline void prepare(JawariAudioProcessor& p, double rate, int block)
{
    p.prepareToPlay(rate, block);
    REQUIRE(p.waitForBuilds());
}

inline float parameterValue(JawariAudioProcessor& p, const char* id)
{
    return p.parameters().getRawParameterValue(id)->load();
}

// Renders `seconds` with `first` in the first block (an empty buffer after); returns the left channel.
inline std::vector<double> render(JawariAudioProcessor& p, double rate, int block, double seconds,
                           const juce::MidiBuffer& first = {})
{
    juce::AudioBuffer<float> buffer(2, block);
    std::vector<double> out;
    const long total = std::lround(seconds * rate);
    for (long n = 0; n < total; n += block)
    {
        juce::MidiBuffer midi;
        if (n == 0)
            midi = first;
        buffer.clear();
        p.processBlock(buffer, midi);
        for (int i = 0; i < block && n + i < total; ++i)
            out.push_back(buffer.getSample(0, i));
    }
    return out;
}

// Renders `seconds` with one note held from the start; returns the left channel.
inline std::vector<double> renderNote(JawariAudioProcessor& p, double rate, int block, double seconds, int note = 55,
                               juce::uint8 velocity = 100)
{
    juce::MidiBuffer midi;
    midi.addEvent(juce::MidiMessage::noteOn(1, note, velocity), 0);
    return render(p, rate, block, seconds, midi);
}

inline double peakOf(const std::vector<double>& y)
{
    double m = 0.0;
    for (double v : y)
        m = std::max(m, std::abs(v));
    return m;
}

// Finite and within the output guard's ceiling (+12 dBFS: extreme gains and obstacles may pass full
// scale, as a float pipeline carries them).
inline bool allFinite(const juce::AudioBuffer<float>& b)
{
    for (int c = 0; c < b.getNumChannels(); ++c)
        for (int i = 0; i < b.getNumSamples(); ++i)
            if (!std::isfinite(b.getSample(c, i)) || std::abs(b.getSample(c, i)) > kOutputCeiling)
                return false;
    return true;
}
}  // namespace jawari::plugin_tests
