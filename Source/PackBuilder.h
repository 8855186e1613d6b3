#pragma once
// The processor's builder thread (its definition, included by PluginProcessor.cpp alone): it watches
// the structural parameters, builds a new voice pack for them off the audio thread, offers it through
// the lock-free exchange, and frees the packs the audio thread retires.

#include "PluginProcessor.h"

namespace jawari::plugin
{

// Watches the structural parameters and builds new packs for them off the audio thread; frees the
// packs the audio thread retires.
class JawariAudioProcessor::Builder : public juce::Thread
{
public:
    explicit Builder(JawariAudioProcessor& owner)
        : juce::Thread("Jawari builder")
        , owner_(owner)
    {}

    void setBuilt(const InstrumentStructure& s)
    {
        const juce::SpinLock::ScopedLockType lock(guard_);  // builder and message threads only
        built_ = s;
    }

    bool hasBuilt(const InstrumentStructure& s)
    {
        const juce::SpinLock::ScopedLockType lock(guard_);
        return built_ == s;
    }

    // Each pass: the worker and the retired packs looked after, then a pack for the wanted
    // structure if it changed. When the host rate has no pack yet, a cheap one (draft, one
    // polarisation) goes first, so that the instrument plays within milliseconds of prepareToPlay.
    // Nothing thrown here leaves the thread: it is reported and the last good pack plays on.
    void run() override
    {
        while (!threadShouldExit())
        {
            try
            {
                if (buildIfWanted())
                    continue;
            }
            catch (const std::exception& e)
            {
                owner_.reportProblem(juce::String("the builder stopped on an error: ") + e.what());
            }
            catch (...)
            {
                owner_.reportProblem("the builder stopped on an unknown error");
            }
            wait(10);
        }
    }

private:
    // Returns whether it built (then it looks again at once).
    bool buildIfWanted()
    {
        owner_.syncWorker();
        owner_.collectRetired();
        const double rate = owner_.hostRate_.load();
        if (!playableHostRate(rate))
            return false;
        const auto wanted = owner_.wantedStructure(rate);
        if (hasBuilt(wanted))
            return false;
        if (offeredRate_ != rate && (wanted.quality != 0 || wanted.polarisations != 1))
        {
            auto cheap = wanted;
            cheap.quality = 0;
            cheap.polarisations = 1;
            offer(cheap);
        }
        if (offer(wanted))
        {
            owner_.clearProblem();
            owner_.triggerAsyncUpdate();  // the latency reported to the host
        }
        setBuilt(wanted);  // built or refused: either way not tried again until it changes
        return true;
    }

    // Builds a pack and offers it to the audio thread; a structure the engine refuses is reported
    // and the instrument keeps the pack it has. Returns whether it offered one.
    bool offer(const InstrumentStructure& s)
    {
        try
        {
            auto pack = buildVoicePack(s);
            owner_.exchange_.offer(std::move(pack));
            offeredRate_ = s.hostRateHz;
            return true;
        }
        catch (const std::exception& e)
        {
            owner_.reportProblem(juce::String("these settings could not be built (") + e.what()
                                 + "); the instrument plays the last ones it could");
        }
        return false;
    }

    JawariAudioProcessor& owner_;
    juce::SpinLock guard_;
    InstrumentStructure built_{};
    double offeredRate_ = 0.0;  // the host rate of the last pack offered (builder thread only)
};

}  // namespace jawari::plugin
