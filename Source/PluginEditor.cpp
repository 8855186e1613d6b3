#include "PluginEditor.h"

#include "ParameterText.h"
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

// Every parameter's control: the panel it sits in, its title and what it does physically.
struct ControlSpec
{
    const char* panel;
    const char* id;
    const char* title;
    const char* tooltip;
};
const ControlSpec kControls[] = {
    {"String", ids::stringType, "String",
     "Which string: its length, mass, diameter, tuning and stiffness. Steel is the paper's 1.002 m string, "
     "sitar steel 0.90 m, bass E 0.864 m."},
    {"String", ids::pluckPosition, "Pluck at",
     "Where the string is plucked, in mm from the bridge end (or type a % of the length). Plucking at 1/n of "
     "the length leaves out every n-th harmonic; near an end sounds brighter."},
    {"String", ids::pickupPosition, "Pickup at",
     "Where the string's motion is heard, in mm from the bridge end (or a %). Harmonics with a node there are "
     "silent; near an end all are heard."},
    {"String", ids::inharmonicity, "Inharmonicity",
     "Bending stiffness B: mode p sounds at p f0 sqrt(1 + B p^2), so the upper partials are stretched sharp. "
     "0 is a perfectly flexible string."},
    {"String", ids::release, "Release", "How long a released note takes to fall 60 dB after note-off."},
    {"Obstacle", ids::obstacleShape, "Shape",
     "What the string beats against: a point (a tanpura's bridge and thread), a curved parabolic bridge "
     "(a sitar's jawari) or five frets under the string."},
    {"Obstacle", ids::obstaclePosition, "Position",
     "Where the obstacle stands, in mm from the bridge end (or a %). A few mm from the end the string wraps "
     "over it and buzzes like a tanpura; at the centre it shortens the period (the pitch rises by 4/3)."},
    {"Obstacle", ids::obstacleHeight, "Height",
     "The obstacle's top against the string at rest: 0 touches it, above 0 pushes into the string, below 0 "
     "leaves a gap the string must swing across before it buzzes."},
    {"Obstacle", ids::obstacleStiffness, "Stiffness",
     "How hard the obstacle is: K in the contact force K [penetration]^alpha, in N/m^(1+alpha). Harder gives "
     "a shorter, brighter contact."},
    {"Obstacle", ids::obstacleExponent, "Exponent",
     "alpha in the contact force K [penetration]^alpha: 1 is a linear spring; higher is soft at first touch "
     "and stiff when pressed deep."},
    {"Obstacle", ids::obstacleWidth, "Width",
     "How much of the string the obstacle touches: a point's width, a bridge's extent along the string, a "
     "fret's width."},
    {"Obstacle", ids::bridgeCurvature, "Curvature",
     "The parabolic bridge's curvature: how fast its surface falls away from the apex (0 is flat). Only the "
     "parabolic bridge uses it."},
    {"Damping", ids::decayScale, "Decay",
     "Scales every mode's damping: x2 dies away twice as fast, x0.5 rings twice as long."},
    {"Damping", ids::airDamping, "Air",
     "Friction of the air on the moving string, times the paper's; it damps the low modes most."},
    {"Damping", ids::viscoelasticLoss, "Viscoelastic",
     "The loss angle delta_ve of the string's material: internal friction as it bends, damping the high "
     "modes most."},
    {"Damping", ids::thermoelasticLoss, "Thermoelastic",
     "Thermoelastic loss 1/Q: heat flow as the string bends, the same damping for every mode."},
    {"Drone", ids::drone, "Drone", "Plays the four-string tanpura drone by itself, its strings plucked in turn."},
    {"Drone", ids::droneTonic, "Sa", "The tonic Sa the drone's strings are tuned from."},
    {"Drone", ids::droneFirst, "First string",
     "The first string's note below Sa: Pa (a fifth), Ma (a fourth), Ni (a major seventh) or Sa."},
    {"Drone", ids::droneTempo, "Tempo", "Plucks per minute: one beat between plucks, two after the low Sa."},
    {"Drone", ids::humanise, "Humanise",
     "Spreads the drone's timing (up to 15 %) and pluck strength (up to 25 %) as a player's hand would."},
    {"Drone", ids::droneStrength, "Strength", "How hard the drone's strings are plucked."},
    {"Drone tuning", ids::droneTuning, "Tuning",
     "How the drone's strings are tuned from Sa: just intervals (Pa 3/4, Ma 2/3, Ni 15/16 below Sa, low Sa 1/2) "
     "or equal temperament."},
    {"Drone tuning", ids::droneSaHz, "Sa in Hz", "Sa as a frequency; at 0 the Sa note sets it."},
    {"Drone tuning", ids::droneFine1, "First", "Fine tune of the first string (Pa, Ma, Ni or Sa)."},
    {"Drone tuning", ids::droneFine2, "Sa", "Fine tune of the Sa string."},
    {"Drone tuning", ids::droneFine3, "Second Sa", "Fine tune of the second Sa string."},
    {"Drone tuning", ids::droneFine4, "Low Sa", "Fine tune of the low Sa string."},
    {"Output", ids::gain, "Gain", "The output level."},
    {"Output", ids::bendRange, "Bend range", "How far the pitch wheel bends the strings, each way."},
    {"Output", ids::stereoWidth, "Width",
     "How far the strings spread across the stereo field by pitch (100 %: from hard left at C3 to hard right at "
     "C7), and how much of the right channel a second pickup reads, 5 % of the string further in: 0 is mono."},
    {"MIDI", ids::mpe, "MPE",
     "MPE (the lower zone): a note on its own channel 2..16 bends, presses (its bridge up to 0.5 mm further "
     "in: more buzz) and slides (its damping) by itself; channel 1 moves every note."},
    {"MIDI", ids::mpeBendRange, "MPE bend", "How far a note's own pitch bend goes under MPE, each way."},
    {"Quality", ids::quality, "Quality",
     "How much of the model runs: standard (eight strings and the drone in real time on one core), draft "
     "for weak machines, high or paper (the most modes and the highest internal rate)."},
    {"Quality", ids::method, "Contact",
     "How the contact force is found each step: energy-conserving (the paper's scheme, never gains energy), "
     "quadratised (no iteration), penalty (explicit, cheapest; unstable on hard obstacles) or quadratic spline "
     "(the paper's scheme on a contact force within 1 % of the law, solved without iteration; a bridge's or "
     "the frets' several points take the energy-conserving method)."},
    {"String", ids::polarisations, "Polarisations",
     "1: the string moves in the vertical only. 2: its horizontal polarisation too, coupled to the vertical near the "
     "far end by a tilted spring, so the string's motion turns and beats as a real string's does."},
    {"Thread", ids::thread, "Thread",
     "The tanpura's thread (jiva) across the curved bridge: the string rests on it, the bridge one diameter below "
     "it there. Sliding it sets the jawari. Parabola shape only."},
    {"Thread", ids::threadPosition, "Position", "Where the thread lies, from the bridge's edge nearer the end."},
    {"Thread", ids::threadDiameter, "Diameter", "How far the thread lifts the string off the bridge."},
    {"Quality", ids::secondCore, "2nd core",
     "Steps half the sounding strings on a second core, beside the host's audio thread: for high quality or many "
     "strings where one core is not enough. The sound is the same to the last bit; off, everything runs on the "
     "audio thread."},
};
static_assert(std::size(kControls) == kParameterCount);

