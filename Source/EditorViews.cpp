#include "EditorViews.h"

#include "EditorStyle.h"

#include <cmath>

namespace jawari::plugin
{
namespace
{
// The damping curve editor's vertical scale, in octaves of multiplier: x1 in the middle, the
// engine's limits at the edges (reciprocal, so the scale is symmetric).
static_assert(kDampingCurveMin * kDampingCurveMax == 1.0);
const float kCurveOctaves = std::log2(static_cast<float>(kDampingCurveMax));

// The curve's range as the editor labels it: "x1/8 .. x8".
juce::String dampingCurveRangeText()
{
    return "x1/" + juce::String(juce::roundToInt(1.0 / kDampingCurveMin)) + " .. x"
           + juce::String(juce::roundToInt(kDampingCurveMax));
}
}  // namespace

void StringView::paint(juce::Graphics& g)
{
    const auto area = getLocalBounds().toFloat().reduced(8.0f);
    g.setColour(kPanel);
    g.fillRoundedRectangle(getLocalBounds().toFloat(), 6.0f);
    if (snapshot_.sequence == 0)
    {
        g.setColour(kText);
        g.setFont(13.0f);
        g.drawText("string: waiting for audio", area.toNearestInt(), juce::Justification::topLeft);
        return;
    }
    float peak = 0.0f;
    for (int k = 0; k < kDrawPoints; ++k)
    {
        peak = std::max({peak, std::abs(snapshot_.shape[size_t(k)]), std::abs(snapshot_.horizontal[size_t(k)])});
        if (std::isfinite(snapshot_.obstacle[size_t(k)]))
            peak = std::max(peak, std::abs(snapshot_.obstacle[size_t(k)]));
    }
    scale_ = std::max({peak * 1.2f, 0.97f * scale_, 5e-5f});
    auto toY = [&](float u) { return area.getCentreY() - u / scale_ * 0.5f * area.getHeight(); };
    auto toX = [&](int k) { return area.getX() + area.getWidth() * float(k) / float(kDrawPoints - 1); };
    g.setColour(kGrid);
    g.drawHorizontalLine(int(area.getCentreY()), area.getX(), area.getRight());
    g.setColour(kObstacle);
    for (int k = 0; k < kDrawPoints; ++k)
    {
        const float h = snapshot_.obstacle[size_t(k)];
        if (!std::isfinite(h))
            continue;
        const float y = toY(h);
        g.fillRect(juce::Rectangle<float>(toX(k) - 3.0f, y, 6.0f, area.getBottom() - y));
    }
    auto trace = [&](const std::array<float, kDrawPoints>& u) {
        juce::Path path;
        for (int k = 0; k < kDrawPoints; ++k)
        {
            const float y = toY(u[size_t(k)]);
            if (k == 0)
                path.startNewSubPath(toX(k), y);
            else
                path.lineTo(toX(k), y);
        }
        return path;
    };
    if (snapshot_.twoPolarisations)
    {
        // The horizontal polarisation, seen from above, faint behind the vertical.
        g.setColour(kString.withAlpha(0.4f));
        g.strokePath(trace(snapshot_.horizontal), juce::PathStrokeType(1.5f));
    }
    g.setColour(kString);
    g.strokePath(trace(snapshot_.shape), juce::PathStrokeType(2.0f));
    g.setColour(kText);
    g.setFont(13.0f);
    const juce::String what = snapshot_.twoPolarisations ? "string: vertical, horizontal faint" : "string";
    g.drawText(what + " (full height " + juce::String(scale_ * 1e3f, 3) + " mm)", area.toNearestInt(),
               juce::Justification::topLeft);
}

SpectrumView::SpectrumView()
{
    window_.resize(kSize);
    for (int n = 0; n < kSize; ++n)
        window_[size_t(n)] = 0.5f - 0.5f * std::cos(2.0f * juce::MathConstants<float>::pi * float(n) / float(kSize));
    work_.assign(2 * kSize, 0.0f);
    levels_.assign(kSize / 2, -120.0f);
}

void SpectrumView::update(const float* samples, int count, double sampleRate)
{
    rate_ = sampleRate;
    std::fill(work_.begin(), work_.end(), 0.0f);
    for (int n = 0; n < std::min(count, kSize); ++n)
        work_[size_t(n)] = samples[n] * window_[size_t(n)];
    fft_.performFrequencyOnlyForwardTransform(work_.data());
    for (int k = 0; k < kSize / 2; ++k)
    {
        const float db = 20.0f * std::log10(std::max(work_[size_t(k)] * 4.0f / kSize, 1e-7f));
        levels_[size_t(k)] = std::max(db, levels_[size_t(k)] - 3.0f);  // falls 3 dB per frame
    }
    repaint();
}

void SpectrumView::paint(juce::Graphics& g)
{
    g.setColour(kPanel);
    g.fillRoundedRectangle(getLocalBounds().toFloat(), 6.0f);
    const auto area = getLocalBounds().toFloat().reduced(8.0f);
    auto toX = [&](double f) { return area.getX() + area.getWidth() * float(std::log(f / 20.0) / std::log(1000.0)); };
    auto toY = [&](float db) { return area.getY() + area.getHeight() * juce::jlimit(0.0f, 1.0f, -db / 100.0f); };
    g.setColour(kGrid);
    for (double f : {100.0, 1000.0, 10000.0})
        g.drawVerticalLine(int(toX(f)), area.getY(), area.getBottom());
    juce::Path path;
    bool started = false;
    for (int k = 1; k < kSize / 2; ++k)
    {
        const double f = k * rate_ / kSize;
        if (f < 20.0 || f > 20000.0)
            continue;
        const float x = toX(f), y = toY(levels_[size_t(k)]);
        if (!started)
            path.startNewSubPath(x, y);
        else
            path.lineTo(x, y);
        started = true;
    }
    g.setColour(kObstacle);
    g.strokePath(path, juce::PathStrokeType(1.2f));
    g.setColour(kText);
    g.setFont(13.0f);
    g.drawText("spectrum 20 Hz - 20 kHz, 0 to -100 dB", area.toNearestInt(), juce::Justification::topLeft);
}

juce::Point<float> DampingCurveEditor::pointPosition(int i) const
{
    const auto area = getLocalBounds().toFloat().reduced(14.0f);
    const float x = area.getX() + area.getWidth() * float(i) / float(kDampingCurvePoints - 1);
    const float octaves = std::log2(processor_.dampingCurvePoint(i));  // -kCurveOctaves .. kCurveOctaves
    return {x, area.getCentreY() - octaves / kCurveOctaves * 0.5f * area.getHeight()};
}

int DampingCurveEditor::nearest(juce::Point<float> p) const
{
    int best = 0;
    for (int i = 1; i < kDampingCurvePoints; ++i)
        if (std::abs(pointPosition(i).x - p.x) < std::abs(pointPosition(best).x - p.x))
            best = i;
    return best;
}

void DampingCurveEditor::paint(juce::Graphics& g)
{
    g.setColour(kPanel);
    g.fillRoundedRectangle(getLocalBounds().toFloat(), 6.0f);
    const auto area = getLocalBounds().toFloat().reduced(14.0f);
    g.setColour(kGrid);
    g.drawHorizontalLine(int(area.getCentreY()), area.getX(), area.getRight());
    juce::Path path;
    for (int i = 0; i < kDampingCurvePoints; ++i)
    {
        const auto p = pointPosition(i);
        if (i == 0)
            path.startNewSubPath(p);
        else
            path.lineTo(p);
    }
    g.setColour(kString);
    g.strokePath(path, juce::PathStrokeType(1.5f));
    for (int i = 0; i < kDampingCurvePoints; ++i)
        g.fillEllipse(juce::Rectangle<float>(9.0f, 9.0f).withCentre(pointPosition(i)));
    g.setColour(kText);
    g.setFont(13.0f);
    g.drawText("per-mode damping " + dampingCurveRangeText() + ", 20 Hz - 20 kHz (drag; double-click resets)",
               area.toNearestInt(), juce::Justification::topLeft);
}

void DampingCurveEditor::mouseDown(const juce::MouseEvent& e)
{
    dragging_ = nearest(e.position);
    mouseDrag(e);
}

void DampingCurveEditor::mouseDrag(const juce::MouseEvent& e)
{
    if (dragging_ < 0)
        return;
    const auto area = getLocalBounds().toFloat().reduced(14.0f);
    const float octaves = juce::jlimit(-kCurveOctaves, kCurveOctaves,
                                       (area.getCentreY() - e.position.y) / (0.5f * area.getHeight()) * kCurveOctaves);
    processor_.setDampingCurvePoint(dragging_, std::exp2(octaves));
    repaint();
}

void DampingCurveEditor::mouseDoubleClick(const juce::MouseEvent&)
{
    for (int i = 0; i < kDampingCurvePoints; ++i)
        processor_.setDampingCurvePoint(i, 1.0f);
    repaint();
}

}  // namespace jawari::plugin
