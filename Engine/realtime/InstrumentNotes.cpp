// The instrument's MIDI strings: notes on and off, stealing, the sustain pedal, the bend and MPE's
// per-channel expression, and how a string starts (from rest, or plucked again while it sounds).

#include "realtime/Instrument.h"

#include "realtime/VoiceStealing.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jawari
{
namespace
{
constexpr double kPluckMetresPerVelocity = 1.5e-3 * 127.0 / 100.0;  // MIDI velocity 100: 1.5 mm
}  // namespace

double Instrument::noteRatio(double note) const
{
    const double f = current_.tuningA4Hz * std::pow(2.0, (note - 69.0) / 12.0);
    return f / pack_->baseFundamentalHz;
}

// A MIDI key: the pitch its tuning gives it (an unmapped key does not sound). The newest tuning
// applies at once: pitches are not smoothed.
void Instrument::startKey(int slot, int note, double velocity, int channel)
{
    const double pitch =
        note >= 0 && note < kMidiNotes ? target_.keyPitches[size_t(note)] : std::numeric_limits<double>::quiet_NaN();
    if (std::isfinite(pitch))
        start(slot, note, pitch, velocity, channel);
}

double Instrument::slotPitchNow(int slot) const
{
    const auto& s = slots_[size_t(slot)];
    if (slot >= kMidiVoices)
        return s.pitch;
    const double pitch = s.pitch + bendSmoothed_ * current_.bendRangeSemitones;
    return s.channel > 0 ? pitch + channels_[size_t(s.channel)].bend : pitch;
}

double Instrument::keyboardPan(double pitch) const
{
    return current_.stereoWidth * std::clamp((pitch - 72.0) / 24.0, -1.0, 1.0);
}

void Instrument::channelBend(int channel, double semitones)
{
    if (channel >= 1 && channel <= 16)
        channels_[size_t(channel)].bend = std::isfinite(semitones) ? std::clamp(semitones, -96.0, 96.0) : 0.0;
}

void Instrument::channelPressure(int channel, double amount)
{
    if (channel < 1 || channel > 16)
        return;
    channels_[size_t(channel)].pressure = std::isfinite(amount) ? std::clamp(amount, 0.0, 1.0) : 0.0;
    pressureMoved_ = true;
}

void Instrument::channelSlide(int channel, double amount)
{
    if (channel < 1 || channel > 16)
        return;
    channels_[size_t(channel)].slide = std::isfinite(amount) ? std::clamp(amount, 0.0, 1.0) : 0.5;
    slideMoved_[size_t(channel)] = true;
}

void Instrument::start(int slot, int note, double pitch, double velocity, int channel)
{
    auto& s = slots_[size_t(slot)];
    auto& voice = *pack_->voices[size_t(slot)];
    const bool fromRest = !s.sounding || s.note != note;
    const bool newChannel = s.channel != channel;
    s.note = note;
    s.pitch = pitch;
    s.channel = channel;
    s.ratio = noteRatio(slotPitchNow(slot));
    if (newChannel)
        voice.setContactLaw(contactLaw(), slotHeight(slot));
    if (fromRest)
    {
        voice.silence();
        s.peakEnergy = 0.0;
    }
    retune(slot);
    voice.cancelRelease();
    if (fromRest)
    {
        voice.pluckFromShape(kPluckMetresPerVelocity * velocity);
        ++activity_.notesStarted;
    }
    else
    {
        voice.pluckWithPulse(velocity);
        ++activity_.pulses;
    }
    s.held = true;
    s.sustained = false;
    s.sounding = true;
    s.fade = -1;
    s.age = ++clock_;
}

void Instrument::noteOn(int note, double velocity, int channel)
{
    if (pack_ == nullptr)
        return;
    if (!(velocity > 0.0))
    {
        noteOff(note, channel);
        return;
    }
    velocity = std::min(velocity, 1.0);
    if (note < 0 || note >= kMidiNotes || !std::isfinite(target_.keyPitches[size_t(note)]))
        return;  // a key the tuning leaves unmapped
    // The same note rings on its own string: pluck it again (a string can be re-plucked while sounding).
    for (int i = 0; i < kMidiVoices; ++i)
    {
        auto& s = slots_[size_t(i)];
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
    for (int i = 0; i < kMidiVoices; ++i)
        if (!slots_[size_t(i)].sounding)
        {
            startKey(i, note, velocity, channel);
            return;
        }
    // Steal: the quietest released string, else the oldest held one. It fades out over 5 ms first.
    std::array<StringActivity, kMidiVoices> strings;
    for (int i = 0; i < kMidiVoices; ++i)
    {
        const auto& s = slots_[size_t(i)];
        strings[size_t(i)] = {s.fade >= 0, s.held, s.sustained, s.age, 0.0};
        if (s.fade < 0 && !s.held && !s.sustained)
            strings[size_t(i)].energy = pack_->voices[size_t(i)]->stringEnergy();
    }
    int victim = chooseStolenString(strings.data(), kMidiVoices);
    if (victim < 0)
        victim = 0;  // every string is already fading: take over the first one's pending note
    auto& s = slots_[size_t(victim)];
    if (s.fade < 0)
        s.fade = fadeLength_;
    s.pendingNote = note;
    s.pendingChannel = channel;
    s.pendingVelocity = velocity;
    s.pendingHeld = true;
    s.pendingSustained = false;
}

void Instrument::noteOff(int note, int channel)
{
    if (pack_ == nullptr)
        return;
    for (int i = 0; i < kMidiVoices; ++i)
    {
        auto& s = slots_[size_t(i)];
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
            pack_->voices[size_t(i)]->release();
    }
}

void Instrument::sustain(bool down)
{
    sustain_ = down;
    if (down || pack_ == nullptr)
        return;
    for (int i = 0; i < kMidiVoices; ++i)
    {
        auto& s = slots_[size_t(i)];
        s.pendingSustained = false;
        if (s.sustained)
        {
            s.sustained = false;
            if (s.fade < 0)
                pack_->voices[size_t(i)]->release();
        }
    }
}

void Instrument::pitchBend(double amount)
{
    bend_ = std::isfinite(amount) ? std::clamp(amount, -1.0, 1.0) : 0.0;
}

void Instrument::allNotesOff()
{
    sustain_ = false;
    for (int i = 0; i < kMidiVoices; ++i)
    {
        auto& s = slots_[size_t(i)];
        s.held = s.sustained = false;
        s.pendingHeld = s.pendingSustained = false;
        if (pack_ != nullptr && s.fade < 0)
            pack_->voices[size_t(i)]->release();
    }
}

// The stolen string is silent: the pending note starts from rest, released at once if its key
// was let go meanwhile.
void Instrument::startPendingNote(int slot)
{
    auto& s = slots_[size_t(slot)];
    auto& voice = *pack_->voices[size_t(slot)];
    voice.silence();
    s.sounding = false;
    startKey(slot, s.pendingNote, s.pendingVelocity, s.pendingChannel);
    s.pendingNote = -1;
    if (!s.pendingHeld)
    {
        s.held = false;
        s.sustained = s.pendingSustained;
        if (!s.sustained)
            voice.release();
    }
}

}  // namespace jawari
