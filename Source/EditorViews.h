#pragma once
// The editor's live views: the sounding strings over their obstacle (from the engine's lock-free
// snapshot), the output's spectrum, and the per-mode damping curve a player drags.

#include "PluginProcessor.h"

#include <juce_dsp/juce_dsp.h>
#include <juce_gui_basics/juce_gui_basics.h>

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

}  // namespace jawari::plugin
