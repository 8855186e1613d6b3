#include "WavOutput.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace jawari::render
{

std::optional<SampleFormat> sampleFormatNamed(const juce::String& name)
{
    if (name == "int24")
        return SampleFormat::int24;
    if (name == "float")
        return SampleFormat::float32;
    return std::nullopt;
}

const char* formatDescription(SampleFormat format)
{
    return format == SampleFormat::int24 ? "24-bit" : "32-bit float";
}

std::string dbfsText(double peak)
{
    if (!(peak > 0.0))
        return "-inf dBFS";
    char text[32];
    const double db = 20.0 * std::log10(peak);
    std::snprintf(text, sizeof text, peak > 1.0 ? "%+.2f dBFS" : "%.1f dBFS", db);
    return text;
}

WavOutput::WavOutput(const juce::File& target, double rate, int channels, SampleFormat format)
    : target_(target)
    , temp_(target)
    , channels_(channels)
    , format_(format)
{
    auto stream = std::make_unique<juce::FileOutputStream>(temp_.getFile());
    if (!stream->openedOk())
        throw std::runtime_error("cannot write '" + temp_.getFile().getFullPathName().toStdString() + "'");
    // JUCE's WAV writer writes IEEE float (format tag 3) when asked for 32 bits.
    const int bits = format == SampleFormat::int24 ? 24 : 32;
    juce::WavAudioFormat wav;
    writer_.reset(wav.createWriterFor(stream.get(), rate, static_cast<unsigned>(channels), bits, {}, 0));
    if (writer_ == nullptr)
        throw std::runtime_error("cannot create a WAV writer at " + std::to_string(rate) + " Hz");
    stream_ = stream.release();  // the writer owns it now
}

void WavOutput::write(const float* const* channels, int count)
{
    if (count <= 0)
        return;
    for (int c = 0; c < channels_; ++c)
        for (int i = 0; i < count; ++i)
        {
            const double magnitude = std::abs(double(channels[c][i]));
            level_.peak = std::max(level_.peak, magnitude);
            level_.atOrBeyondFull += magnitude >= 1.0 ? 1 : 0;
        }
    level_.samples += static_cast<long long>(count) * channels_;
    if (!writer_->writeFromFloatArrays(channels, channels_, count))
        throw std::runtime_error("writing the WAV data failed");
}

void WavOutput::finish()
{
    // The header is written and the stream flushed here, where a failure (a full disk) can still
    // stop the move; the writer's destructor would write them without a word. juce::FileOutputStream
    // records a write that fails but not one cut short (its flush ignores the count), so the file's
    // size on disk is checked against the stream's position too.
    const bool headerWritten = writer_->flush();
    stream_->flush();
    const auto status = stream_->getStatus();
    if (!headerWritten || status.failed() || temp_.getFile().getSize() < stream_->getPosition())
        throw std::runtime_error("writing the WAV file failed: "
                                 + (status.failed() ? status.getErrorMessage().toStdString()
                                                    : std::string("the data did not all reach the disk")));
    writer_.reset();  // writes the same header again, in place
    if (!temp_.overwriteTargetFileWithTemporary())
        throw std::runtime_error("cannot move the finished WAV to '" + target_.getFullPathName().toStdString() + "'");
}

}  // namespace jawari::render
