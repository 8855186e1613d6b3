#pragma once
// The editor: the string and its obstacle drawn live (from the engine's lock-free snapshot), the
// contact/energy meter, the output spectrum and the per-mode damping curve on the left; the
// parameters on the right in titled panels as a player thinks of them (string, obstacle, damping,
// drone, output, quality), each value in its unit and each control with a tooltip saying what it
// does physically; an on-screen keyboard (also played from the computer keyboard) and a Pluck
// button along the bottom. Resizable; the standalone app shows the same editor.

#include "ControlPanel.h"
#include "EditorViews.h"
#include "PluginProcessor.h"

#include <juce_audio_processors/juce_audio_processors.h>
#include <juce_audio_utils/juce_audio_utils.h>
#include <juce_gui_basics/juce_gui_basics.h>

#include <memory>
#include <vector>

namespace jawari::plugin
{

// The on-screen keyboard, with a tooltip.
class Keyboard : public juce::MidiKeyboardComponent, public juce::SettableTooltipClient
{
public:
    using MidiKeyboardComponent::MidiKeyboardComponent;
};

class JawariLookAndFeel : public juce::LookAndFeel_V4
{
public:
    JawariLookAndFeel();
    juce::Label* createSliderTextBox(juce::Slider& slider) override;
};

class JawariEditor : public juce::AudioProcessorEditor, private juce::Timer
{
public:
    explicit JawariEditor(JawariAudioProcessor& p);
    ~JawariEditor() override;
    void paint(juce::Graphics& g) override;
    void resized() override;
    // Reads the engine's newest snapshot, the recent output and the meters (the 30 Hz timer).
    void refreshFromProcessor();

private:
    void timerCallback() override;
    void refreshTexts();
    juce::String statusText() const;
    void setUpPresets();
    void setUpScale();
    void chooseScale();
    void refreshPresetList();
    void setUpPlaying();
    void pluck(bool down);
    void layOutPanels(juce::Rectangle<int> area);
    void layOutPlaying(juce::Rectangle<int> area);

    JawariAudioProcessor& processor_;
    JawariLookAndFeel lookAndFeel_;
    juce::TooltipWindow tooltips_{this, 700};
    StringView stringView_;
    SpectrumView spectrum_;
    DampingCurveEditor curve_;
    juce::Label meter_;
    juce::Label status_;      // what was refused or corrected (statusText)
    juce::String editorNote_;  // the editor's own last failed action (a preset, a scale), until the next
    juce::ComboBox presets_;
    juce::TextEditor presetName_;
    juce::TextButton savePreset_{"Save preset"};
    juce::TextButton scale_;                      // the keyboard's tuning: shows it, opens its menu
    std::unique_ptr<juce::FileChooser> chooser_;  // alive while the scale's file dialog is open
    std::vector<std::unique_ptr<ControlPanel>> panels_;
    Keyboard keyboard_;
    juce::TextButton pluck_{"Pluck"};
    int pluckedNote_ = -1;  // the note the Pluck button holds, -1 when up
    juce::Array<juce::File> userPresets_;
    std::vector<float> recent_;
    InstrumentSnapshot snapshot_{};

    JUCE_DECLARE_NON_COPYABLE_WITH_LEAK_DETECTOR(JawariEditor)
};

}  // namespace jawari::plugin
