#pragma once
// Factory presets (the paper's centre obstacle, tanpura, sitar, bass fret buzz) and user presets
// (the whole state as an XML file in the user's application-data folder).

#include <juce_audio_processors/juce_audio_processors.h>

#include <utility>
#include <vector>

namespace jawari::plugin
{

struct FactoryPreset
{
    const char* name;
    std::vector<std::pair<const char*, float>> values;  // parameter id, value (others: defaults)
};

const std::vector<FactoryPreset>& factoryPresets();
int factoryPresetIndex(const juce::String& name);  // -1 when there is none of that name
// A preset named by a user: its full name or the part before its parenthesis, in any case ("sitar"
// for "Sitar (parabolic bridge)"). -1 when none matches.
int factoryPresetByShortName(const juce::String& wanted);

// Sets every parameter to the preset's value, or its default where the preset says nothing. CT.
void applyFactoryPreset(juce::AudioProcessorValueTreeState& state, const FactoryPreset& preset);

// Where user presets live: <user application data>/Jawari/Presets, *.jawaripreset.
juce::File userPresetFolder();

}  // namespace jawari::plugin