// The panels, row by row as the editor lays them out.
const std::vector<std::vector<const char*>> kPanelRows = {
    {"String", "Output"}, {"Obstacle", "Thread"}, {"Damping", "Quality"}, {"Drone"}, {"Drone tuning", "MIDI"}};

// The keyboard's and the Pluck button's velocity, wherever a key is clicked: the paper's 1.5 mm
// pluck (velocity 100).
constexpr float kKeyVelocity = 100.0f / 127.0f;

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

ParameterControl::ParameterControl(juce::AudioProcessorValueTreeState& state, const char* id, const char* title,
                                   const char* tooltip)
{
    title_.setText(title, juce::dontSendNotification);
    title_.setJustificationType(juce::Justification::centred);
    title_.setTooltip(tooltip);
    addAndMakeVisible(title_);
    auto* parameter = state.getParameter(id);
    jassert(parameter != nullptr);
    juce::Component* control = nullptr;
    if (auto* choice = dynamic_cast<juce::AudioParameterChoice*>(parameter))
    {
        box_ = std::make_unique<juce::ComboBox>();
        box_->addItemList(choice->choices, 1);
        boxAttachment_ = std::make_unique<Attachments::ComboBoxAttachment>(state, id, *box_);
        box_->setTooltip(tooltip);
        control = box_.get();
    }
    else if (dynamic_cast<juce::AudioParameterBool*>(parameter) != nullptr)
    {
        toggle_ = std::make_unique<juce::ToggleButton>("on");
        toggleAttachment_ = std::make_unique<Attachments::ButtonAttachment>(state, id, *toggle_);
        toggle_->setTooltip(tooltip);
        control = toggle_.get();
    }
    else
    {
        slider_ =
            std::make_unique<juce::Slider>(juce::Slider::RotaryHorizontalVerticalDrag, juce::Slider::TextBoxBelow);
        sliderAttachment_ = std::make_unique<Attachments::SliderAttachment>(state, id, *slider_);
        // A double-click returns to the default.
        if (auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(parameter))
            slider_->setDoubleClickReturnValue(true, ranged->convertFrom0to1(ranged->getDefaultValue()));
        slider_->setTooltip(tooltip);
        control = slider_.get();
    }
    // Clicking a control leaves the keyboard focus with the on-screen keyboard.
    control->setMouseClickGrabsKeyboardFocus(false);
    control->setComponentID(id);
    addAndMakeVisible(control);
}

