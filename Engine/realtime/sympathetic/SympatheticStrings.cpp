#include "realtime/sympathetic/SympatheticStrings.h"

#include "physics/string/SpringLoadedModes.h"

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

Obstacle sympatheticBridge(double lengthMetres)
{
    Obstacle bridge;
    bridge.type = ObstacleType::point;
    bridge.position = 0.03 * lengthMetres;
    bridge.width = 1e-3;  // the point's weight: the law's stiffness is per metre of it
    bridge.law.bilateral = true;
    bridge.law.exponent = 1.0;
    bridge.law.stiffness = kSympatheticBridgeStiffness / bridge.width;
    return bridge;
}

Obstacle sympatheticJawari(double lengthMetres)
{
    Obstacle jawari;
    jawari.type = ObstacleType::point;
    jawari.position = sympatheticBridge(lengthMetres).position + kSympatheticJawariDistance;
    jawari.height = 0.0;
    jawari.width = 1e-3;
    jawari.law.exponent = 1.5;
    jawari.law.stiffness = 1e12;
    return jawari;
}

namespace
{
// The first mode on its bridge's spring (SpringLoadedModes.h) of the voice `config` builds, its
// tension scaled by ratio^2 (B kept). OFF.
double loadedHzAt(VoiceConfig config, double ratio)
{
    config.string.tensionNewtons = config.string.tensionNewtons * ratio * ratio;
    return springLoadedFrequencyHz(voiceSolverConfig(config), 0);
}
}  // namespace

StringParameters sympatheticStringAt(double hz)
{
    // The spring stays as stiff while the tension scales, so the loaded pitch is not quite
    // proportional to the ratio: a few fixed-point steps on it.
    VoiceQuality quality;
    quality.oversampling = 1;
    const VoiceConfig config = sympatheticVoiceConfig(quality, 48000.0);
    double ratio = 1.0;
    for (int step = 0; step < 4; ++step)
        ratio *= hz / loadedHzAt(config, ratio);
    StringParameters string = config.string;
    string.tensionNewtons = string.tensionNewtons * ratio * ratio;
    return string;
}

VoiceConfig sympatheticVoiceConfig(const VoiceQuality& quality, double hostRateHz, bool jawari)
{
    VoiceConfig config;
    config.string = sympatheticString();
    const double L = config.string.lengthMetres;
    config.obstacles = {sympatheticBridge(L)};
    if (jawari)
        config.obstacles.push_back(sympatheticJawari(L));
    config.excitationPosition = 0.5 * L;
    config.pickupPosition = 0.9 * L;
    config.quantity = PickupQuantity::velocity;
    config.modes = jawari ? kSympatheticJawariModes : kSympatheticModes;
    config.oversampling = quality.oversampling;
    config.hostRateHz = hostRateHz;
    config.method = ContactMethod::energyConserving;
    config.keepEveryMode = true;
    config.ownDecimator = false;
    config.movingBridge = true;
    return config;
}

namespace
{
// The ratios the loading table spans, kLoadingPoints log-spaced from kLowestRatio to 1 / kLowestRatio.
constexpr double kLowestRatio = 0.25;
constexpr int kLoadingPoints = 33;
double loadingRatio(int i)
{
    return kLowestRatio * std::pow(1.0 / (kLowestRatio * kLowestRatio), double(i) / (kLoadingPoints - 1));
}

// f(r) / (r f(1)) at each table ratio: the voice's first mode on its spring with the tension scaled by r^2.
std::vector<double> springLoading(const VoiceConfig& config)
{
    const double f1 = loadedHzAt(config, 1.0);
    std::vector<double> loading;
    for (int i = 0; i < kLoadingPoints; ++i)
        loading.push_back(loadedHzAt(config, loadingRatio(i)) / (loadingRatio(i) * f1));
    return loading;
}

// The table at ratio r, linear in log r (clamped to its ends). RT.
double loadingAt(const std::vector<double>& loading, double r)
{
    const double x = std::clamp(std::log(r / kLowestRatio) / std::log(1.0 / (kLowestRatio * kLowestRatio)), 0.0, 1.0)
                     * (kLoadingPoints - 1);
    const int i = std::min(static_cast<int>(x), kLoadingPoints - 2);
    return loading[size_t(i)] + (x - i) * (loading[size_t(i + 1)] - loading[size_t(i)]);
}
}  // namespace

void addSympatheticStrings(VoicePack& pack, const VoiceQuality& quality)
{
    const int count = std::clamp(pack.structure.sympatheticStrings, 0, kMaxSympatheticStrings);
    if (!pack.body || count == 0)
        return;
    const bool jawari = pack.structure.sympatheticJawari;
    const VoiceConfig config = sympatheticVoiceConfig(quality, pack.structure.hostRateHz, jawari);
    const ModalSolverConfig solverConfig = voiceSolverConfig(config);
    for (int k = 0; k < count; ++k)
    {
        pack.sympathetic.push_back(std::make_unique<Voice>(config, solverConfig));
        if (jawari)
            pack.body->check(pack.sympathetic.back()->solver());
        else
            pack.body->checkLinear(pack.sympathetic.back()->solver());
    }
    pack.sympatheticRetuner = StringRetuner(config.string, solverConfig.modes.size());
    // The pitch it sounds on its bridge's spring (SpringLoadedModes.h), which the tunings aim at.
    pack.sympatheticFundamentalHz = springLoadedFrequencyHz(solverConfig, 0);
    pack.sympatheticLoading = springLoading(config);
    for (auto& block : pack.sympatheticBlocks)
        block.assign(size_t(kChunkSamples) * size_t(pack.oversampling), 0.0);
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
            retune(k, ModalSolver::RetuneMotion::keepActions);
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

void SympatheticStrings::retune(int k, ModalSolver::RetuneMotion motion)
{
    const auto& c = controls_.current();
    // The ratio whose loaded pitch r f(1) loading(r) is the note's: a few fixed-point steps.
    const double wanted = frequencyOfPitch(pitch_[size_t(k)], c.tuningA4Hz) / pack_->sympatheticFundamentalHz;
    double ratio = wanted;
    for (int step = 0; step < 4; ++step)
        ratio = wanted / loadingAt(pack_->sympatheticLoading, ratio);
    pack_->sympatheticRetuner.retune(voice(k), ratio, c, damping_, motion);
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
