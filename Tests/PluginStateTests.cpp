// The plugin's state: every parameter round-tripped, the presets' program numbers and bodies, older
// states restored, bad data refused with its reason, a Scala scale carried.

#include "PluginTestSupport.h"
#include "AllocationCounter.h"
#include "StoredReference.h"
#include "PluginEditor.h"
#include "PluginProcessor.h"
#include "Presets.h"
#include "offline/Analysis.h"
#include "offline/OfflineRender.h"
#include "offline/Scene.h"
#include "physics/body/FactoryBodies.h"
#include "realtime/voice/Voice.h"

#include <catch2/catch.hpp>

#include <juce_audio_processors/juce_audio_processors.h>
#include <juce_events/juce_events.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

using namespace jawari;
using namespace jawari::plugin;
using namespace jawari::plugin_tests;

TEST_CASE("The state round-trips every parameter and the damping curve", "[plugin]")
{
    JawariAudioProcessor a;
    std::mt19937 rng(7);
    for (auto* param : a.getParameters())
        param->setValueNotifyingHost(std::uniform_real_distribution<float>(0.0f, 1.0f)(rng));
    for (int i = 0; i < kDampingCurvePoints; ++i)
        a.setDampingCurvePoint(i, 0.25f + 0.5f * float(i));
    juce::MemoryBlock blob;
    a.getStateInformation(blob);
    JawariAudioProcessor b;
    b.setStateInformation(blob.getData(), int(blob.getSize()));
    int checked = 0;
    for (int i = 0; i < a.getParameters().size(); ++i)
    {
        auto* pa = dynamic_cast<juce::RangedAudioParameter*>(a.getParameters()[i]);
        auto* pb = dynamic_cast<juce::RangedAudioParameter*>(b.getParameters()[i]);
        INFO(pa->getParameterID());
        CHECK(pa->convertFrom0to1(pa->getValue()) == Approx(pb->convertFrom0to1(pb->getValue())).margin(1e-5));
        ++checked;
    }
    CHECK(checked == int(kParameterCount));
    for (int i = 0; i < kDampingCurvePoints; ++i)
        CHECK(b.dampingCurvePoint(i) == Approx(std::clamp(0.25f + 0.5f * float(i), 0.125f, 8.0f)));
}

TEST_CASE("The factory presets keep their program numbers: a new one comes last", "[plugin]")
{
    // A host recalls a program by its number; a preset inserted before another would change the sound
    // of every session saved on the later one.
    const char* names[] = {"Default (tanpura bridge, no drone)", "Paper centre obstacle", "Tanpura drone",
                           "Sitar (parabolic bridge)", "Bass fret buzz", "Tanpura thread (jiva, two polarisations)",
                           "Sitar Sa-Pa (sympathetic strings for a drone)"};
    JawariAudioProcessor p;
    REQUIRE(p.getNumPrograms() == int(std::size(names)));
    for (int i = 0; i < p.getNumPrograms(); ++i)
        CHECK(p.getProgramName(i) == juce::String(names[i]));
}

TEST_CASE("The factory presets play through their instrument's body: tanpuras the tanpura's, sitars the sitar's",
          "[plugin]")
{
    // The Body choice: 0 none, 1 tanpura, 2 sitar (kBodyNames).
    JawariAudioProcessor p;
    int tanpuras = 0, sitars = 0;
    for (int i = 0; i < p.getNumPrograms(); ++i)
    {
        p.setCurrentProgram(i);
        const auto name = p.getProgramName(i);
        INFO(name << ": body " << parameterValue(p, ids::body));
        if (name.startsWith("Tanpura"))
        {
            CHECK(parameterValue(p, ids::body) == 1.0f);
            ++tanpuras;
        }
        if (name.startsWith("Sitar"))
        {
            CHECK(parameterValue(p, ids::body) == 2.0f);
            ++sitars;
        }
    }
    CHECK(tanpuras == 2);
    CHECK(sitars == 2);
}

