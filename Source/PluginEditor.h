#pragma once
// The editor: the string and its obstacle drawn live (from the engine's lock-free snapshot), the
// contact/energy meter, the output spectrum and the per-mode damping curve on the left; the
// parameters on the right in titled panels as a player thinks of them (string, obstacle, damping,
// drone, output, quality), each value in its unit and each control with a tooltip saying what it
// does physically; an on-screen keyboard (also played from the computer keyboard) and a Pluck
// button along the bottom. Resizable; the standalone app shows the same editor.

#include "PluginProcessor.h"

#include <juce_audio_processors/juce_audio_processors.h>
#include <juce_audio_utils/juce_audio_utils.h>
#include <juce_dsp/juce_dsp.h>
#include <juce_gui_basics/juce_gui_basics.h>

#include <memory>
#include <vector>

namespace jawari::plugin
{

class StringView : public juce::Component, public juce::SettableTooltipClient
{
public:
    void setSnapshot(const InstrumentSnapshot& s)
    {
        snapshot_ = s;
        repaint();
    }
    void paint(juce::Graphics& g) override;

private:
    InstrumentSnapshot snapshot_{};
    float scale_ = 1e-4f;  // metres at full height, follows the motion with a slow release
};

class SpectrumView : public juce::Component, public juce::SettableTooltipClient
{
public:
    SpectrumView();
    void update(const float* samples, int count, double sampleRate);
    void paint(juce::Graphics& g) override;

private:
    static constexpr int kOrder = 12, kSize = 1 << kOrder;
    juce::dsp::FFT fft_{kOrder};
    std::vector<float> window_, work_, levels_;
    double rate_ = 48000.0;
};

class DampingCurveEditor : public juce::Component, public juce::SettableTooltipClient
{
public:
    explicit DampingCurveEditor(JawariAudioProcessor& p)
        : processor_(p)
    {}
    void paint(juce::Graphics& g) override;
    void mouseDown(const juce::MouseEvent& e) override;
    void mouseDrag(const juce::MouseEvent& e) override;
    void mouseDoubleClick(const juce::MouseEvent& e) override;

private:
    juce::Point<float> pointPosition(int i) const;
    int nearest(juce::Point<float> p) const;
    JawariAudioProcessor& processor_;
    int dragging_ = -1;
};

// One parameter's control: a rotary slider, a combo box for a choice or a toggle for an on/off,
// its title above, attached to the parameter; the control's component ID is the parameter's ID.
class ParameterControl : public juce::Component
{
public:
    ParameterControl(juce::AudioProcessorValueTreeState& state, const char* id, const char* title, const char* tooltip);
    void resized() override;
    // Rereads the value text, which may depend on other parameters (positions on the string's
    // length, stiffness in the exponent's unit).
    void refreshText();
    // How many cells of a panel's row it takes: a choice's names need more room than a knob.
    float width() const { return box_ != nullptr ? 1.5f : 1.0f; }

private:
    using Attachments = juce::AudioProcessorValueTreeState;
    juce::Label title_;
    std::unique_ptr<juce::Slider> slider_;
    std::unique_ptr<juce::ComboBox> box_;
    std::unique_ptr<juce::ToggleButton> toggle_;
    std::unique_ptr<Attachments::SliderAttachment> sliderAttachment_;
    std::unique_ptr<Attachments::ComboBoxAttachment> boxAttachment_;
    std::unique_ptr<Attachments::ButtonAttachment> toggleAttachment_;
};

// A titled group of controls laid out in a row of equal cells.
class ControlPanel : public juce::Component
{
public:
    explicit ControlPanel(const juce::String& title)
        : title_(title)
    {}
    void add(std::unique_ptr<ParameterControl> control);
    // The controls' widths in cells, added up.
    float cells() const;
    void refreshTexts();
    void paint(juce::Graphics& g) override;
    void resized() override;

private:
    juce::String title_;
    std::vector<std::unique_ptr<ParameterControl>> controls_;
};

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
