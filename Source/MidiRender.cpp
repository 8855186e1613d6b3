#include "MidiRender.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace jawari::midi
{
namespace
{
// The score's events into each block's MidiBuffer, at their sample offsets in it.
class EventFeed
{
public:
    EventFeed(const juce::MidiMessageSequence& events, double rateHz)
        : events_(events)
        , rate_(rateHz)
    {}

    void fill(juce::MidiBuffer& midi, long long blockStart, int blockSize)
    {
        midi.clear();
        for (; next_ < events_.getNumEvents(); ++next_)
        {
            const auto& message = events_.getEventPointer(next_)->message;
            const long long at = std::llround(message.getTimeStamp() * rate_);
            if (at >= blockStart + blockSize)
                break;
            midi.addEvent(message, static_cast<int>(at - blockStart));
        }
    }

private:
    const juce::MidiMessageSequence& events_;
    double rate_;
    int next_ = 0;
};

// Where the output ends: a fixed length, or silence after the last event (capped).
class Ending
{
public:
    Ending(const MidiRenderSettings& s, long long lastEventSample)
        : fixed_(s.lengthSamples)
        , lastEvent_(lastEventSample)
        , level_(s.silenceLevel)
        , hold_(std::max(1LL, std::llround(s.silenceSeconds * s.rateHz)))
        , cap_(lastEventSample + std::llround(s.tailCapSeconds * s.rateHz))
    {}

    // How many of this block's samples, starting at output sample `written`, the output keeps.
    int keep(const float* left, const float* right, int count, long long written)
    {
        if (fixed_)
        {
            const auto n = static_cast<int>(std::min<long long>(count, *fixed_ - written));
            done_ = written + n >= *fixed_;
            return n;
        }
        for (int i = 0; i < count; ++i)
        {
            const long long index = written + i;
            const bool loud = std::abs(left[i]) >= level_ || std::abs(right[i]) >= level_;
            quiet_ = index < lastEvent_ || loud ? 0 : quiet_ + 1;
            capped_ = index + 1 >= cap_ && quiet_ < hold_;
            if (quiet_ >= hold_ || capped_)
            {
                done_ = true;
                return i + 1;
            }
        }
        return count;
    }

    bool done() const { return done_; }
    bool capped() const { return capped_; }
    // The length the progress bar counts towards: the fixed length, else the last event.
    long long expected() const { return fixed_ ? *fixed_ : std::max(1LL, lastEvent_); }

private:
    std::optional<long long> fixed_;
    long long lastEvent_;
    double level_;
    long long hold_, cap_;
    long long quiet_ = 0;
    bool done_ = false, capped_ = false;
};

void prepare(plugin::JawariAudioProcessor& processor, const MidiRenderSettings& s)
{
    processor.setNonRealtime(true);
    processor.setPlayConfigDetails(0, 2, s.rateHz, s.blockSize);
    processor.prepareToPlay(s.rateHz, s.blockSize);
    if (!processor.waitForBuilds())
        throw std::runtime_error("the instrument's voices were not built in time");
}
}  // namespace

MidiRenderStats renderScore(plugin::JawariAudioProcessor& processor, const MidiScore& score,
                            const MidiRenderSettings& settings, const StereoSink& sink)
{
    prepare(processor, settings);
    MidiRenderStats stats;
    stats.latencySamples = processor.getLatencySamples();
    EventFeed feed(score.events, settings.rateHz);
    Ending ending(settings, std::llround(score.lastEventSeconds * settings.rateHz));
    const int block = settings.blockSize;
    juce::AudioBuffer<float> buffer(2, block);
    juce::MidiBuffer midi;
    long long processed = 0;  // samples through the processor, its latency included
    int blocksSinceProgress = 0;
    while (!ending.done())
    {
        feed.fill(midi, processed, block);
        buffer.clear();
        processor.processBlock(buffer, midi);
        const auto skip = static_cast<int>(std::clamp<long long>(stats.latencySamples - processed, 0, block));
        processed += block;
        const float* left = buffer.getReadPointer(0) + skip;
        const float* right = buffer.getReadPointer(1) + skip;
        const int count = skip < block ? ending.keep(left, right, block - skip, stats.samples) : 0;
        sink(left, right, count);
        stats.samples += count;
        if (settings.progress && (++blocksSinceProgress == 32 || ending.done()))
        {
            blocksSinceProgress = 0;
            settings.progress(ending.done() ? 1.0 : std::min(1.0, double(stats.samples) / double(ending.expected())));
        }
    }
    stats.tailCapped = ending.capped();
    processor.releaseResources();
    return stats;
}

}  // namespace jawari::midi
