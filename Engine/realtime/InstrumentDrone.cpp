// The tanpura drone: its four strings plucked in turn at the tempo, tuned from Sa, humanised.

#include "realtime/Instrument.h"

#include <algorithm>
#include <cmath>

namespace jawari
{

double Instrument::nextRandom()
{
    // xorshift32: deterministic, so a drone renders the same every time.
    random_ ^= random_ << 13;
    random_ ^= random_ >> 17;
    random_ ^= random_ << 5;
    return double(random_) / 2147483648.0 - 1.0;
}

void Instrument::dronePluck(int string)
{
    // Sa from its frequency when one is set, else from its MIDI note; the strings below it by pure
    // intervals or equal-tempered ones, each with its own fine tuning.
    const double sa = current_.droneSaHz > 0.0 ? pitchOfFrequency(current_.droneSaHz, current_.tuningA4Hz)
                                               : double(std::clamp(current_.droneTonic, 12, 108));
    const auto first = static_cast<DroneFirstString>(std::clamp(current_.droneFirst, 0, 3));
    const double pitch =
        dronePitch(string, sa, first, current_.droneTuning) + current_.droneFineCents[size_t(string)] / 100.0;
    const int slot = kMidiVoices + string;
    const double h = std::clamp(current_.humanise, 0.0, 1.0);
    const double velocity = std::clamp(current_.droneStrength * (1.0 + 0.25 * h * nextRandom()), 0.05, 1.0);
    start(slot, static_cast<int>(std::lround(pitch)), pitch, velocity);
    ++dronePlucks_;
    ++activity_.dronePlucks;
}

void Instrument::scheduleDrone(int samples)
{
    const bool on = current_.drone;
    if (on != droneOn_)
    {
        droneOn_ = on;
        droneCountdown_ = 0.0;
        droneNext_ = 0;
        if (!on)
            for (int i = 0; i < kDroneStrings; ++i)
            {
                auto& s = slots_[size_t(kMidiVoices + i)];
                s.held = false;
                if (s.sounding)
                    pack_->voices[size_t(kMidiVoices + i)]->release();
            }
    }
    if (!on)
        return;
    while (droneCountdown_ < 0.5)  // due within this chunk's first sample
    {
        dronePluck(droneNext_);
        // One beat between plucks, two after the low Sa: the cycle breathes before it starts again.
        const double beat = 60.0 / std::clamp(current_.droneTempo, 10.0, 400.0) * pack_->structure.hostRateHz;
        const double beats = droneNext_ == kDroneStrings - 1 ? 2.0 : 1.0;
        const double h = std::clamp(current_.humanise, 0.0, 1.0);
        droneCountdown_ += beats * beat * (1.0 + 0.15 * h * nextRandom());
        droneNext_ = (droneNext_ + 1) % kDroneStrings;
    }
    droneCountdown_ -= samples;
}

}  // namespace jawari
