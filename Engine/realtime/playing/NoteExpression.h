#pragma once
// What MIDI says of the notes beyond their keys: the pitch bend, smoothed, and MPE's per-channel
// expression (bend, pressure, slide). RT throughout: plain values, no allocation.

#include "realtime/playing/ControlSmoothing.h"

#include <array>

namespace jawari
{

class NoteExpression
{
public:
    // Pressure presses a string's bridge up to this much further in (for more buzz).
    static constexpr double kPressureHeightMetres = 0.5e-3;

    void pitchBend(double amount);  // -1..1 of the bend range
    // The notes of one MIDI channel (1..16): their own bend (semitones), pressure (0..1) and slide
    // (0..1, 0.5 neutral: 0 doubles their damping, 1 halves it). Channel 0 stays neutral.
    void channelBend(int channel, double semitones);
    void channelPressure(int channel, double amount);
    void channelSlide(int channel, double amount);

    // The bend one chunk on, through a 5 ms one-pole of step k; returns whether it has just
    // settled on its target (a retune is due then).
    bool followBend(double k);
    // A MIDI string playing `pitch` on `channel` (0: none), with the bends that apply to it.
    double pitchOf(double pitch, int channel, double bendRangeSemitones) const;
    // Its bridge's height above `height` with the channel's pressure.
    double heightOf(double height, int channel) const;
    // Its damping's factor from the channel's slide: 4^(0.5 - slide), 1 without a channel.
    double dampingOf(int channel) const;

    // What moved since clearMoves(): a channel's slide (retune its strings), any pressure (re-apply
    // the contact).
    bool slideMoved(int channel) const { return slideMoved_[size_t(channel)]; }
    bool pressureMoved() const { return pressureMoved_; }
    void clearMoves();

private:
    struct Channel
    {
        double bend = 0.0, pressure = 0.0, slide = 0.5;
    };
    std::array<Channel, 17> channels_{};  // index 1..16; 0 stays neutral
    std::array<bool, 17> slideMoved_{};
    bool pressureMoved_ = false;
    double bend_ = 0.0, bendSmoothed_ = 0.0;
};

}  // namespace jawari
