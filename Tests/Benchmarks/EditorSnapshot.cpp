// jawari-editor-snapshot: the editor as the standalone app and the plugin show it, drawn offline
// while the tanpura drone plays (no window, no audio device needed), written as a PNG.
//   jawari-editor-snapshot OUT.png [seconds of drone before the picture, default 2.3] [polarisations, 1 or 2]

#include "PluginEditor.h"
#include "PluginProcessor.h"
#include "Presets.h"

#include <juce_events/juce_events.h>
#include <juce_gui_basics/juce_gui_basics.h>

#include <cstdio>
#include <string>

int main(int argc, char* argv[])
{
    if (argc < 2)
    {
        std::fprintf(stderr, "usage: jawari-editor-snapshot OUT.png [seconds] [polarisations]\n");
        return 2;
    }
    juce::ScopedJuceInitialiser_GUI juce;
    const double seconds = argc > 2 ? std::stod(argv[2]) : 2.3;
    jawari::plugin::JawariAudioProcessor p;
    p.setCurrentProgram(jawari::plugin::factoryPresetIndex("Tanpura drone"));
    if (argc > 3 && std::string(argv[3]) == "2")
        p.parameters().getParameter(jawari::plugin::ids::polarisations)->setValueNotifyingHost(1.0f);
    p.prepareToPlay(48000.0, 512);
    p.waitForBuilds();
    std::unique_ptr<juce::AudioProcessorEditor> editor(p.createEditorIfNeeded());
    auto* jawariEditor = dynamic_cast<jawari::plugin::JawariEditor*>(editor.get());
    juce::AudioBuffer<float> buffer(2, 512);
    juce::MidiBuffer midi;
    const int blocks = int(seconds * 48000.0 / 512.0);
    for (int b = 0; b < blocks; ++b)
    {
        buffer.clear();
        p.processBlock(buffer, midi);
        if (b % 3 == 0)
            jawariEditor->refreshFromProcessor();  // the editor's 30 Hz timer, in step with the audio
    }
    jawariEditor->refreshFromProcessor();
    const auto image = editor->createComponentSnapshot(editor->getLocalBounds(), true, 1.0f);
    const juce::File out = juce::File::getCurrentWorkingDirectory().getChildFile(argv[1]);
    out.deleteFile();
    juce::FileOutputStream stream(out);
    juce::PNGImageFormat png;
    if (!stream.openedOk() || !png.writeImageToStream(image, stream))
    {
        std::fprintf(stderr, "jawari-editor-snapshot: could not write %s\n", argv[1]);
        return 1;
    }
    p.editorBeingDeleted(editor.get());
    std::printf("jawari-editor-snapshot: wrote %s (%dx%d)\n", argv[1], image.getWidth(), image.getHeight());
    return 0;
}
