// libFuzzer on the renderer's MIDI reading (MidiScore: the structural checks, juce::MidiFile, the
// tempo map): whatever the bytes, a score or a MidiFileError, no crash, no other exception, no
// sanitizer report; a score holds channel messages in time order between 0 and the latest time
// allowed, the last at lastEventSeconds. Built by tools/fuzz.sh (clang, ASan, UBSan).
// JAWARI_MIDI_SEEDS=folder writes valid files there first (the fuzzer's seeds).

#include "MidiFileSupport.h"
#include "MidiScore.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>

namespace
{
using jawari::test::track;

// Type 0 with notes, controllers, bend and a system exclusive; type 1 with a conductor track of
// tempo and time-signature changes; SMPTE timing.
void writeSeeds(const juce::File& folder)
{
    folder.createDirectory();
    using M = juce::MidiMessage;
    const juce::uint8 sysex[] = {0x7e, 0x7f, 0x09, 0x01};
    const auto notes = track({{0, M::noteOn(1, 57, juce::uint8(100))},
                              {120, M::pitchWheel(1, 12000)},
                              {240, M::controllerEvent(1, 64, 127)},
                              {360, M::noteOff(1, 57)},
                              {480, M::noteOn(2, 64, juce::uint8(90))},
                              {600, M::createSysExMessage(sysex, int(sizeof sysex))},
                              {720, M::controllerEvent(1, 64, 0)},
                              {960, M::allNotesOff(1)}});
    const auto conductor = track({{0, M::tempoMetaEvent(500000)},
                                  {0, M::timeSignatureMetaEvent(3, 4)},
                                  {960, M::tempoMetaEvent(1000000)},
                                  {1440, M::tempoMetaEvent(250000)}});
    jawari::test::writeMidiFile(folder.getChildFile("type0.mid"), {notes}, 0, 480);
    jawari::test::writeMidiFile(folder.getChildFile("type1.mid"), {conductor, notes, notes}, 1, 96);
    jawari::test::writeMidiFile(folder.getChildFile("smpte.mid"), {notes}, 0, 0);
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    if (const char* folder = std::getenv("JAWARI_MIDI_SEEDS"))
        writeSeeds(juce::File::getCurrentWorkingDirectory().getChildFile(folder));
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    try
    {
        const auto score = jawari::midi::readMidiScore(data, size);
        double previous = 0.0;
        for (const auto* e : score.events)
        {
            const auto& m = e->message;
            const double t = m.getTimeStamp();
            const bool channel = m.getRawDataSize() > 0 && m.getRawData()[0] >= 0x80 && m.getRawData()[0] < 0xf0;
            if (!channel || !(t >= previous && t <= jawari::midi::kMaxScoreSeconds))
                std::abort();
            previous = t;
        }
        if (score.events.getNumEvents() == 0 || score.lastEventSeconds != previous)
            std::abort();
    }
    catch (const jawari::midi::MidiFileError&)
    {}
    return 0;
}
