// libFuzzer on the plugin's state reader: each input as setStateInformation's data and as the XML
// text of a state file (setStateFromXml, what user presets and jawari-render --state read).
// Whatever the bytes, no crash, no sanitizer report, and every parameter ends finite and inside its
// range. Built by tools/fuzz.sh (clang, ASan, UBSan).
// JAWARI_STATE_SEED=path writes a valid state there first, and its XML text beside it (.xml): the
// fuzzer's seeds.

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

void checkParameters(jawari::plugin::JawariAudioProcessor& p)
{
    for (auto* param : p.getParameters())
    {
        const float v = param->getValue();
        if (!(std::isfinite(v) && v >= 0.0f && v <= 1.0f))
            std::abort();
    }
    for (int i = 0; i < jawari::kDampingCurvePoints; ++i)
        if (!(p.dampingCurvePoint(i) >= 0.125f && p.dampingCurvePoint(i) <= 8.0f))
            std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    if (const char* seed = std::getenv("JAWARI_STATE_SEED"))
    {
        juce::MemoryBlock blob;
        processor().getStateInformation(blob);
        const auto file = juce::File::getCurrentWorkingDirectory().getChildFile(seed);
        file.replaceWithData(blob.getData(), blob.getSize());
        file.withFileExtension("xml").replaceWithText(processor().state().toXmlString());
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    auto& p = processor();
    p.setStateInformation(data, static_cast<int>(size));
    checkParameters(p);
    static_cast<void>(p.setStateFromXml(reinterpret_cast<const char*>(data), size));
    checkParameters(p);
    return 0;
}
