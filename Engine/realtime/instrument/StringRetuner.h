#pragma once
// How a string is retuned: to a pitch ratio r of the string it was built as (tension scaled by r^2,
// bending stiffness with it: length, mass and B stay, so every mode's frequency scales by r), each
// mode damped as the damping controls say at its new frequency. Its scratch (the retuned string,
// the modes' damping) is its own, allocated OFF when the pack is built.

#include "physics/string/StringModel.h"
#include "realtime/instrument/InstrumentSettings.h"
#include "realtime/voice/Voice.h"

#include <vector>

namespace jawari
{

class StringRetuner
{
public:
    StringRetuner() = default;
    StringRetuner(const StringParameters& string, int modes);  // OFF

    // Retunes voice to ratio: mode p at f_p = r f_p(built) gets the damping
    // sigma_p = s * curve(f_p) * pi f_p / Q(f_p), Q Valette's at the controls' constants and s the
    // decay scale times `dampingFactor` (the note's slide); the motion carried as `motion` says
    // (Voice::retune). RT.
    void retune(Voice& voice, double ratio, const InstrumentControls& controls, double dampingFactor,
                ModalSolver::RetuneMotion motion = ModalSolver::RetuneMotion::keepState);

private:
    StringParameters string_;  // the built string; its tension and damping constants rewritten per retune
    double builtTension_ = 0.0;
    std::vector<double> sigma_;  // per mode
};

}  // namespace jawari
