#include "realtime/SympatheticStrings.h"

#include "physics/SpringLoadedModes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace jawari
{

StringParameters sympatheticString()
{
    StringParameters s;
    s.lengthMetres = 0.55;
    s.diameterMetres = 0.2e-3;
    s.linearDensity = 7850.0 * std::numbers::pi * 0.25 * s.diameterMetres * s.diameterMetres;  // steel
    const double c = 2.0 * s.lengthMetres * 370.0;
    s.tensionNewtons = s.linearDensity * c * c;
    // B = pi^3 E d^4 / (64 T L^2), E = 200 GPa.
    s.inharmonicity = std::pow(std::numbers::pi, 3) * 200e9 * std::pow(s.diameterMetres, 4)
                      / (64.0 * s.tensionNewtons * s.lengthMetres * s.lengthMetres);
    return s;
}

VoiceConfig sympatheticVoiceConfig(const VoiceQuality& quality, double hostRateHz)
{
    VoiceConfig config;
    config.string = sympatheticString();
    const double L = config.string.lengthMetres;
    Obstacle bridge;
    bridge.type = ObstacleType::point;
    bridge.position = 0.03 * L;
    bridge.width = 1e-3;  // the point's weight: the law's stiffness is per metre of it
    bridge.law.bilateral = true;
    bridge.law.exponent = 1.0;
    bridge.law.stiffness = kSympatheticBridgeStiffness / bridge.width;
    config.obstacles = {bridge};
    config.excitationPosition = 0.5 * L;
    config.pickupPosition = 0.9 * L;
    config.quantity = PickupQuantity::velocity;
    config.modes = kSympatheticModes;
    config.oversampling = quality.oversampling;
    config.hostRateHz = hostRateHz;
    config.method = ContactMethod::energyConserving;
    config.keepEveryMode = true;
    config.ownDecimator = false;
    config.movingBridge = true;
    return config;
}

void addSympatheticStrings(VoicePack& pack, const VoiceQuality& quality)
{
    const int count = std::clamp(pack.structure.sympatheticStrings, 0, kMaxSympatheticStrings);
    if (!pack.body || count == 0)
        return;
    const VoiceConfig config = sympatheticVoiceConfig(quality, pack.structure.hostRateHz);
    const ModalSolverConfig solverConfig = voiceSolverConfig(config);
    for (int k = 0; k < count; ++k)
    {
        pack.sympathetic.push_back(std::make_unique<Voice>(config, solverConfig));
        pack.body->checkLinear(pack.sympathetic.back()->solver());
    }
    pack.sympatheticString = config.string;
    pack.sympatheticRetuner = StringRetuner(config.string, solverConfig.modes.size());
    // The pitch it sounds on its bridge's spring (SpringLoadedModes.h), which the tunings aim at.
    pack.sympatheticFundamentalHz = springLoadedFrequencyHz(solverConfig, 0);
    pack.sympatheticBlock.assign(size_t(kChunkSamples) * size_t(pack.oversampling), 0.0);
}

void SympatheticStrings::install(VoicePack& pack, bool carry)
{
    pack_ = &pack;
    damping_ = controls_.current().sympatheticDamping;
    for (int k = 0; k < count(); ++k)
    {
        if (!carry)
            voice(k).silence();
        pitch_[size_t(k)] = wantedPitch(k);
        retune(k);
    }
}

void SympatheticStrings::follow(bool dampingChanged)
{
    const double damping = controls_.current().sympatheticDamping;
    const bool allDue = dampingChanged || damping != damping_;
    damping_ = damping;
    for (int k = 0; k < count(); ++k)
    {
        const double wanted = wantedPitch(k);
        if (allDue || wanted != pitch_[size_t(k)])
        {
            pitch_[size_t(k)] = wanted;
            retune(k);
        }
    }
}

double SympatheticStrings::wantedPitch(int k) const
{
    const auto& c = controls_.current();
    const int saKey = std::clamp(c.droneTonic, 12, 108);
    return sympatheticPitch(k, c.sympatheticScale, c.sympatheticIntonation, saPitch(c), saKey,
                            controls_.target().keyPitches);
}

void SympatheticStrings::retune(int k)
{
    const auto& c = controls_.current();
    const double hz = c.tuningA4Hz * std::pow(2.0, (pitch_[size_t(k)] - 69.0) / 12.0);
    pack_->sympatheticRetuner.retune(voice(k), hz / pack_->sympatheticFundamentalHz, c, damping_);
}

double SympatheticStrings::energy(int k) const
{
    return pack_->sympathetic[size_t(k)]->stringEnergy();
}

bool SympatheticStrings::atRest() const
{
    for (int k = 0; k < count(); ++k)
        if (!(energy(k) < kRestJoules))
            return false;
    return true;
}

}  // namespace jawari
