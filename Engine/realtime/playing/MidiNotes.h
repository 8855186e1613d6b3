#pragma once
// The eight MIDI strings (the first slots): keys on and off, the sustain pedal, and voice
// stealing: with every string busy a new note takes the quietest released string, else the oldest
// held one, which fades out first (StringSlot::fade) and then starts the pending note from rest.
// Only the first InstrumentControls::midiVoices strings take notes; those above the limit fade out
// as a stolen string does, with no note to follow. RT throughout: no allocation.

#include "realtime/instrument/InstrumentSettings.h"
#include "realtime/playing/StringSlots.h"

namespace jawari
{

class MidiNotes
{
public:
    MidiNotes(StringSlots& strings, const SmoothedControls& controls)
        : strings_(strings)
        , controls_(controls)
    {}

    // Velocity 0..1 (0 is a note off). `channel`: the note's MPE channel (1..16), whose expression
    // it follows, or 0. The key plays the pitch the controls' keyPitches give it; an unmapped key
    // does not sound. The same note on the same channel plucks its string again.
    void noteOn(int note, double velocity, int channel);
    void noteOff(int note, int channel);
    void sustain(bool down);
    void allNotesOff();  // every MIDI string released, the pedal up
    // After a chunk's mix: each stolen string that has faded out starts its pending note.
    void startStolenNotes();
    // Before a chunk: the strings above the voice limit set to fade out, released; a note waiting to
    // follow a steal in one of them is played within the limit instead.
    void fitVoiceLimit();

private:
    void startKey(int slot, int note, double velocity, int channel);
    void steal(int note, double velocity, int channel);
    void startPendingNote(int slot);
    int voiceLimit() const;

    StringSlots& strings_;
    const SmoothedControls& controls_;
    bool sustain_ = false;
};

}  // namespace jawari
