// libFuzzer on the plugin's setStateInformation: whatever the bytes, no crash, no sanitizer report,
// and every parameter ends finite and inside its range. Built by tools/fuzz.sh (clang, ASan, UBSan).
// JAWARI_STATE_SEED=path writes a valid state there first (the fuzzer's seed).

#include "PluginProcessor.h"

#include <juce_events/juce_events.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace
{
jawari::plugin::JawariAudioProcessor& processor()
{
    // Never destroyed: libFuzzer exits without running static destructors in a defined order.
    static auto* juce = new juce::ScopedJuceInitialiser_GUI();
    static auto* p = new jawari::plugin::JawariAudioProcessor();
    static_cast<void>(juce);
    return *p;
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    if (const char* seed = std::getenv("JAWARI_STATE_SEED"))
    {
        juce::MemoryBlock blob;
        processor().getStateInformation(blob);
        juce::File(seed).replaceWithData(blob.getData(), blob.getSize());
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    auto& p = processor();
    p.setStateInformation(data, static_cast<int>(size));
    for (auto* param : p.getParameters())
    {
        const float v = param->getValue();
        if (!(std::isfinite(v) && v >= 0.0f && v <= 1.0f))
            std::abort();
    }
    for (int i = 0; i < jawari::kDampingCurvePoints; ++i)
        if (!(p.dampingCurvePoint(i) >= 0.125f && p.dampingCurvePoint(i) <= 8.0f))
            std::abort();
    return 0;
}
