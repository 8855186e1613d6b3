#include "PluginEditor.h"

#include "EditorStyle.h"
#include "ParameterText.h"
#include "Presets.h"

#include <cmath>

namespace jawari::plugin
{
namespace
{
// The keyboard's and the Pluck button's velocity, wherever a key is clicked: the paper's 1.5 mm
// pluck (velocity 100).
constexpr float kKeyVelocity = 100.0f / 127.0f;
}  // namespace

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
