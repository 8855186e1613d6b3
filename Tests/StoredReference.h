#pragma once
// The converged references a scene's own configuration renders in minutes, too slow for every test
// run: stored once in Resources/References as the renderer wrote them (`jawari-render SCENE -o
// FILE --raw`: 32-bit float WAV, SI units, at the scene's output rate), read here with JUCE.

#include "Fnv1a.h"

#include <juce_audio_formats/juce_audio_formats.h>

#include <catch2/catch.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace jawari::test
{

struct StoredReference
{
    double rateHz = 0.0;
    std::vector<double> samples;
    uint64_t fnv1a = 0;  // over the file's 32-bit samples, as stored
};

// Resources/References/NAME.wav, one channel of 32-bit floats.
inline StoredReference storedReference(const std::string& name)
{
    const juce::File file(std::string(JAWARI_RESOURCES_DIR) + "/References/" + name + ".wav");
    juce::WavAudioFormat format;
    std::unique_ptr<juce::AudioFormatReader> reader(format.createReaderFor(new juce::FileInputStream(file), true));
    REQUIRE(reader != nullptr);
    REQUIRE(reader->numChannels == 1);
    REQUIRE(reader->usesFloatingPointData);
    juce::AudioBuffer<float> buffer(1, int(reader->lengthInSamples));
    REQUIRE(reader->read(&buffer, 0, buffer.getNumSamples(), 0, true, false));
    StoredReference r;
    r.rateHz = reader->sampleRate;
    const float* stored = buffer.getReadPointer(0);
    Fnv1a hash;
    hash.add(stored, size_t(buffer.getNumSamples()) * sizeof(float));
    r.fnv1a = hash.value;
    r.samples.assign(stored, stored + buffer.getNumSamples());
    return r;
}

}  // namespace jawari::test
