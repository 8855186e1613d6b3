#pragma once
// The parameters' controls, grouped in titled panels as a player thinks of them, and the table that
// says which panel each parameter sits in, its title and what it does physically.

#include "Parameters.h"

#include <juce_audio_processors/juce_audio_processors.h>
#include <juce_gui_basics/juce_gui_basics.h>

#include <memory>
#include <vector>

namespace jawari::plugin
{

// Every parameter's control: the panel it sits in, its title and what it does physically.
struct ControlSpec
{
    const char* panel;
    const char* id;
    const char* title;
    const char* tooltip;
};
extern const ControlSpec kControls[kParameterCount];
// The panels, row by row as the editor lays them out.
extern const std::vector<std::vector<const char*>> kPanelRows;

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

}  // namespace jawari::plugin