void ParameterControl::resized()
{
    auto area = getLocalBounds();
    title_.setBounds(area.removeFromTop(18));
    if (slider_ != nullptr)
    {
        slider_->setTextBoxStyle(juce::Slider::TextBoxBelow, false, area.getWidth(), 20);
        slider_->setBounds(area);
    }
    const auto middle = area.withSizeKeepingCentre(area.getWidth(), 26);
    if (box_ != nullptr)
        box_->setBounds(middle.reduced(2, 0));
    if (toggle_ != nullptr)
        toggle_->setBounds(middle.withSizeKeepingCentre(std::min(area.getWidth(), 60), 26));
}

void ParameterControl::refreshText()
{
    if (slider_ != nullptr)
        slider_->updateText();
}

void ControlPanel::add(std::unique_ptr<ParameterControl> control)
{
    addAndMakeVisible(*control);
    controls_.push_back(std::move(control));
}

float ControlPanel::cells() const
{
    float sum = 0.0f;
    for (const auto& c : controls_)
        sum += c->width();
    return sum;
}

void ControlPanel::refreshTexts()
{
    for (auto& c : controls_)
        c->refreshText();
}

void ControlPanel::paint(juce::Graphics& g)
{
    g.setColour(kPanel);
    g.fillRoundedRectangle(getLocalBounds().toFloat(), 6.0f);
    g.setColour(kString);
    g.setFont(juce::Font(13.0f, juce::Font::bold));
    g.drawText(title_.toUpperCase(), getLocalBounds().reduced(10, 4).removeFromTop(16),
               juce::Justification::centredLeft);
}

void ControlPanel::resized()
{
    auto area = getLocalBounds().reduced(4);
    area.removeFromTop(18);
    const float cell = float(area.getWidth()) / std::max(cells(), 1.0f);
    for (auto& c : controls_)
        c->setBounds(area.removeFromLeft(juce::roundToInt(cell * c->width())).reduced(2, 0));
}