TEST_CASE("A state or preset saved with the old id droneLevel restores the drone strength", "[plugin]")
{
    // The state of an older version: drone strength saved as "droneLevel".
    auto stateWithDroneLevel = [](double value) {
        juce::ValueTree tree("JawariState");
        tree.setProperty("version", 2, nullptr);
        juce::ValueTree params("Parameters");
        juce::ValueTree param("Param");
        param.setProperty("id", "droneLevel", nullptr);
        param.setProperty("value", value, nullptr);
        params.appendChild(param, nullptr);
        tree.appendChild(params, nullptr);
        return tree;
    };
    JawariAudioProcessor p;
    REQUIRE(parameterValue(p, ids::droneStrength) == Approx(0.7f));
    juce::MemoryBlock blob;
    juce::AudioProcessor::copyXmlToBinary(*stateWithDroneLevel(0.35).createXml(), blob);
    p.setStateInformation(blob.getData(), int(blob.getSize()));
    CHECK(parameterValue(p, ids::droneStrength) == Approx(0.35f));

    // A user preset file of that version.
    juce::TemporaryFile preset(".jawaripreset");
    REQUIRE(stateWithDroneLevel(0.9).createXml()->writeTo(preset.getFile()));
    REQUIRE(p.loadUserPreset(preset.getFile()).wasOk());
    CHECK(parameterValue(p, ids::droneStrength) == Approx(0.9f));

    // Both ids in one state: the current one wins.
    auto both = stateWithDroneLevel(0.2);
    juce::ValueTree current("Param");
    current.setProperty("id", ids::droneStrength, nullptr);
    current.setProperty("value", 0.6, nullptr);
    both.getChildWithName("Parameters").appendChild(current, nullptr);
    p.setState(both);
    CHECK(parameterValue(p, ids::droneStrength) == Approx(0.6f));
}

TEST_CASE("A thread saved before the thread had a model plays rigid as it did; a new one is DAFx-16's damped thread",
          "[plugin]")
{
    auto stateWithThread = [](int version) {
        juce::ValueTree tree("JawariState");
        tree.setProperty("version", version, nullptr);
        juce::ValueTree params("Parameters");
        juce::ValueTree param("Param");
        param.setProperty("id", ids::thread, nullptr);
        param.setProperty("value", 1.0, nullptr);
        params.appendChild(param, nullptr);
        tree.appendChild(params, nullptr);
        return tree;
    };
    JawariAudioProcessor p;
    CHECK(parameterValue(p, ids::threadModel) == 0.0f);  // damped
    p.setState(stateWithThread(2));
    CHECK(parameterValue(p, ids::thread) == 1.0f);
    CHECK(parameterValue(p, ids::threadModel) == 1.0f);  // rigid, as version 2 played it
    p.setState(stateWithThread(3));
    CHECK(parameterValue(p, ids::threadModel) == 0.0f);
    const auto structure = ParameterReader(p.parameters()).structure(48000.0);
    CHECK(structure.threadModel == ThreadModel::springDamper);
    CHECK(structure.threadStiffness == Approx(1.2e5));
    CHECK(structure.threadDamping == Approx(1.2));
}


