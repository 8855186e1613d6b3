#include "realtime/playing/StringSlots.h"

#include <algorithm>
#include <cmath>

namespace jawari
{
namespace
{
constexpr double kFadeSeconds = 0.005;  // a stolen string fades out over this
constexpr int kRetuneChunks = 4;        // a moving bend retunes every 4 chunks (128 samples)
constexpr double kPluckMetresPerVelocity = 1.5e-3 * 127.0 / 100.0;  // MIDI velocity 100: 1.5 mm
constexpr double kDronePans[kDroneStrings] = {-0.6, -0.2, 0.2, 0.6};
constexpr double kBridgeReturnSeconds = 0.005;  // a carried bridge's glide to rest
constexpr double kBridgeAtRestMetres = 1e-12;   // below this the glide ends
}  // namespace

StringSlots::StringSlots(const SmoothedControls& controls, const NoteExpression& expression,
                         InstrumentActivity& activity)
    : controls_(controls)
    , expression_(expression)
    , activity_(activity)
{
    for (int i = 0; i < kDroneStrings; ++i)
        slots_[size_t(kMidiVoices + i)].pan = kDronePans[i];
}

void StringSlots::install(VoicePack& pack, bool carry, double bridge)
{
    pack_ = &pack;
    carriedBridge_ = carry ? bridge : 0.0;
    fadeLength_ = std::max(1, static_cast<int>(std::lround(kFadeSeconds * pack.structure.hostRateHz)));
    for (int i = 0; i < kSlots; ++i)
    {
        auto& s = slots_[size_t(i)];
        if (!carry)
        {
            s.sounding = false;
            s.fade = -1;
            voice(i).silence();
        }
        retune(i);
    }
    applyContact();
}

void StringSlots::start(int slot, int note, double pitch, double velocity, int channel)
{
    auto& s = slots_[size_t(slot)];
    auto& v = voice(slot);
    const bool fromRest = !s.sounding || s.note != note;
    const bool newChannel = s.channel != channel;
    s.note = note;
    s.pitch = pitch;
    s.channel = channel;
    s.ratio = ratioFor(pitchNow(slot));
    if (newChannel)
        v.setContactLaw(contactLaw(), heightOf(slot));
    if (fromRest)
    {
        v.silence();
        s.peakEnergy = 0.0;
    }
    retune(slot);
    v.cancelRelease();
    // Through a body a pluck's energy follows the velocity at every pitch (its displacement over the
    // tuning ratio: the energy goes as the tension times its square); on rigid supports its displacement.
    const double scale = pack_->body ? 1.0 / std::max(s.ratio, 1e-3) : 1.0;
    if (fromRest && !v.pushes())
    {
        v.pluckFromShape(kPluckMetresPerVelocity * velocity * scale);
        ++activity_.notesStarted;
    }
    else
    {
        v.pluckWithPulse(velocity, scale);  // a soft pluck pushes from rest too
        if (fromRest)
            ++activity_.notesStarted;
        else
            ++activity_.pulses;
    }
    s.held = true;
    s.sustained = false;
    s.sounding = true;
    s.fade = -1;
    s.age = ++clock_;
}

double StringSlots::pitchNow(int slot) const
{
    const auto& s = slots_[size_t(slot)];
    return slot < kMidiVoices ? expression_.pitchOf(s.pitch, s.channel, controls_.current().bendRangeSemitones)
                              : s.pitch;
}

double StringSlots::heightOf(int slot) const
{
    return expression_.heightOf(controls_.current().obstacleHeight, slots_[size_t(slot)].channel) + carriedBridge_;
}

void StringSlots::relaxCarriedBridge(int count, double rate)
{
    if (carriedBridge_ == 0.0)
        return;
    carriedBridge_ *= std::exp(-count / (kBridgeReturnSeconds * rate));
    if (std::abs(carriedBridge_) < kBridgeAtRestMetres)
        carriedBridge_ = 0.0;
    applyContact();
}

double StringSlots::ratioFor(double pitch) const
{
    const double f = frequencyOfPitch(pitch, controls_.current().tuningA4Hz);
    return f / pack_->baseFundamentalHz;
}

void StringSlots::retune(int slot, ModalSolver::RetuneMotion motion)
{
    ++activity_.retunes;
    const auto& s = slots_[size_t(slot)];
    pack_->retuner.retune(voice(slot), s.ratio, controls_.current(), expression_.dampingOf(s.channel), motion);
}

void StringSlots::retuneSounding(bool dampingChanged, bool bendSettled)
{
    ++chunkClock_;
    const bool due = bendSettled || chunkClock_ % kRetuneChunks == 0;
    for (int i = 0; i < kSlots; ++i)
    {
        auto& s = slots_[size_t(i)];
        if (!s.sounding || s.fade >= 0)
            continue;
        const double wanted = ratioFor(pitchNow(i));
        const bool pitchMoved = std::abs(wanted / s.ratio - 1.0) > 1e-9;
        if (dampingChanged || expression_.slideMoved(s.channel) || (pitchMoved && due))
        {
            s.ratio = wanted;
            retune(i, ModalSolver::RetuneMotion::keepActions);
        }
    }
    if (expression_.pressureMoved())
        applyContact();
}

void StringSlots::applyContact()
{
    const ContactLaw law = contactLaw();
    for (int i = 0; i < kSlots; ++i)
        voice(i).setContactLaw(law, heightOf(i));
}

ContactLaw StringSlots::contactLaw() const
{
    const auto& c = controls_.current();
    return {std::max(c.stiffness, 0.0), std::max(c.exponent, 1.0)};
}

int StringSlots::sounding() const
{
    int n = 0;
    for (const auto& s : slots_)
        n += s.sounding ? 1 : 0;
    return n;
}

}  // namespace jawari
