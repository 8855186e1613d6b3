#pragma once
// The tanpura drone: its four strings (the last four slots) plucked in turn at the tempo, tuned
// from Sa, humanised by a deterministic random spread of timing and strength. RT: no allocation.

#include "realtime/instrument/InstrumentActivity.h"
#include "realtime/instrument/InstrumentSettings.h"
#include "realtime/playing/StringSlots.h"

#include <cstdint>

namespace jawari
{

class TanpuraDrone
{
public:
    // One chunk of `samples` host samples: starts the cycle when the controls turn the drone on
    // (releasing its strings when they turn it off), and plucks the strings due within the chunk.
    void advance(int samples, const InstrumentControls& controls, double hostRateHz, StringSlots& strings,
                 InstrumentActivity& activity);
    long plucks() const { return plucks_; }  // since construction

private:
    void pluck(int string, const InstrumentControls& controls, StringSlots& strings);
    double nextRandom();  // uniform -1..1

    bool on_ = false;
    double countdown_ = 0.0;  // host samples to the next pluck
    int next_ = 0;            // the string it plucks
    long plucks_ = 0;
    uint32_t random_ = 0x2545F491u;
};

}  // namespace jawari