JawariLookAndFeel::JawariLookAndFeel()
{
    setColour(juce::Label::textColourId, kText);
    setColour(juce::Slider::rotarySliderFillColourId, kObstacle);
    setColour(juce::Slider::thumbColourId, kString);
    setColour(juce::Slider::textBoxOutlineColourId, juce::Colours::transparentBlack);
    setColour(juce::TooltipWindow::backgroundColourId, juce::Colour(0xff2b303a));
    setColour(juce::TooltipWindow::textColourId, kText);
}

juce::Label* JawariLookAndFeel::createSliderTextBox(juce::Slider& slider)
{
    // Values with their units ("1.0e13 N/m^2.3") fit a narrow cell: a smaller font, squeezed if need be.
    auto* label = LookAndFeel_V4::createSliderTextBox(slider);
    label->setFont(juce::Font(13.0f));
    label->setMinimumHorizontalScale(0.7f);
    return label;
}

JawariEditor::JawariEditor(JawariAudioProcessor& p)
    : AudioProcessorEditor(p)
    , processor_(p)
    , curve_(p)
    , keyboard_(p.keyboardState(), juce::MidiKeyboardComponent::horizontalKeyboard)
{
    setLookAndFeel(&lookAndFeel_);
    addAndMakeVisible(stringView_);
    stringView_.setTooltip("The sounding strings and the obstacle (blue), drawn live; the height is scaled to "
                           "the motion.");
    addAndMakeVisible(spectrum_);
    spectrum_.setTooltip("The output's spectrum.");
    addAndMakeVisible(curve_);
    curve_.setTooltip("Per-mode damping: multiplies each mode's damping by the curve at its frequency. Drag a "
                      "point; a double-click resets the curve flat.");
    addAndMakeVisible(meter_);
    meter_.setFont(juce::Font(13.0f));
    meter_.setJustificationType(juce::Justification::topLeft);
    addAndMakeVisible(status_);
    status_.setFont(juce::Font(13.0f));
    status_.setColour(juce::Label::textColourId, juce::Colour(0xffffb040));
    status_.setJustificationType(juce::Justification::topLeft);
    status_.setTooltip("What Jawari refused or had to correct, and why; empty while all is well.");
    setUpPresets();
    setUpScale();
    for (const auto& row : kPanelRows)
        for (const char* title : row)
        {
            auto panel = std::make_unique<ControlPanel>(title);
            for (const auto& c : kControls)
                if (juce::String(c.panel) == title)
                    panel->add(std::make_unique<ParameterControl>(processor_.parameters(), c.id, c.title, c.tooltip));
            addAndMakeVisible(*panel);
            panels_.push_back(std::move(panel));
        }
    setUpPlaying();
    refreshTexts();

    setResizable(true, true);
    setResizeLimits(1000, 760, 2400, 1600);
    setSize(1240, 900);
    startTimerHz(30);
}

JawariEditor::~JawariEditor()
{
    stopTimer();
    pluck(false);
    setLookAndFeel(nullptr);
}

void JawariEditor::setUpPresets()
{
    addAndMakeVisible(presets_);
    presets_.setTooltip("Factory presets, then yours (saved with the name on the right).");
    presets_.onChange = [this] {
        const int id = presets_.getSelectedId();
        const int factory = static_cast<int>(factoryPresets().size());
        if (id >= 1 && id <= factory)
            processor_.setCurrentProgram(id - 1);
        else if (id > factory && id - factory - 1 < userPresets_.size())
        {
            const auto result = processor_.loadUserPreset(userPresets_[id - factory - 1]);
            editorNote_ = result.failed() ? result.getErrorMessage() : juce::String();
        }
        curve_.repaint();
    };
    addAndMakeVisible(presetName_);
    presetName_.setTextToShowWhenEmpty("preset name", juce::Colours::grey);
    addAndMakeVisible(savePreset_);
    savePreset_.setTooltip("Saves every parameter and the damping curve as a user preset.");
    savePreset_.onClick = [this] {
        const auto result = processor_.saveUserPreset(presetName_.getText());
        editorNote_ = result.wasOk() ? juce::String() : result.getErrorMessage();
        refreshPresetList();
    };
    refreshPresetList();
}

