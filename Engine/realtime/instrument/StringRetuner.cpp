#include "realtime/instrument/StringRetuner.h"

#include <algorithm>
#include <numbers>

namespace jawari
{

StringRetuner::StringRetuner(const StringParameters& string, int modes)
    : string_(string)
    , builtTension_(string.tensionNewtons)
    , sigma_(size_t(modes), 0.0)
{}

void StringRetuner::retune(Voice& voice, double ratio, const InstrumentControls& controls, double dampingFactor,
                           ModalSolver::RetuneMotion motion)
{
    string_.tensionNewtons = builtTension_ * ratio * ratio;  // B stays: EI scales with T
    string_.damping.etaAir = DampingParameters{}.etaAir * std::max(controls.airScale, 0.0);
    string_.damping.deltaVe = std::max(controls.deltaVe, 0.0);
    string_.damping.qTeInv = std::max(controls.qTeInv, 0.0);
    const auto& f = voice.baseFrequencies();
    const double scale = std::max(controls.decayScale, 0.0) * dampingFactor;
    for (size_t p = 0; p < sigma_.size(); ++p)
    {
        const double fp = ratio * f[p];
        sigma_[p] =
            scale * dampingCurveAt(controls.dampingCurve, fp) * std::numbers::pi * fp * valetteInverseQ(string_, fp);
    }
    voice.retune(ratio, sigma_.data(), motion);
}

}  // namespace jawari
