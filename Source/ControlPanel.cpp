#include "ControlPanel.h"

#include "EditorStyle.h"

namespace jawari::plugin
{

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
     "C7), and how much of the right channel a second pickup reads, 5 % of the string further in: 0 is mono. "
     "Through a body, also how far each channel hears the body from 30 degrees to its side rather than from "
     "in front."},
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
    {"Thread", ids::threadModel, "Model",
     "Damped: the cotton thread as van Walstijn, Bridges and Mehes model it (DAFx-16), a spring and damper over its "
     "1.2 mm that the string never leaves; its damping softens the high ringing between the bridge and the end. "
     "Rigid: a contact as hard as the bridge's."},
    {"Thread", ids::threadStiffness, "Stiffness", "How hard the damped thread pulls the string back to it."},
    {"Thread", ids::threadDamping, "Damping", "How much the damped thread takes out of the string's motion there."},
    {"Quality", ids::secondCore, "2nd core",
     "Steps half the sounding strings on a second core, beside the host's audio thread: for high quality or many "
     "strings where one core is not enough. The sound is the same to the last bit; off, everything runs on the "
     "audio thread."},
    {"Quality", ids::voices, "Voices",
     "How many notes sound at once; a note beyond them takes the quietest or oldest. Fewer cost less, most "
     "through a body."},
    {"String", ids::pluckStyle, "Pluck",
     "Sharp: a 1.5 ms flick at the pluck point. Soft: a finger's push, rising over 50 ms and letting go "
     "abruptly; through a body the sound then grows for half a second as the bridge wakes the high partials."},
    {"Body", ids::body, "Body",
     "What the bridge stands on. A tanpura's top plate (fitted to a measured tanpura's response) or a sitar's "
     "(the same build at a sitar's size: higher and sparser modes) moves with the bridge and radiates the sound "
     "you hear; none: rigid supports, heard through the pickup."},
    {"Body", ids::bodyMix, "Mix", "With a body: its radiated sound at 100 %, the pickup (the string's velocity) at 0."},
    {"Body", ids::bodyTuning, "Tuning", "Scales every body mode's frequency: a smaller body sounds higher."},
    {"Body", ids::bodyDamping, "Damping", "Scales every body mode's damping."},
    {"Sympathetic", ids::sympathetic, "Strings",
     "The sitar's sympathetic strings (taraf): never plucked, they ring when the body moves them at their pitch. "
     "Only with a body."},
    {"Sympathetic", ids::sympatheticScale, "Tuning",
     "The thaat they are tuned to, upwards from the Pa below the upper Sa (the drone's Sa), or Sa and Pa alone."},
    {"Sympathetic", ids::sympatheticIntonation, "Intonation",
     "Just: pure intervals above Sa. Keyboard: the pitch the keyboard plays for each note (its Scala scale)."},
    {"Sympathetic", ids::sympatheticDamping, "Damping", "Scales their damping: a cloth laid over them."},
    {"Sympathetic", ids::sympatheticLevel, "Level", "Their share of the body's sound."},
    {"Sympathetic", ids::sympatheticJawari, "Jawari",
     "Each rests on a curved bridge of its own and buzzes on it, the brighter the louder it rings. Costs CPU: "
     "they are then solved with the played strings."},
};
static_assert(std::size(kControls) == kParameterCount);

// The panels, row by row as the editor lays them out.
const std::vector<std::vector<const char*>> kPanelRows = {
    {"String", "Output"}, {"Obstacle", "Thread"}, {"Damping", "Quality"}, {"Drone", "Body"}, {"Drone tuning", "MIDI", "Sympathetic"}};

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

}  // namespace jawari::plugin