// The keyboard's tuning: a Scala scale (.scl) chosen from a file dialog, with the keyboard map
// (.kbm) of the same name beside it when there is one; or back to equal temperament.
void JawariEditor::setUpScale()
{
    addAndMakeVisible(scale_);
    scale_.setTooltip("The keyboard's tuning: equal temperament, or a Scala scale (.scl) with the keyboard map "
                      "(.kbm) of the same name beside it, kept in the plugin's state.");
    scale_.setButtonText("Scale: " + processor_.keyboardTuningName());
    scale_.onClick = [this] {
        juce::PopupMenu menu;
        menu.addItem(1, "Load a Scala scale...");
        menu.addItem(2, "Equal temperament");
        menu.showMenuAsync(juce::PopupMenu::Options().withTargetComponent(&scale_), [this](int choice) {
            if (choice == 1)
                chooseScale();
            else if (choice == 2)
            {
                processor_.setKeyboardTuning({}, {});
                scale_.setButtonText("Scale: " + processor_.keyboardTuningName());
            }
        });
    };
}

void JawariEditor::chooseScale()
{
    chooser_ = std::make_unique<juce::FileChooser>("A Scala scale", juce::File(), "*.scl");
    chooser_->launchAsync(juce::FileBrowserComponent::openMode | juce::FileBrowserComponent::canSelectFiles,
                          [this](const juce::FileChooser& chooser) {
                              const auto file = chooser.getResult();
                              if (file == juce::File())
                                  return;
                              const auto map = file.withFileExtension("kbm");
                              const auto error = processor_.setKeyboardTuning(
                                  file.loadFileAsString(),
                                  map.existsAsFile() ? map.loadFileAsString() : juce::String());
                              editorNote_ = error.isNotEmpty() ? file.getFileName() + ": " + error : juce::String();
                              scale_.setButtonText("Scale: " + processor_.keyboardTuningName());
                          });
}

void JawariEditor::setUpPlaying()
{
    // C1 to C7 on screen; the computer keyboard's row A S D F ... plays C3 to E4.
    keyboard_.setAvailableRange(24, 96);
    keyboard_.setOctaveForMiddleC(4);
    keyboard_.setKeyPressBaseOctave(4);
    keyboard_.setVelocity(kKeyVelocity, false);
    keyboard_.setScrollButtonsVisible(false);
    keyboard_.setWantsKeyboardFocus(true);
    keyboard_.setTooltip("Click to play, or type on the computer keyboard: A W S E D F T G Y H U J K O L P ; "
                         "play C3 to E4.");
    addAndMakeVisible(keyboard_);
    pluck_.setComponentID("pluck");
    pluck_.setMouseClickGrabsKeyboardFocus(false);
    pluck_.setTooltip("Plucks the drone's tonic Sa while held, the paper's 1.5 mm pluck.");
    pluck_.onStateChange = [this] { pluck(pluck_.isDown()); };
    addAndMakeVisible(pluck_);
}

void JawariEditor::pluck(bool down)
{
    auto& keys = processor_.keyboardState();
    if (down && pluckedNote_ < 0)
    {
        pluckedNote_ = juce::roundToInt(processor_.parameters().getRawParameterValue(ids::droneTonic)->load());
        keys.noteOn(1, pluckedNote_, kKeyVelocity);
    }
    else if (!down && pluckedNote_ >= 0)
    {
        keys.noteOff(1, pluckedNote_, 0.0f);
        pluckedNote_ = -1;
    }
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
    presets_.setBounds(top.removeFromLeft(300).reduced(2));
    presetName_.setBounds(top.removeFromLeft(160).reduced(2));
    savePreset_.setBounds(top.removeFromLeft(110).reduced(2));
    scale_.setBounds(top.removeFromLeft(260).reduced(2));
    area.removeFromTop(6);
    layOutPlaying(area.removeFromBottom(96));
    area.removeFromBottom(6);

    auto left = area.removeFromLeft(area.getWidth() * 2 / 5);
    stringView_.setBounds(left.removeFromTop(left.getHeight() * 36 / 100).reduced(3));
    meter_.setBounds(left.removeFromTop(40).reduced(3));
    status_.setBounds(left.removeFromTop(36).reduced(3));
    spectrum_.setBounds(left.removeFromTop(left.getHeight() / 2).reduced(3));
    curve_.setBounds(left.reduced(3));
    layOutPanels(area.withTrimmedLeft(4));
}

