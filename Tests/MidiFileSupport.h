#pragma once
// MIDI files written with juce::MidiFile, for the renderer's tests and the MIDI fuzzer's seeds.

#include <juce_audio_basics/juce_audio_basics.h>

#include <initializer_list>
#include <utility>
#include <vector>

namespace jawari::test
{

// A track of timed messages (timestamps in ticks).
inline juce::MidiMessageSequence track(std::initializer_list<std::pair<double, juce::MidiMessage>> events)
{
    juce::MidiMessageSequence sequence;
    for (auto [tick, message] : events)
    {
        message.setTimeStamp(tick);
        sequence.addEvent(message);
    }
    return sequence;
}

// The tracks as a file of `type` (0 or 1), replacing any file there: ticksPerQuarter ticks per
// quarter note, or SMPTE timing (25 frames per second, 40 ticks a frame) when it is 0.
inline bool writeMidiFile(const juce::File& file, const std::vector<juce::MidiMessageSequence>& tracks, int type,
                          int ticksPerQuarter)
{
    juce::MidiFile midi;
    if (ticksPerQuarter > 0)
        midi.setTicksPerQuarterNote(ticksPerQuarter);
    else
        midi.setSmpteTimeFormat(25, 40);
    for (const auto& t : tracks)
        midi.addTrack(t);
    file.deleteFile();
    juce::FileOutputStream out(file);
    return out.openedOk() && midi.writeTo(out, type);
}

}  // namespace jawari::test
