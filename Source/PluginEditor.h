#pragma once
// The editor: a live drawing of the string and its obstacle (from the engine's lock-free
// snapshot), a contact/energy meter, the output spectrum, the per-mode damping curve, CPU load,
// presets and every parameter. Resizable; the standalone app shows the same editor.

#include "PluginProcessor.h"

#include <juce_audio_processors/juce_audio_processors.h>
#include <juce_dsp/juce_dsp.h>
#include <juce_gui_basics/juce_gui_basics.h>

#include <memory>
#include <vector>

namespace jawari::plugin
{

class StringView : public juce::Component
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

class SpectrumView : public juce::Component
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

class DampingCurveEditor : public juce::Component
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
    void timerCallback() override { refreshFromProcessor(); }
    void refreshPresetList();

    struct Knob
    {
        std::unique_ptr<juce::Slider> slider;
        std::unique_ptr<juce::Label> label;
        std::unique_ptr<juce::AudioProcessorValueTreeState::SliderAttachment> attachment;
    };
    struct Choice
    {
        std::unique_ptr<juce::ComboBox> box;
        std::unique_ptr<juce::Label> label;
        std::unique_ptr<juce::AudioProcessorValueTreeState::ComboBoxAttachment> attachment;
    };
    void addKnob(const char* id, const char* title);
    void addChoice(const char* id, const char* title);

    JawariAudioProcessor& processor_;
    StringView stringView_;
    SpectrumView spectrum_;
    DampingCurveEditor curve_;
    juce::Label meter_;
    juce::ComboBox presets_;
    juce::TextEditor presetName_;
    juce::TextButton savePreset_{"Save preset"};
    juce::ToggleButton drone_{"Tanpura drone"};
    std::unique_ptr<juce::AudioProcessorValueTreeState::ButtonAttachment> droneAttachment_;
    std::vector<Knob> knobs_;
    std::vector<Choice> choices_;
    juce::Array<juce::File> userPresets_;
    std::vector<float> recent_;
    InstrumentSnapshot snapshot_{};
    juce::ComponentBoundsConstrainer constrainer_;

    JUCE_DECLARE_NON_COPYABLE_WITH_LEAK_DETECTOR(JawariEditor)
};

}  // namespace jawari::plugin
