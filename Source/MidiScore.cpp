#include "MidiScore.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace jawari::midi
{
namespace
{
using std::to_string;

uint32_t bigEndian32(const uint8_t* p)
{
    return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | uint32_t(p[3]);
}

int bigEndian16(const uint8_t* p)
{
    return p[0] << 8 | p[1];
}

// A chunk's four-letter type as it can be printed.
std::string chunkType(const uint8_t* p)
{
    std::string name(4, '?');
    for (size_t i = 0; i < 4; ++i)
        if (p[i] >= 0x20 && p[i] < 0x7f)
            name[i] = char(p[i]);
    return name;
}

// Ticks per quarter note (> 0), or SMPTE: the high byte is minus the frames per second.
void checkDivision(int division)
{
    if ((division & 0x8000) == 0)
    {
        if (division == 0)
            throw MidiFileError("the division (ticks per quarter note) is 0");
        return;
    }
    const int framesPerSecond = 256 - (division >> 8), ticksPerFrame = division & 0xff;
    if (framesPerSecond != 24 && framesPerSecond != 25 && framesPerSecond != 29 && framesPerSecond != 30)
        throw MidiFileError("an SMPTE division of " + to_string(framesPerSecond)
                            + " frames per second (24, 25, 29 or 30 expected)");
    if (ticksPerFrame == 0)
        throw MidiFileError("an SMPTE division of 0 ticks per frame");
}

// The header chunk: its type and number of tracks.
std::pair<int, int> readHeader(const uint8_t* d, size_t size)
{
    if (size < 4 || std::memcmp(d, "MThd", 4) != 0)
        throw MidiFileError("not a Standard MIDI File (it does not start with 'MThd')");
    if (size < 14)
        throw MidiFileError("truncated: the header needs 14 bytes, the file has " + to_string(size));
    if (const auto length = bigEndian32(d + 4); length != 6)
        throw MidiFileError("the header chunk is " + to_string(length) + " bytes long (6 expected)");
    const int type = bigEndian16(d + 8), tracks = bigEndian16(d + 10);
    if (type == 2)
        throw MidiFileError("type 2 (independent sequences) is not supported, only type 0 and 1");
    if (type > 2)
        throw MidiFileError("unknown file type " + to_string(type) + " (0 or 1 expected)");
    if (tracks == 0)
        throw MidiFileError("the header declares no tracks");
    if (type == 0 && tracks != 1)
        throw MidiFileError("a type 0 file holds one track; this one declares " + to_string(tracks));
    checkDivision(bigEndian16(d + 12));
    return {type, tracks};
}

// Every track chunk the header declares, whole, and nothing after the last.
void checkChunks(const uint8_t* d, size_t size, int tracks)
{
    size_t at = 14;
    for (int t = 1; t <= tracks; ++t)
    {
        const std::string track = "track " + to_string(t) + " of " + to_string(tracks);
        if (size - at < 8)
            throw MidiFileError("truncated: " + track + (at == size ? " is missing" : " is cut short in its header"));
        if (std::memcmp(d + at, "MTrk", 4) != 0)
            throw MidiFileError(track + ": a chunk '" + chunkType(d + at) + "' where a track ('MTrk') belongs");
        const size_t length = bigEndian32(d + at + 4), remaining = size - at - 8;
        if (length > remaining)
            throw MidiFileError("truncated: " + track + " declares " + to_string(length) + " bytes, "
                                + to_string(remaining) + " remain");
        at += 8 + length;
    }
    if (at != size)
        throw MidiFileError(to_string(size - at) + " bytes follow the last of the " + to_string(tracks)
                            + " tracks the header declares");
}

// What JUCE read: a track stops at a malformed event, so each must end with its End of Track; an
// escape event (F7 and its length) is read by JUCE as one byte and its contents as further events,
// so none may appear; a tempo event holds three bytes; the tempo map is bounded (converting costs
// events x tempo events).
void checkTracks(const juce::MidiFile& file)
{
    int tempoEvents = 0;
    for (int t = 0; t < file.getNumTracks(); ++t)
    {
        const auto& track = *file.getTrack(t);
        const int n = track.getNumEvents();
        if (n == 0 || !track.getEventPointer(n - 1)->message.isEndOfTrackMetaEvent())
            throw MidiFileError(
                "track " + to_string(t + 1)
                + " does not end with an End of Track event (an event in it is malformed or cut short)");
        for (const auto* e : track)
        {
            if (e->message.getRawDataSize() > 0 && e->message.getRawData()[0] == 0xf7)
                throw MidiFileError("track " + to_string(t + 1)
                                    + ": an escape event (F7), which juce::MidiFile cannot read");
            const int type = e->message.getMetaEventType();
            if (type == 0x51 && e->message.getMetaEventLength() != 3)
                throw MidiFileError("track " + to_string(t + 1) + ": a tempo event of "
                                    + to_string(e->message.getMetaEventLength()) + " bytes (3 expected)");
            tempoEvents += type == 0x51 || type == 0x58 ? 1 : 0;
        }
    }
    if (tempoEvents > kMaxTempoEvents)
        throw MidiFileError(to_string(tempoEvents) + " tempo and time-signature events (at most "
                            + to_string(kMaxTempoEvents) + ")");
}

// Every track's channel messages (no meta, system exclusive or system messages), timed in seconds.
juce::MidiMessageSequence channelEvents(juce::MidiFile& file)
{
    file.convertTimestampTicksToSeconds();
    std::vector<juce::MidiMessage> kept;
    for (int t = 0; t < file.getNumTracks(); ++t)
        for (const auto* e : *file.getTrack(t))
            if (e->message.getRawDataSize() > 0 && e->message.getRawData()[0] < 0xf0)
                kept.push_back(e->message);
    std::stable_sort(kept.begin(), kept.end(), [](const juce::MidiMessage& a, const juce::MidiMessage& b) {
        return a.getTimeStamp() < b.getTimeStamp();
    });
    juce::MidiMessageSequence events;
    for (const auto& m : kept)
    {
        const double t = m.getTimeStamp();
        if (!(t >= 0.0 && t <= kMaxScoreSeconds))
        {
            char at[64];
            std::snprintf(at, sizeof at, "%.6g s", t);
            throw MidiFileError(std::string("an event at ") + at + " (a score may last at most "
                                + to_string(int(kMaxScoreSeconds)) + " s)");
        }
        events.addEvent(m);
    }
    return events;
}
void checkSize(uint64_t bytes)
{
    if (bytes > kMaxMidiFileBytes)
        throw MidiFileError(to_string(bytes) + " bytes: larger than the " + to_string(kMaxMidiFileBytes >> 20)
                            + " MiB a MIDI file may be");
}
}  // namespace

MidiScore readMidiScore(const void* data, size_t size)
{
    checkSize(size);
    const auto* bytes = static_cast<const uint8_t*>(data);
    MidiScore score;
    std::tie(score.fileType, score.tracks) = readHeader(bytes, size);
    checkChunks(bytes, size, score.tracks);

    juce::MemoryInputStream in(data, size, false);
    juce::MidiFile file;
    if (!file.readFrom(in, false))
        throw MidiFileError("JUCE's MIDI file reader refused it");
    checkTracks(file);
    score.events = channelEvents(file);
    score.lastEventSeconds = score.events.getEndTime();
    return score;
}

MidiScore loadMidiScore(const juce::File& file)
{
    if (!file.existsAsFile())
        throw MidiFileError(file.isDirectory() ? "a folder, not a file" : "no such file");
    checkSize(uint64_t(file.getSize()));
    juce::MemoryBlock data;
    if (!file.loadFileAsData(data))
        throw MidiFileError("cannot read it");
    return readMidiScore(data.getData(), data.getSize());
}

}  // namespace jawari::midi
