#include "PluginEditor.h"

#include "Presets.h"

#include <cmath>

namespace jawari::plugin
{
namespace
{
const juce::Colour kBackground{0xff15171c}, kPanel{0xff1f232b}, kString{0xfff2c14e}, kObstacle{0xff6fb3d2},
    kGrid{0xff343a46}, kText{0xffd8dde6};

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
        peak = std::max(peak, std::abs(snapshot_.shape[size_t(k)]));
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
    juce::Path path;
    for (int k = 0; k < kDrawPoints; ++k)
    {
        const float y = toY(snapshot_.shape[size_t(k)]);
        if (k == 0)
            path.startNewSubPath(toX(k), y);
        else
            path.lineTo(toX(k), y);
    }
    g.setColour(kString);
    g.strokePath(path, juce::PathStrokeType(2.0f));
    g.setColour(kText);
    g.setFont(13.0f);
    g.drawText("string (full height " + juce::String(scale_ * 1e3f, 3) + " mm)", area.toNearestInt(),
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

JawariEditor::JawariEditor(JawariAudioProcessor& p)
    : AudioProcessorEditor(p)
    , processor_(p)
    , curve_(p)
{
    addAndMakeVisible(stringView_);
    addAndMakeVisible(spectrum_);
    addAndMakeVisible(curve_);
    addAndMakeVisible(meter_);
    meter_.setColour(juce::Label::textColourId, kText);
    meter_.setFont(juce::Font(13.0f));
    meter_.setJustificationType(juce::Justification::topLeft);

    addAndMakeVisible(presets_);
    presets_.onChange = [this] {
        const int id = presets_.getSelectedId();
        const int factory = static_cast<int>(factoryPresets().size());
        if (id >= 1 && id <= factory)
            processor_.setCurrentProgram(id - 1);
        else if (id > factory && id - factory - 1 < userPresets_.size())
        {
            const auto result = processor_.loadUserPreset(userPresets_[id - factory - 1]);
            if (result.failed())
                meter_.setText(result.getErrorMessage(), juce::dontSendNotification);
        }
        curve_.repaint();
    };
    addAndMakeVisible(presetName_);
    presetName_.setTextToShowWhenEmpty("preset name", juce::Colours::grey);
    addAndMakeVisible(savePreset_);
    savePreset_.onClick = [this] {
        const auto result = processor_.saveUserPreset(presetName_.getText());
        meter_.setText(result.wasOk() ? "saved " + presetName_.getText() : result.getErrorMessage(),
                       juce::dontSendNotification);
        refreshPresetList();
    };
    refreshPresetList();

    addAndMakeVisible(drone_);
    droneAttachment_ = std::make_unique<juce::AudioProcessorValueTreeState::ButtonAttachment>(processor_.parameters(),
                                                                                              ids::drone, drone_);
    addChoice(ids::stringType, "String");
    addChoice(ids::obstacleShape, "Obstacle");
    addChoice(ids::quality, "Quality");
    addChoice(ids::method, "Method");
    addChoice(ids::droneFirst, "First string");
    for (const auto& [id, title] :
         std::vector<std::pair<const char*, const char*>>{{ids::obstaclePosition, "Position"},
                                                          {ids::obstacleHeight, "Height mm"},
                                                          {ids::obstacleStiffness, "log10 K"},
                                                          {ids::obstacleExponent, "Exponent"},
                                                          {ids::obstacleWidth, "Width mm"},
                                                          {ids::bridgeCurvature, "Curvature"},
                                                          {ids::pluckPosition, "Pluck at"},
                                                          {ids::pickupPosition, "Pickup at"},
                                                          {ids::inharmonicity, "Inharmonicity"},
                                                          {ids::release, "Release s"},
                                                          {ids::decayScale, "Decay x"},
                                                          {ids::airDamping, "Air x"},
                                                          {ids::viscoelasticLoss, "Visco"},
                                                          {ids::thermoelasticLoss, "Thermo"},
                                                          {ids::gain, "Gain dB"},
                                                          {ids::bendRange, "Bend st"},
                                                          {ids::droneTonic, "Sa (MIDI)"},
                                                          {ids::droneTempo, "Tempo"},
                                                          {ids::humanise, "Humanise"},
                                                          {ids::droneStrength, "Drone strength"}})
        addKnob(id, title);

    constrainer_.setMinimumSize(860, 600);
    setResizable(true, true);
    setResizeLimits(860, 600, 2400, 1600);
    setSize(1100, 720);
    startTimerHz(30);
}

JawariEditor::~JawariEditor()
{
    stopTimer();
}

void JawariEditor::addKnob(const char* id, const char* title)
{
    Knob k;
    k.slider = std::make_unique<juce::Slider>(juce::Slider::RotaryHorizontalVerticalDrag, juce::Slider::TextBoxBelow);
    k.slider->setTextBoxStyle(juce::Slider::TextBoxBelow, false, 80, 18);
    k.label = std::make_unique<juce::Label>(juce::String(), title);
    k.label->setJustificationType(juce::Justification::centred);
    k.label->setColour(juce::Label::textColourId, kText);
    k.attachment =
        std::make_unique<juce::AudioProcessorValueTreeState::SliderAttachment>(processor_.parameters(), id, *k.slider);
    addAndMakeVisible(*k.slider);
    addAndMakeVisible(*k.label);
    knobs_.push_back(std::move(k));
}

void JawariEditor::addChoice(const char* id, const char* title)
{
    Choice c;
    c.box = std::make_unique<juce::ComboBox>();
    if (auto* choice = dynamic_cast<juce::AudioParameterChoice*>(processor_.parameters().getParameter(id)))
        c.box->addItemList(choice->choices, 1);
    c.label = std::make_unique<juce::Label>(juce::String(), title);
    c.label->setColour(juce::Label::textColourId, kText);
    c.attachment =
        std::make_unique<juce::AudioProcessorValueTreeState::ComboBoxAttachment>(processor_.parameters(), id, *c.box);
    addAndMakeVisible(*c.box);
    addAndMakeVisible(*c.label);
    choices_.push_back(std::move(c));
}

void JawariEditor::refreshPresetList()
{
    presets_.clear(juce::dontSendNotification);
    int id = 1;
    for (const auto& preset : factoryPresets())
        presets_.addItem(preset.name, id++);
    userPresets_ = userPresetFolder().findChildFiles(juce::File::findFiles, false, "*.jawaripreset");
    userPresets_.sort();
    if (!userPresets_.isEmpty())
        presets_.addSeparator();
    for (const auto& f : userPresets_)
        presets_.addItem("user: " + f.getFileNameWithoutExtension(), id++);
    presets_.setSelectedId(processor_.getCurrentProgram() + 1, juce::dontSendNotification);
}

void JawariEditor::paint(juce::Graphics& g)
{
    g.fillAll(kBackground);
    g.setColour(kText);
    g.setFont(juce::Font(20.0f, juce::Font::bold));
    g.drawText("JAWARI", 12, 8, 120, 28, juce::Justification::centredLeft);
}

void JawariEditor::resized()
{
    auto area = getLocalBounds().reduced(8);
    auto top = area.removeFromTop(32);
    top.removeFromLeft(120);
    presets_.setBounds(top.removeFromLeft(260).reduced(2));
    presetName_.setBounds(top.removeFromLeft(160).reduced(2));
    savePreset_.setBounds(top.removeFromLeft(110).reduced(2));
    drone_.setBounds(top.removeFromLeft(140).reduced(2));
    area.removeFromTop(6);

    auto left = area.removeFromLeft(area.getWidth() * 11 / 20);
    stringView_.setBounds(left.removeFromTop(left.getHeight() * 36 / 100).reduced(3));
    meter_.setBounds(left.removeFromTop(48).reduced(3));
    spectrum_.setBounds(left.removeFromTop(left.getHeight() / 2).reduced(3));
    curve_.setBounds(left.reduced(3));

    auto right = area.reduced(4, 0);
    auto choiceRow = right.removeFromTop(52);
    const int choiceWidth = choiceRow.getWidth() / int(choices_.size());
    for (auto& c : choices_)
    {
        auto cell = choiceRow.removeFromLeft(choiceWidth).reduced(2);
        c.label->setBounds(cell.removeFromTop(20));
        c.box->setBounds(cell.removeFromTop(26));
    }
    const int columns = 5;
    const int rows = (int(knobs_.size()) + columns - 1) / columns;
    const int cellWidth = right.getWidth() / columns, cellHeight = right.getHeight() / std::max(rows, 1);
    for (size_t i = 0; i < knobs_.size(); ++i)
    {
        const int row = int(i) / columns, column = int(i) % columns;
        auto cell = juce::Rectangle<int>(right.getX() + column * cellWidth, right.getY() + row * cellHeight, cellWidth,
                                         cellHeight)
                        .reduced(2);
        knobs_[i].label->setBounds(cell.removeFromTop(18));
        knobs_[i].slider->setBounds(cell);
    }
}

void JawariEditor::refreshFromProcessor()
{
    if (processor_.instrument().snapshots().read(snapshot_))
        stringView_.setSnapshot(snapshot_);
    recent_.resize(4096);
    const int n = processor_.readRecentOutput(recent_.data(), 4096);
    spectrum_.update(recent_.data(), n, processor_.getSampleRate() > 0 ? processor_.getSampleRate() : 48000.0);
    meter_.setText(juce::String::formatted("energy %.3g mJ   penetration %.3g um   Newton max %d   strings %d   "
                                           "CPU %.1f %%   latency %d   recoveries %ld",
                                           double(snapshot_.energy) * 1e3, double(snapshot_.penetration) * 1e6,
                                           snapshot_.maxIterations, snapshot_.activeStrings,
                                           double(processor_.cpuLoad()) * 100.0, processor_.getLatencySamples(),
                                           snapshot_.blowUps),
                   juce::dontSendNotification);
}

}  // namespace jawari::plugin