void JawariEditor::layOutPanels(juce::Rectangle<int> area)
{
    // Rows of equal height; in a row each panel's width is in proportion to its controls.
    const int rowHeight = area.getHeight() / int(kPanelRows.size());
    size_t next = 0;
    for (const auto& row : kPanelRows)
    {
        auto rowArea = area.removeFromTop(rowHeight);
        float cells = 0.0f;
        for (size_t i = 0; i < row.size(); ++i)
            cells += panels_[next + i]->cells();
        const float cell = float(rowArea.getWidth()) / cells;
        for (size_t i = 0; i < row.size(); ++i, ++next)
        {
            const int width =
                i + 1 == row.size() ? rowArea.getWidth() : juce::roundToInt(cell * panels_[next]->cells());
            panels_[next]->setBounds(rowArea.removeFromLeft(width).reduced(3));
        }
    }
}

void JawariEditor::layOutPlaying(juce::Rectangle<int> area)
{
    pluck_.setBounds(area.removeFromLeft(110).reduced(3, 20));
    area.removeFromLeft(6);
    keyboard_.setBounds(area);
    // Every key of the range fits the width.
    int whiteKeys = 0;
    for (int note = keyboard_.getRangeStart(); note <= keyboard_.getRangeEnd(); ++note)
        whiteKeys += juce::MidiMessage::isMidiNoteBlack(note) ? 0 : 1;
    keyboard_.setKeyWidth(float(area.getWidth()) / float(std::max(whiteKeys, 1)));
}

void JawariEditor::timerCallback()
{
    refreshFromProcessor();
    // In the standalone app the on-screen keyboard holds the focus whenever the window has it and
    // nothing else in the editor does, so the computer keyboard plays. (In a host the keyboard takes
    // the focus when clicked, leaving the host's shortcuts alone until then.)
    const bool standalone = processor_.wrapperType == juce::AudioProcessor::wrapperType_Standalone;
    auto* focused = juce::Component::getCurrentlyFocusedComponent();
    if (auto* peer = getPeer(); standalone && peer != nullptr && peer->isFocused() && !isParentOf(focused))
        keyboard_.grabKeyboardFocus();
}

void JawariEditor::refreshTexts()
{
    for (auto& panel : panels_)
        panel->refreshTexts();
    const int tonic = juce::roundToInt(processor_.parameters().getRawParameterValue(ids::droneTonic)->load());
    pluck_.setButtonText("Pluck " + text::noteName(tonic));
}

void JawariEditor::refreshFromProcessor()
{
    refreshTexts();
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
    status_.setText(statusText(), juce::dontSendNotification);
}

// What the player should know went wrong: a refused build or state, the editor's last failed
// action, the output guard or the blow-up guard having acted, a block that threw.
juce::String JawariEditor::statusText() const
{
    juce::StringArray notes;
    if (const auto problem = processor_.problem(); problem.isNotEmpty())
        notes.add(problem);
    if (editorNote_.isNotEmpty())
        notes.add(editorNote_);
    if (snapshot_.limited > 0)
        notes.add(juce::String(snapshot_.limited)
                  + " output samples held by the guard (beyond +12 dBFS or not a number): lower the gain");
    if (snapshot_.blowUps > 0)
        notes.add(juce::String(snapshot_.blowUps) + " string blow-ups stopped and restarted by the runaway guard");
    if (const long faults = processor_.renderFaults(); faults > 0)
        notes.add(juce::String(faults) + " blocks silenced after an error on the audio thread");
    return notes.joinIntoString("  |  ");
}

}  // namespace jawari::plugin
