#pragma once
// The sitar's sympathetic strings (taraf): strings beside the played ones that nobody plucks, each
// pressed on a small bridge of its own that stands on the body (docs/design.md section 1,
// "Sympathetic strings"). They ring only because the body moves under them: a played note at one's
// pitch drives it at its resonance through the bridge. Their bridge is taken to move with the main
// bridge (the two stand a few centimetres apart on the top, within a third of its bending wavelength
// below 1 kHz), so they are more strings on the pack's SharedBody. Each is held on its bridge by a
// stiff spring the string never leaves (a bilateral point: the string's downbearing keeps it
// pressed), so without their jawari the coupling is linear. With it (InstrumentStructure::
// sympatheticJawari), the bridge's curved top is a point just beyond the spring that the string
// grazes at rest and presses in the half of each cycle it dips there: their buzz, the louder they
// ring the brighter.
//
// A string nobody plucks carries little energy and few high partials: without their jawari the
// taraf keep the modes below about 6 kHz (kSympatheticModes) at the instrument's internal rate; with
// it, those below about 18 kHz (kSympatheticJawariModes), where the buzz puts its energy.

#include "realtime/playing/ControlSmoothing.h"
#include "realtime/instrument/VoicePack.h"

#include <array>

namespace jawari
{

inline constexpr int kSympatheticModes = 16;
inline constexpr int kSympatheticJawariModes = 48;
// The taraf's string: plain steel, 0.2 mm, 0.55 m from its bridge to its peg (a sitar's run from
// about 0.4 to 0.8 m), built at 370 Hz, the geometric middle of what the tunings ask (G#3 to F5 for
// Sa at C#3), and retuned from there (tension ~ ratio^2, B kept).
StringParameters sympatheticString();
// Its bridge: a point 3 % of its length from its end, a spring of kSympatheticBridgeStiffness the
// string never leaves (a bilateral point: its downbearing keeps it pressed).
Obstacle sympatheticBridge(double lengthMetres);
// Its jawari: a point kSympatheticJawariDistance beyond the spring, towards the speaking length, at
// the string's height at rest (it touches with no force there, so the tuning stands), with the
// played sitar's point law (sitar-point: 1e12 N/m^2.5 per metre of its 1 mm, exponent 1.5).
inline constexpr double kSympatheticJawariDistance = 1e-3;  // m
Obstacle sympatheticJawari(double lengthMetres);
// The string retuned (tension ~ ratio^2, B kept) so that on its bridge's spring its first mode sounds
// at `hz` (SpringLoadedModes.h, at kSympatheticModes): a scene's sympathetic string. OFF.
StringParameters sympatheticStringAt(double hz);
// A taraf string's voice: on sympatheticBridge (the spring 40 times as stiff as the string is there,
// so nearly rigid), its pickup the velocity (unheard: the taraf are heard through the body). OFF.
inline constexpr double kSympatheticBridgeStiffness = 1e5;  // N/m
// With `jawari`, on sympatheticJawari too, at kSympatheticJawariModes.
VoiceConfig sympatheticVoiceConfig(const VoiceQuality& quality, double hostRateHz, bool jawari = false);
// OFF: the structure's sympathetic strings into the pack (with a body; none without one).
void addSympatheticStrings(VoicePack& pack, const VoiceQuality& quality);

// The installed pack's sympathetic strings as played: tuned from the controls, retuned when Sa, the
// scale, the intonation, the reference pitch or the damping move. RT: no allocation.
class SympatheticStrings
{
public:
    explicit SympatheticStrings(const SmoothedControls& controls)
        : controls_(controls)
    {}

    // Every string tuned for the new pack; without `carry` each starts from rest.
    void install(VoicePack& pack, bool carry);
    // One chunk: retunes the strings whose pitch moved, or all of them when the damping changed.
    void follow(bool dampingChanged);
    int count() const { return pack_ == nullptr ? 0 : static_cast<int>(pack_->sympathetic.size()); }
    Voice& voice(int k) { return *pack_->sympathetic[size_t(k)]; }
    double pitch(int k) const { return pitch_[size_t(k)]; }  // what string k is tuned to (MIDI pitch)
    double energy(int k) const;                               // J, without the spring's
    bool atRest() const;  // every string below kRestJoules: none is stepped until the body moves them
    static constexpr double kRestJoules = 1e-18;

private:
    double wantedPitch(int k) const;
    void retune(int k, ModalSolver::RetuneMotion motion = ModalSolver::RetuneMotion::keepState);

    const SmoothedControls& controls_;
    VoicePack* pack_ = nullptr;
    std::array<double, kMaxSympatheticStrings> pitch_{};
    double damping_ = 1.0;
};

}  // namespace jawari