TEST_CASE("setStateInformation survives empty, truncated, random and older-version data", "[plugin]")
{
    JawariAudioProcessor p;
    setParameter(p, ids::gain, -6.0f);
    juce::MemoryBlock good;
    p.getStateInformation(good);
    std::mt19937 rng(3);
    // Empty, null and truncated: nothing changes.
    p.setStateInformation(nullptr, 0);
    p.setStateInformation(good.getData(), 0);
    for (size_t cut = 1; cut < good.getSize(); cut += 7)
        p.setStateInformation(good.getData(), int(cut));
    CHECK(parameterValue(p, ids::gain) == Approx(-6.0f));
    // Thousands of random blobs, some behind a valid JUCE XML header so the parser sees them.
    std::vector<char> blob;
    for (int i = 0; i < 3000; ++i)
    {
        blob.resize(size_t(1 + rng() % 600));
        for (auto& c : blob)
            c = char(rng());
        if (i % 2 == 0 && blob.size() > 8)
        {
            const juce::uint32 magic = 0x21324356, size = juce::uint32(blob.size() - 8);
            std::memcpy(blob.data(), &magic, 4);
            std::memcpy(blob.data() + 4, &size, 4);
        }
        p.setStateInformation(blob.data(), int(blob.size()));
    }
    // What libFuzzer found under ASan: a header, then UTF-8 lead bytes with no continuation (JUCE's
    // parser read past the end of it). Kept as a regression file; and the same shape built here.
    {
        juce::MemoryBlock crash;
        REQUIRE(juce::File(JAWARI_TESTS_DIR "/Fuzz/regressions/state-invalid-utf8.bin").loadFileAsData(crash));
        p.setStateInformation(crash.getData(), int(crash.getSize()));
        // And a value with an exponent too long for JUCE's number reader (signed overflow in it).
        juce::MemoryBlock longExponent;
        REQUIRE(juce::File(JAWARI_TESTS_DIR "/Fuzz/regressions/state-long-exponent.bin").loadFileAsData(longExponent));
        juce::MemoryBlock keep;
        p.getStateInformation(keep);
        p.setStateInformation(longExponent.getData(), int(longExponent.getSize()));
        p.setStateInformation(keep.getData(), int(keep.getSize()));
        // And a processing instruction followed by text inside an element (JUCE's XML reader
        // looped for ever on it).
        juce::MemoryBlock instruction;
        REQUIRE(juce::File(JAWARI_TESTS_DIR "/Fuzz/regressions/state-processing-instruction.bin")
                    .loadFileAsData(instruction));
        p.setStateInformation(instruction.getData(), int(instruction.getSize()));
        std::vector<char> cut = {'V', 'C', '2', '!', 6, 0, 0, 0, '<', 'a', '>', char(0xeb), char(0xeb), char(0xeb)};
        p.setStateInformation(cut.data(), int(cut.size()));
        CHECK(parameterValue(p, ids::gain) == Approx(-6.0f));
    }
    // Mangled values inside a real state: NaN, infinities, text, out of range, unknown ids.
    for (const char* bad : {"nan", "inf", "-inf", "1e400", "banana", "", "-1e30", "1e30"})
    {
        juce::ValueTree tree = p.state();
        auto params = tree.getChildWithName("Parameters");
        for (int i = 0; i < params.getNumChildren(); ++i)
            params.getChild(i).setProperty("value", bad, nullptr);
        tree.getChildWithName("DampingCurve").setProperty("p3", bad, nullptr);
        juce::MemoryBlock mangled;
        juce::AudioProcessor::copyXmlToBinary(*tree.createXml(), mangled);
        p.setStateInformation(mangled.getData(), int(mangled.getSize()));
        for (auto* param : p.getParameters())
        {
            auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(param);
            INFO(ranged->getParameterID() << " after value " << bad);
            CHECK(ranged->getValue() == Approx(ranged->getDefaultValue()));
        }
        CHECK(p.dampingCurvePoint(3) == 1.0f);
    }
    // An older state (version 1: no damping curve) with one parameter set: read, the rest default.
    juce::ValueTree old("JawariState");
    old.setProperty("version", 1, nullptr);
    juce::ValueTree params("Parameters");
    juce::ValueTree gain("Param");
    gain.setProperty("id", ids::gain, nullptr);
    gain.setProperty("value", -12.0, nullptr);
    params.appendChild(gain, nullptr);
    old.appendChild(params, nullptr);
    juce::MemoryBlock oldBlob;
    juce::AudioProcessor::copyXmlToBinary(*old.createXml(), oldBlob);
    p.setDampingCurvePoint(0, 4.0f);
    p.setStateInformation(oldBlob.getData(), int(oldBlob.getSize()));
    CHECK(parameterValue(p, ids::gain) == Approx(-12.0f));
    CHECK(parameterValue(p, ids::obstacleStiffness) == Approx(13.0f));
    CHECK(p.dampingCurvePoint(0) == 1.0f);
    // And it still plays.
    prepare(p, 48000.0, 256);
    const auto y = renderNote(p, 48000.0, 256, 0.3);
    CHECK(peakOf(y) > 1e-3);
    CHECK(peakOf(y) <= 1.0);
}

