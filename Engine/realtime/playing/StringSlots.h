#pragma once
// The instrument's twelve strings as played, slot by slot (eight MIDI strings, then the drone's
// four): what each plays, the ratio its voice is tuned to, whether it sounds, a steal's fade. It
// starts, retunes and presses the installed pack's voices, for the notes and the drone alike. RT
// throughout: no allocation.

#include "realtime/playing/ControlSmoothing.h"
#include "realtime/instrument/InstrumentActivity.h"
#include "realtime/playing/NoteExpression.h"
#include "realtime/instrument/VoicePack.h"

#include <array>
#include <cstdint>

namespace jawari
{

struct StringSlot
{
    int note = -1;       // the key (or the drone string's nearest note)
    int channel = 0;     // its MPE channel, 0 for none
    double pitch = 0.0;  // what it plays, a fractional MIDI note (Tuning.h)
    bool held = false, sustained = false, sounding = false;
    uint64_t age = 0;
    double ratio = 1.0;  // the ratio the voice is tuned to
    double peakEnergy = 0.0;
    // A steal: the string fades out over the fade length, then the pending note starts from rest.
    int fade = -1;
    int pendingNote = -1;
    int pendingChannel = 0;
    double pendingVelocity = 0.0;
    bool pendingHeld = false, pendingSustained = false;
    double pan = 0.0;  // -1 .. 1
};

class StringSlots
{
public:
    StringSlots(const SmoothedControls& controls, const NoteExpression& expression, InstrumentActivity& activity);

    // A new pack's voices; with `carry` each string keeps sounding, else all fall silent. Every
    // string is retuned and pressed for it. `bridge` (m): where the bridge stood under strings
    // carried off a body onto rigid supports; their obstacles start there and glide to rest
    // (relaxCarriedBridge), so the strings pressing on it are not struck by its jump.
    void install(VoicePack& pack, bool carry, double bridge = 0.0);
    StringSlot& operator[](int slot) { return slots_[size_t(slot)]; }
    const StringSlot& operator[](int slot) const { return slots_[size_t(slot)]; }
    Voice& voice(int slot) { return *pack_->voices[size_t(slot)]; }
    int fadeLength() const { return fadeLength_; }  // a steal's fade-out, host samples

    // Starts `slot` playing `pitch` (a fractional MIDI note) as `note`: from rest when it sounded
    // nothing or another note, else plucked again while it sounds. Velocity 0..1.
    void start(int slot, int note, double pitch, double velocity, int channel);
    void release(int slot)
    {
        if (pack_ != nullptr)
            voice(slot).release();
    }

    // What a slot plays now (a MIDI string's pitch with its bends), its bridge's height, and the
    // ratio to the built string's fundamental that sounds `pitch` at the controls' A4.
    double pitchNow(int slot) const;
    double heightOf(int slot) const;
    double ratioFor(double pitch) const;

    // One chunk: retunes each sounding string whose damping changed, whose channel's slide moved,
    // or whose pitch moved when a retune is due (`bendSettled`, or every few chunks); re-applies
    // the contact after a pressure moved.
    void retuneSounding(bool dampingChanged, bool bendSettled);
    void applyContact();  // every voice's contact law and height, from the controls
    // RT, once a chunk of `count` host samples at `rate`: the carried bridge's offset relaxed
    // towards rest (time constant kBridgeReturnSeconds), the contact applied again while it moves.
    void relaxCarriedBridge(int count, double rate);
    int sounding() const;

private:
    // The string in `slot` to its ratio; a sounding one keeps its modes' actions (ModalSolver::retune).
    void retune(int slot, ModalSolver::RetuneMotion motion = ModalSolver::RetuneMotion::keepState);
    ContactLaw contactLaw() const;

    const SmoothedControls& controls_;
    const NoteExpression& expression_;
    InstrumentActivity& activity_;
    VoicePack* pack_ = nullptr;
    std::array<StringSlot, kSlots> slots_{};
    int fadeLength_ = 1;
    uint64_t clock_ = 0;       // the newest start's age
    uint64_t chunkClock_ = 0;  // chunks since construction, for the retunes' pace
    double carriedBridge_ = 0.0;  // the obstacles' offset from a body the strings left (m)
};

}  // namespace jawari
