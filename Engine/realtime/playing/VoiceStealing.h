#pragma once
// Which sounding string a new note takes when every MIDI string is busy. RT, no allocation.

#include <cstdint>

namespace jawari
{

struct StringActivity
{
    bool fading = false;     // already being stolen: fading out before its pending note
    bool held = false;       // its key is down
    bool sustained = false;  // its key is up, the sustain pedal holds it
    uint64_t age = 0;        // when its note started (larger is newer)
    double energy = 0.0;     // J; read only for strings neither held nor sustained
};

// The quietest released string (neither held nor sustained), else the oldest; -1 when every
// string is already fading out.
int chooseStolenString(const StringActivity* strings, int count);

}  // namespace jawari