TEST_CASE("A state file that is not UTF-8, not XML or not a Jawari state is refused with its reason", "[plugin]")
{
    JawariAudioProcessor p;
    setParameter(p, ids::gain, -6.0f);
    const auto xml = p.state().toXmlString();
    setParameter(p, ids::gain, -3.0f);
    struct Case
    {
        std::string bytes, expected;
    };
    const std::vector<Case> cases = {
        {"<JawariState a=\"\xe9\"/>", "not valid UTF-8"},
        {"<JawariState><Parameters>", "not XML"},
        {" \n", "not XML"},
        {"<Other/>", "its root element is <Other>, not <JawariState>"},
        {"<JawariState><?p?>x</JawariState>", "a processing instruction"},
    };
    juce::TemporaryFile file(".jawaripreset");
    for (const auto& c : cases)
    {
        REQUIRE(file.getFile().replaceWithData(c.bytes.data(), c.bytes.size()));
        const auto result = p.loadUserPreset(file.getFile());
        INFO(c.bytes << ": " << result.getErrorMessage());
        CHECK(result.failed());
        CHECK(result.getErrorMessage().contains(c.expected));
        CHECK(parameterValue(p, ids::gain) == Approx(-3.0f));
    }
    CHECK(p.loadUserPreset(file.getFile().getSiblingFile("missing.jawaripreset"))
              .getErrorMessage()
              .contains("no such file"));
    // A good state behind a byte order mark, as a text editor may save it.
    const std::string marked = "\xEF\xBB\xBF" + xml.toStdString();
    REQUIRE(file.getFile().replaceWithData(marked.data(), marked.size()));
    CHECK(p.loadUserPreset(file.getFile()).wasOk());
    CHECK(parameterValue(p, ids::gain) == Approx(-6.0f));
}


TEST_CASE("A Scala scale tunes the keyboard, travels in the state, and a bad one is refused", "[plugin]")
{
    const juce::String justScale =
        "5-limit just\n12\n16/15\n9/8\n6/5\n5/4\n4/3\n45/32\n3/2\n8/5\n5/3\n9/5\n15/8\n2/1\n";
    const juce::String a440 = "12\n0\n127\n60\n69\n440.0\n12\n0\n1\n2\n3\n4\n5\n6\n7\n8\n9\n10\n11\n";
    JawariAudioProcessor p;
    prepare(p, 48000.0, 512);
    setParameter(p, ids::obstacleHeight, -5.0f);  // the bridge out of reach: a free string, a clean pitch
    REQUIRE(p.waitForBuilds());
    CHECK(p.setKeyboardTuning(justScale, a440).isEmpty());
    CHECK(p.keyboardTuningName() == "5-limit just");
    // G4 (67) is C 3/2 = 396 Hz in this tuning (392.0 Hz in equal temperament).
    const auto y = renderNote(p, 48000.0, 512, 1.5, 67);
    const double f = peakFrequency(y, 48000.0, 380.0, 410.0, 4800, y.size() - 4800);
    INFO("G4 plays " << f << " Hz");
    CHECK(std::abs(f / 396.0 - 1.0) < 0.002);

    // The state carries the scale: a second processor restores it.
    juce::MemoryBlock saved;
    p.getStateInformation(saved);
    JawariAudioProcessor q;
    q.setStateInformation(saved.getData(), int(saved.getSize()));
    CHECK(q.keyboardTuningName() == "5-limit just");

    // A bad scale is refused with its problem named, and the tuning stays.
    const auto error = p.setKeyboardTuning("broken\n3\n100.0\n", {});
    INFO("error: " << error);
    CHECK(error.contains("announces 3 pitches but gives 1"));
    CHECK(p.keyboardTuningName() == "5-limit just");
    // The editor shows the tuning on its scale button (which loads .scl files).
    {
        std::unique_ptr<juce::AudioProcessorEditor> editor(p.createEditorIfNeeded());
        REQUIRE(editor != nullptr);
        bool shown = false;
        for (auto* child : editor->getChildren())
            if (auto* button = dynamic_cast<juce::TextButton*>(child))
                shown = shown || button->getButtonText() == "Scale: 5-limit just";
        CHECK(shown);
        p.editorBeingDeleted(editor.get());
    }
    // Back to equal temperament.
    CHECK(p.setKeyboardTuning({}, {}).isEmpty());
    CHECK(p.keyboardTuningName() == "equal temperament");
}
