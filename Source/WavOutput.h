#pragma once
// The renderer's WAV files (jawari-render, docs/scenes.md): 24-bit integer PCM or 32-bit IEEE float,
// written to a temporary beside the target and moved into place only when complete. Every sample is
// measured on its way in, so that what a 24-bit file cannot hold (|x| >= 1: JUCE's conversion puts
// it on the rail) is reported rather than clipped in silence. OFF.

#include <juce_audio_formats/juce_audio_formats.h>

#include <memory>
#include <optional>
#include <string>

namespace jawari::render
{

enum class SampleFormat
{
    int24,    // 24-bit integer: full scale is +-1, anything at or beyond it lands on the rail
    float32,  // 32-bit IEEE float: every sample as given, above full scale included
};

// The names --format takes: "int24" and "float"; nullopt for any other.
std::optional<SampleFormat> sampleFormatNamed(const juce::String& name);
const char* formatDescription(SampleFormat format);  // "24-bit", "32-bit float"

// The samples given to a file, every channel's counted.
struct Level
{
    long long samples = 0;
    double peak = 0.0;             // the largest |x|
    long long atOrBeyondFull = 0;  // how many have |x| >= 1
};

// A peak in dBFS, for messages: "-3.2 dBFS", "0.0 dBFS", above full scale with its sign and two
// decimals ("+1.30 dBFS", so that a peak just above full scale does not read as 0.0), "-inf dBFS".
std::string dbfsText(double peak);

class WavOutput
{
public:
    WavOutput(const juce::File& target, double rate, int channels, SampleFormat format);

    // Measures and appends `count` samples of each channel. Throws when the write fails.
    void write(const float* const* channels, int count);
    // Completes the header, checks that everything reached the disk and moves the file into place.
    // Destroyed without it (a failed render), the temporary is deleted and the target left as it was.
    void finish();

    SampleFormat format() const { return format_; }
    const Level& level() const { return level_; }
    // Samples the file cannot hold as given: some at or beyond full scale in a 24-bit file.
    bool clipped() const { return format_ == SampleFormat::int24 && level_.atOrBeyondFull > 0; }

private:
    juce::File target_;
    juce::TemporaryFile temp_;
    int channels_;
    SampleFormat format_;
    Level level_;
    juce::FileOutputStream* stream_ = nullptr;         // owned by writer_
    std::unique_ptr<juce::AudioFormatWriter> writer_;  // destroyed before temp_
};

}  // namespace jawari::render
