#include "Presets.h"

#include "Parameters.h"

namespace jawari::plugin
{

const std::vector<FactoryPreset>& factoryPresets()
{
    // Positions are fractions of the string's length (the paper's 0.501 m and 0.992 m on 1.002 m).
    // The tanpura presets play through the tanpura's body, plucked softly, as a finger does; the sitar
    // presets through the sitar's (the same wood and build at a sitar's size).
    // The sitar's played string on its bridge, and its thirteen sympathetic strings, tuned to Kafi.
    // Two voices, a melody's note and the one ringing before it: each string through the body costs
    // about ten per cent of a core (docs/measurements.md, "The voice limit").
    static const std::vector<std::pair<const char*, float>> sitar = {
        {ids::stringType, 1.0f},         {ids::obstacleShape, 1.0f},
        {ids::obstaclePosition, 0.012f}, {ids::obstacleHeight, 0.0f},
        {ids::obstacleStiffness, 12.0f}, {ids::obstacleExponent, 1.5f},
        {ids::obstacleWidth, 20.0f},     {ids::bridgeCurvature, 8.0f},
        {ids::inharmonicity, 1.0e-5f},   {ids::pluckPosition, 0.2f},
        {ids::pickupPosition, 0.95f},    {ids::body, 2.0f},
        {ids::sympathetic, 13.0f},       {ids::voices, 2.0f}};
    static const auto sitarSaPa = [] {
        auto values = sitar;
        values.emplace_back(ids::sympatheticScale, 0.0f);
        return values;
    }();
    static const std::vector<FactoryPreset> presets = {
        {"Default (tanpura bridge, no drone)", {}},
        {"Paper centre obstacle",
         {{ids::stringType, 0.0f},
          {ids::obstacleShape, 0.0f},
          {ids::obstaclePosition, 0.5f},
          {ids::obstacleHeight, 0.0f},
          {ids::obstacleStiffness, 13.0f},
          {ids::obstacleExponent, 1.3f},
          {ids::obstacleWidth, 1.0f},
          {ids::pluckPosition, 0.5f},
          {ids::pickupPosition, 0.992f / 1.002f}}},
        {"Tanpura drone",
         {{ids::stringType, 0.0f},
          {ids::obstacleShape, 0.0f},
          {ids::obstaclePosition, 0.006f / 1.002f},
          {ids::obstacleHeight, 0.0f},
          {ids::obstacleStiffness, 13.0f},
          {ids::obstacleExponent, 1.3f},
          {ids::obstacleWidth, 1.0f},
          {ids::pluckPosition, 0.5f},
          {ids::pickupPosition, 0.992f / 1.002f},
          {ids::drone, 1.0f},
          {ids::body, 1.0f},
          {ids::pluckStyle, 1.0f}}},
        {"Sitar (parabolic bridge)", sitar},
        {"Bass fret buzz",
         {{ids::stringType, 2.0f},
          {ids::obstacleShape, 2.0f},
          {ids::obstacleHeight, -0.25f},
          {ids::obstacleStiffness, 12.0f},
          {ids::obstacleExponent, 1.5f},
          {ids::obstacleWidth, 2.0f},
          {ids::inharmonicity, 1.2e-4f},
          {ids::pluckPosition, 0.12f},
          {ids::pickupPosition, 0.1f},
          {ids::release, 0.25f}}},
        // The tanpura a player sets by its thread: the paper's string over a 10 mm curved bridge (apex
        // 5 mm from the end, 20 /m), a rigid 0.2 mm thread 6 mm from the bridge's edge, both
        // polarisations, the drone on. There the band above the 10th partial sweeps down by a quarter
        // over the first second, the jawari's "open" sound; nearer the apex it hardly moves (8 % at
        // 4 mm), nearer the edge it stays high (docs/measurements.md, "The thread's position,
        // explored"). Rigid: DAFx-16's damped thread buzzes on a nearly flat bridge, whose coupled
        // points cost six times the CPU (docs/measurements.md, "The damped thread on a tanpura's
        // bridge"). Last, so the other presets keep their program numbers in a host.
        {"Tanpura thread (jiva, two polarisations)",
         {{ids::stringType, 0.0f},
          {ids::obstacleShape, 1.0f},
          {ids::obstaclePosition, 0.005f / 1.002f},
          {ids::obstacleHeight, 0.0f},
          {ids::obstacleStiffness, 13.0f},
          {ids::obstacleExponent, 1.3f},
          {ids::obstacleWidth, 10.0f},
          {ids::bridgeCurvature, 20.0f},
          {ids::pluckPosition, 0.5f},
          {ids::pickupPosition, 0.992f / 1.002f},
          {ids::polarisations, 1.0f},
          {ids::thread, 1.0f},
          {ids::threadModel, 1.0f},
          {ids::threadPosition, 6.0f},
          {ids::threadDiameter, 0.2f},
          {ids::drone, 1.0f},
          {ids::body, 1.0f},
          {ids::pluckStyle, 1.0f}}},
        // The Sitar with its sympathetic strings tuned to Sa and Pa alone: they answer a drone.
        {"Sitar Sa-Pa (sympathetic strings for a drone)", sitarSaPa},
    };
    return presets;
}

void applyFactoryPreset(juce::AudioProcessorValueTreeState& state, const FactoryPreset& preset)
{
    for (auto* p : state.processor.getParameters())
    {
        auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(p);
        if (ranged == nullptr || ranged->getParameterID() == ids::secondCore)
            continue;  // the second core is the machine's setting, not the sound's
        float normalised = ranged->getDefaultValue();
        for (const auto& [id, value] : preset.values)
            if (ranged->getParameterID() == id)
                normalised = ranged->convertTo0to1(value);
        ranged->setValueNotifyingHost(normalised);
    }
}

int factoryPresetIndex(const juce::String& name)
{
    const auto& presets = factoryPresets();
    for (size_t i = 0; i < presets.size(); ++i)
        if (name == presets[i].name)
            return static_cast<int>(i);
    return -1;
}

int factoryPresetByShortName(const juce::String& wanted)
{
    const auto& presets = factoryPresets();
    for (size_t i = 0; i < presets.size(); ++i)
    {
        const juce::String name(presets[i].name);
        if (name.equalsIgnoreCase(wanted.trim())
            || name.upToFirstOccurrenceOf(" (", false, false).equalsIgnoreCase(wanted.trim()))
            return static_cast<int>(i);
    }
    return -1;
}

juce::File userPresetFolder()
{
    return juce::File::getSpecialLocation(juce::File::userApplicationDataDirectory)
        .getChildFile("Jawari")
        .getChildFile("Presets");
}

}  // namespace jawari::plugin
