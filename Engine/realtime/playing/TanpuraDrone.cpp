#include "realtime/playing/TanpuraDrone.h"

#include "realtime/playing/Tuning.h"

#include <algorithm>
#include <cmath>

namespace jawari
{

double TanpuraDrone::nextRandom()
{
    // xorshift32: deterministic, so a drone renders the same every time.
    random_ ^= random_ << 13;
    random_ ^= random_ >> 17;
    random_ ^= random_ << 5;
    return double(random_) / 2147483648.0 - 1.0;
}

void TanpuraDrone::pluck(int string, const InstrumentControls& c, StringSlots& strings)
{
    // Sa from its frequency when one is set, else from its MIDI note; the strings below it by pure
    // intervals or equal-tempered ones, each with its own fine tuning.
    const double sa = saPitch(c);
    const auto first = static_cast<DroneFirstString>(std::clamp(c.droneFirst, 0, 3));
    const double pitch = dronePitch(string, sa, first, c.droneTuning) + c.droneFineCents[size_t(string)] / 100.0;
    const double h = std::clamp(c.humanise, 0.0, 1.0);
    const double velocity = std::clamp(c.droneStrength * (1.0 + 0.25 * h * nextRandom()), 0.05, 1.0);
    strings.start(kMidiVoices + string, static_cast<int>(std::lround(pitch)), pitch, velocity, 0);
    ++plucks_;
}

void TanpuraDrone::advance(int samples, const InstrumentControls& c, double hostRateHz, StringSlots& strings,
                           InstrumentActivity& activity)
{
    if (c.drone != on_)
    {
        on_ = c.drone;
        countdown_ = 0.0;
        next_ = 0;
        if (!on_)
            for (int slot = kMidiVoices; slot < kSlots; ++slot)
            {
                strings[slot].held = false;
                if (strings[slot].sounding)
                    strings.release(slot);
            }
    }
    if (!on_)
        return;
    while (countdown_ < 0.5)  // due within this chunk's first sample
    {
        pluck(next_, c, strings);
        ++activity.dronePlucks;
        // One beat between plucks, two after the low Sa: the cycle breathes before it starts again.
        const double beat = 60.0 / std::clamp(c.droneTempo, 10.0, 400.0) * hostRateHz;
        const double beats = next_ == kDroneStrings - 1 ? 2.0 : 1.0;
        const double h = std::clamp(c.humanise, 0.0, 1.0);
        countdown_ += beats * beat * (1.0 + 0.15 * h * nextRandom());
        next_ = (next_ + 1) % kDroneStrings;
    }
    countdown_ -= samples;
}

}  // namespace jawari
