#pragma once
// Standard MIDI Files for jawari-render (docs/scenes.md): type 0 and 1, read with juce::MidiFile,
// every track's channel messages merged into one sequence timed in seconds through the file's tempo
// map. The file's structure is checked first, so a bad or truncated file is an error that names
// what is wrong rather than a shorter song. OFF.

#include <juce_audio_basics/juce_audio_basics.h>

#include <cstddef>
#include <stdexcept>

namespace jawari::midi
{

struct MidiFileError : std::runtime_error
{
    using std::runtime_error::runtime_error;
};

inline constexpr double kMaxScoreSeconds = 3600.0;    // the latest event a score may hold
inline constexpr size_t kMaxMidiFileBytes = 1 << 20;  // MIDI files are small; this bounds the work
inline constexpr int kMaxTempoEvents = 4096;          // tempo and time-signature events, all tracks

struct MidiScore
{
    int fileType = 0;  // 0 or 1
    int tracks = 0;
    // The channel messages (notes, controllers, pitch bend, ...) of every track, timestamps in
    // seconds, in time order; at equal times, a track's own order and earlier tracks first.
    juce::MidiMessageSequence events;
    double lastEventSeconds = 0.0;
};

// The score in a file's bytes. Throws MidiFileError naming the problem (not a MIDI file, truncated,
// type 2, a bad division, a track without its End of Track, an event too late). A file without
// channel events is a score without events: whether that is something to play (a drone) is the
// caller's to decide.
MidiScore readMidiScore(const void* data, size_t size);

// The same for a file; a missing, unreadable or oversized file is a MidiFileError too.
MidiScore loadMidiScore(const juce::File& file);

}  // namespace jawari::midi
