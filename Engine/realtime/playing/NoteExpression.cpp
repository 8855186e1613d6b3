#include "realtime/playing/NoteExpression.h"

#include <cmath>

namespace jawari
{
namespace
{
constexpr ControlRule kBend{.lowest = -1.0, .highest = 1.0, .fallback = 0.0, .glide = true, .tolerance = 1e-6};
constexpr ControlRule kChannelBend{.lowest = -96.0, .highest = 96.0, .fallback = 0.0};
constexpr ControlRule kPressure{.lowest = 0.0, .highest = 1.0, .fallback = 0.0};
constexpr ControlRule kSlide{.lowest = 0.0, .highest = 1.0, .fallback = 0.5};

bool isChannel(int channel)
{
    return channel >= 1 && channel <= 16;
}
}  // namespace

void NoteExpression::pitchBend(double amount)
{
    bend_ = kBend.playable(amount, 0.0);
}

void NoteExpression::channelBend(int channel, double semitones)
{
    if (isChannel(channel))
        channels_[size_t(channel)].bend = kChannelBend.playable(semitones, 0.0);
}

void NoteExpression::channelPressure(int channel, double amount)
{
    if (!isChannel(channel))
        return;
    channels_[size_t(channel)].pressure = kPressure.playable(amount, 0.0);
    pressureMoved_ = true;
}

void NoteExpression::channelSlide(int channel, double amount)
{
    if (!isChannel(channel))
        return;
    channels_[size_t(channel)].slide = kSlide.playable(amount, 0.0);
    slideMoved_[size_t(channel)] = true;
}

bool NoteExpression::followBend(double k)
{
    const double before = bendSmoothed_;
    bendSmoothed_ = kBend.step(bendSmoothed_, bend_, k);
    return bendSmoothed_ == bend_ && before != bend_;
}

double NoteExpression::pitchOf(double pitch, int channel, double bendRangeSemitones) const
{
    const double bent = pitch + bendSmoothed_ * bendRangeSemitones;
    return channel > 0 ? bent + channels_[size_t(channel)].bend : bent;
}

double NoteExpression::heightOf(double height, int channel) const
{
    return channel > 0 ? height + kPressureHeightMetres * channels_[size_t(channel)].pressure : height;
}

double NoteExpression::dampingOf(int channel) const
{
    return channel > 0 ? std::pow(4.0, 0.5 - channels_[size_t(channel)].slide) : 1.0;
}

void NoteExpression::clearMoves()
{
    slideMoved_.fill(false);
    pressureMoved_ = false;
}

}  // namespace jawari
