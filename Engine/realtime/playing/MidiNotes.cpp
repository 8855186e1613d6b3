#include "realtime/playing/MidiNotes.h"

#include "realtime/playing/VoiceStealing.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace jawari
{

// The newest tuning applies at once: pitches are not smoothed.
void MidiNotes::startKey(int slot, int note, double velocity, int channel)
{
    const double pitch = note >= 0 && note < kMidiNotes ? controls_.target().keyPitches[size_t(note)]
                                                        : std::numeric_limits<double>::quiet_NaN();
    if (std::isfinite(pitch))
        strings_.start(slot, note, pitch, velocity, channel);
}

void MidiNotes::noteOn(int note, double velocity, int channel)
{
    if (!(velocity > 0.0))
    {
        noteOff(note, channel);
        return;
    }
    velocity = std::min(velocity, 1.0);
    if (note < 0 || note >= kMidiNotes || !std::isfinite(controls_.target().keyPitches[size_t(note)]))
        return;  // a key the tuning leaves unmapped
    for (int i = 0; i < kMidiVoices; ++i)
    {
        auto& s = strings_[i];
        if (s.fade >= 0 && s.pendingNote == note && s.pendingChannel == channel)
        {
            s.pendingVelocity = velocity;
            return;
        }
        if (s.sounding && s.fade < 0 && s.note == note && s.channel == channel)
        {
            startKey(i, note, velocity, channel);
            return;
        }
    }
    const int limit = voiceLimit();
    for (int i = 0; i < limit; ++i)
        if (!strings_[i].sounding)
        {
            startKey(i, note, velocity, channel);
            return;
        }
    steal(note, velocity, channel);
}

int MidiNotes::voiceLimit() const
{
    return std::clamp(controls_.target().midiVoices, 1, kMidiVoices);
}

void MidiNotes::fitVoiceLimit()
{
    struct Moved
    {
        int note, channel;
        double velocity;
        bool held;
    };
    std::array<Moved, kMidiVoices> moved;
    int count = 0;
    for (int i = voiceLimit(); i < kMidiVoices; ++i)
    {
        auto& s = strings_[i];
        if (s.sounding && s.fade < 0)
            s.fade = strings_.fadeLength();
        s.held = s.sustained = false;
        if (s.pendingNote >= 0)
            moved[size_t(count++)] = {s.pendingNote, s.pendingChannel, s.pendingVelocity, s.pendingHeld};
        s.pendingNote = -1;
    }
    // A note that was to follow a steal above the limit plays within it instead, once every string
    // above it is fading (released at once if its key was let go meanwhile, as it would have been).
    for (int k = 0; k < count; ++k)
    {
        noteOn(moved[size_t(k)].note, moved[size_t(k)].velocity, moved[size_t(k)].channel);
        if (!moved[size_t(k)].held)
            noteOff(moved[size_t(k)].note, moved[size_t(k)].channel);
    }
}

void MidiNotes::steal(int note, double velocity, int channel)
{
    std::array<StringActivity, kMidiVoices> activity;
    const int limit = voiceLimit();
    for (int i = 0; i < limit; ++i)
    {
        const auto& s = strings_[i];
        activity[size_t(i)] = {s.fade >= 0, s.held, s.sustained, s.age, 0.0};
        if (s.fade < 0 && !s.held && !s.sustained)
            activity[size_t(i)].energy = strings_.voice(i).stringEnergy();
    }
    int victim = chooseStolenString(activity.data(), limit);
    if (victim < 0)
        victim = 0;  // every string is already fading: take over the first one's pending note
    auto& s = strings_[victim];
    if (s.fade < 0)
        s.fade = strings_.fadeLength();
    s.pendingNote = note;
    s.pendingChannel = channel;
    s.pendingVelocity = velocity;
    s.pendingHeld = true;
    s.pendingSustained = false;
}

void MidiNotes::noteOff(int note, int channel)
{
    for (int i = 0; i < kMidiVoices; ++i)
    {
        auto& s = strings_[i];
        if (s.fade >= 0 && s.pendingNote == note && s.pendingChannel == channel && s.pendingHeld)
        {
            s.pendingHeld = false;
            s.pendingSustained = sustain_;
        }
        if (s.note != note || s.channel != channel || !s.held)
            continue;
        s.held = false;
        if (sustain_)
            s.sustained = true;
        else if (s.fade < 0)
            strings_.release(i);
    }
}

void MidiNotes::sustain(bool down)
{
    sustain_ = down;
    if (down)
        return;
    for (int i = 0; i < kMidiVoices; ++i)
    {
        auto& s = strings_[i];
        s.pendingSustained = false;
        if (s.sustained)
        {
            s.sustained = false;
            if (s.fade < 0)
                strings_.release(i);
        }
    }
}

void MidiNotes::allNotesOff()
{
    sustain_ = false;
    for (int i = 0; i < kMidiVoices; ++i)
    {
        auto& s = strings_[i];
        s.held = s.sustained = false;
        s.pendingHeld = s.pendingSustained = false;
        if (s.fade < 0)
            strings_.release(i);
    }
}

void MidiNotes::startStolenNotes()
{
    for (int i = 0; i < kMidiVoices; ++i)
        if (strings_[i].fade == 0)
            startPendingNote(i);
}

// The stolen string is silent: the pending note starts from rest, released at once if its key
// was let go meanwhile.
void MidiNotes::startPendingNote(int slot)
{
    auto& s = strings_[slot];
    strings_.voice(slot).silence();
    s.sounding = false;
    if (s.pendingNote < 0)
    {
        s.fade = -1;  // above the voice limit: it stays silent
        return;
    }
    startKey(slot, s.pendingNote, s.pendingVelocity, s.pendingChannel);
    s.pendingNote = -1;
    if (!s.pendingHeld)
    {
        s.held = false;
        s.sustained = s.pendingSustained;
        if (!s.sustained)
            strings_.release(slot);
    }
}

}  // namespace jawari
