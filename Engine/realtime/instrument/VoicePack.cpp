// A VoicePack: everything built OFF the audio thread for one InstrumentStructure (the string, its
// obstacles on their contact points, the quality, twelve voices, the drawing tables, the decimators).

#include "realtime/instrument/VoicePack.h"

#include "physics/body/FactoryBodies.h"
#include "physics/string/SpringLoadedModes.h"
#include "realtime/instrument/PlayableStructure.h"
#include "realtime/sympathetic/SympatheticStrings.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace jawari
{
namespace
{
double clampFraction(double x)
{
    return std::clamp(x, 0.005, 0.995);
}

// The right channel's pickup: kSecondPickupOffset further from the nearer end than the first.
double secondPickupFraction(double pickup)
{
    const double x = clampFraction(pickup);
    return std::clamp(x > 0.5 ? x - kSecondPickupOffset : x + kSecondPickupOffset, 0.02, 0.98);
}

// The frequency the notes tune: mode 1's, or with two polarisations that of the coupled mode most
// like the vertical's first (the largest share of it in the vertical pluck's map); with a damped
// thread, that mode's with the thread's springs folded in.
double verticalFundamentalHz(const ModalSolverConfig& c, int M)
{
    int best = 0;
    if (!c.shapeToModes.empty())
        for (int k = 1; k < c.modes.size(); ++k)
            if (std::abs(c.shapeToModes[size_t(k) * M]) > std::abs(c.shapeToModes[size_t(best) * M]))
                best = k;
    // With a damped thread holding the string, the mode it sounds (SpringLoadedModes.h).
    return springLoadedFrequencyHz(c, best);
}

// What the editor draws, the vertical displacement at kDrawPoints points, per solver mode: phi_p(x),
// or with two polarisations each coupled mode's vertical shape, sum_p B_kp phi_p(x) (B the
// vertical pluck's map into the modes, shapeToModes: the vertical part of the modes' basis).
std::vector<double> drawingShapes(const ModalSolverConfig& c, double L, int M)
{
    const int N = c.modes.size();
    std::vector<double> shapes(size_t(kDrawPoints) * N, 0.0);
    std::vector<double> phi(static_cast<size_t>(M));
    for (int k = 0; k < kDrawPoints; ++k)
    {
        const double x = L * k / (kDrawPoints - 1);
        for (int p = 0; p < M; ++p)
            phi[size_t(p)] = modeShape(L, p + 1, x);
        double* row = shapes.data() + size_t(k) * N;
        if (c.shapeToModes.empty())
            std::copy(phi.begin(), phi.end(), row);
        else
            for (int j = 0; j < N; ++j)
                for (int p = 0; p < M; ++p)
                    row[j] += c.shapeToModes[size_t(j) * M + p] * phi[size_t(p)];
    }
    return shapes;
}
}  // namespace

StringParameters instrumentString(const InstrumentStructure& s)
{
    const auto& type = kStringTypes[std::clamp(s.stringType, 0, kStringTypeCount - 1)];
    StringParameters p;
    p.lengthMetres = type.lengthMetres;
    p.linearDensity = type.linearDensity;
    p.diameterMetres = type.diameterMetres;
    const double c = 2.0 * type.lengthMetres * type.fundamentalHz;
    p.tensionNewtons = type.linearDensity * c * c;
    p.inharmonicity = std::max(0.0, s.inharmonicity);
    return p;
}

std::optional<SecondPolarisation> instrumentSecondPolarisation(const InstrumentStructure& s)
{
    if (s.polarisations < 2)
        return std::nullopt;
    const auto string = instrumentString(s);
    SecondPolarisation second;
    second.detuning = 1e-3;
    second.coupling = {string.lengthMetres - 0.01, std::numbers::pi / 6, 0.1 * string.tensionNewtons / 0.01};
    return second;
}

std::vector<Obstacle> instrumentObstacles(const InstrumentStructure& s, const ContactLaw& law, double height)
{
    const double L = instrumentString(s).lengthMetres;
    std::vector<Obstacle> obstacles;
    Obstacle o;
    o.law = law;
    o.height = height;
    o.width = std::max(s.obstacleWidth, 1e-5);
    switch (s.shape)
    {
        case ObstacleShape::point:
            o.type = ObstacleType::point;
            o.position = clampFraction(s.obstaclePosition) * L;
            obstacles.push_back(o);
            break;
        case ObstacleShape::parabola:
            o.type = ObstacleType::parabola;
            o.position = clampFraction(s.obstaclePosition) * L;
            o.curvature = std::max(0.0, s.curvature);
            if (const int intervals = instrumentQuality(s).contactIntervals; intervals > 0)
                o.spacing = L / intervals;  // the quality's points (Quality.h), the thread's band's too
            if (s.thread)
            {
                // The string rests on its highest support (the thread, or a steep bridge's crown) at
                // `height`.
                // NaN-safe: a value that is not a number lays the thread at the edge, 1 um thick.
                const double offset = s.threadOffset > 0.0 ? std::min(s.threadOffset, o.width) : 0.0;
                const double diameter = s.threadDiameter > 1e-6 ? s.threadDiameter : 1e-6;
                Thread thread{offset, diameter, law, s.threadModel, kThreadWidthMetres, s.threadStiffness,
                              s.threadDamping};
                Obstacle point = layThread(o, thread);
                o.height += height;
                if (!point.law.bilateral)  // the damped thread holds the string at its rest line
                    point.height += height;
                obstacles.push_back(o);
                obstacles.push_back(point);
            }
            else
                obstacles.push_back(o);
            break;
        case ObstacleShape::frets:
            o.type = ObstacleType::point;
            for (int k = 1; k <= 5; ++k)
            {
                o.position = L * std::pow(2.0, -k / 12.0);
                obstacles.push_back(o);
            }
            break;
    }
    return obstacles;
}

std::optional<ModalBody> instrumentBody(const InstrumentStructure& s)
{
    const int choice = std::clamp(static_cast<int>(s.body), 0, static_cast<int>(std::size(kBodyNames)) - 1);
    if (choice == static_cast<int>(BodyChoice::none))
        return std::nullopt;
    auto body = factoryBody(kBodyNames[choice]);
    const double tuning = std::clamp(s.bodyTuning, 0.25, 4.0), damping = std::clamp(s.bodyDamping, 0.0, 100.0);
    for (auto& mode : body->modes)
    {
        mode.frequencyHz *= tuning;
        mode.sigma *= tuning * damping;  // the loss factor stays, times the damping
    }
    return body;
}

ForcePluck instrumentPush(const InstrumentStructure& s)
{
    ForcePluck push;
    push.width = 0.5 * instrumentString(s).lengthMetres;
    push.amplitude = -kPushNewtons;
    push.duration = kPushSeconds;
    return push;
}

VoiceQuality instrumentQuality(const InstrumentStructure& s)
{
    const auto settings =
        qualitySettings(s.shape == ObstacleShape::parabola ? ObstacleKind::bridge : ObstacleKind::points);
    const int q = std::clamp(s.quality, 0, static_cast<int>(settings.size()) - 1);
    return resolveQuality(settings[size_t(q)], instrumentString(s), s.hostRateHz);
}

namespace
{
// The voices' configuration for a structure, at its quality.
VoiceConfig voiceConfig(const InstrumentStructure& structure, const StringParameters& string,
                        const VoiceQuality& quality)
{
    VoiceConfig config;
    config.string = string;
    config.obstacles = instrumentObstacles(structure, ContactLaw{}, 0.0);
    const double L = string.lengthMetres;
    config.excitationPosition = clampFraction(structure.pluckPosition) * L;
    config.pickupPosition = clampFraction(structure.pickupPosition) * L;
    config.secondPickupPosition = secondPickupFraction(structure.pickupPosition) * L;
    config.quantity = PickupQuantity::displacement;
    config.modes = quality.modes;
    config.oversampling = quality.oversampling;
    config.hostRateHz = structure.hostRateHz;
    config.releaseSeconds = std::max(structure.releaseSeconds, 0.01);
    // The quadratic spline solves decoupled points in closed form; the coupled points of a bridge
    // or of the frets take the energy-conserving Newton, the scheme it approximates.
    config.method = structure.method == ContactMethod::quadraticSpline && structure.shape != ObstacleShape::point
                        ? ContactMethod::energyConserving
                        : structure.method;
    config.keepEveryMode = true;
    // A rigid thread (a contact at 1e13 N/m^1.3 that the string slaps every period, at a step the
    // bridge table makes 3x) is met closer to the converged answer when each mode answers a force by
    // its exact static compliance: the Tanpura thread's scene 2.90 dB from it at 3x against 3.60 with
    // the paper's gain (docs/measurements.md, "The static-exact forcing"). Elsewhere the two are
    // within a quarter of a dB, either way, and the paper's gain stays.
    config.staticExactForcing =
        structure.shape == ObstacleShape::parabola && structure.thread && structure.threadModel == ThreadModel::contact;
    config.ownDecimator = false;  // mixed at the internal rate, then decimated per channel
    config.secondPolarisation = instrumentSecondPolarisation(structure);
    if (structure.pluck == PluckStyle::soft)
        config.push = instrumentPush(structure);
    if (structure.body != BodyChoice::none)
    {
        // The strings stand on the pack's shared body (SharedBody), their pickup the string's
        // velocity (a magnetic pickup's reading) that the mix sets beside the body's sound.
        config.movingBridge = true;
        config.quantity = PickupQuantity::velocity;
        config.secondPickupPosition.reset();
    }
    return config;
}

// The obstacles' heights at height 0 at the drawing points (NaN where there is none).
std::vector<double> drawingObstacle(const std::vector<Obstacle>& obstacles, double L)
{
    std::vector<double> heights(kDrawPoints, std::numeric_limits<double>::quiet_NaN());
    for (const auto& o : obstacles)
    {
        if (o.isDistributed())
        {
            for (int k = 0; k < kDrawPoints; ++k)
            {
                const double x = L * k / (kDrawPoints - 1);
                if (x >= o.supportBegin() && x <= o.supportEnd())
                    heights[size_t(k)] = o.heightAt(x);
            }
        }
        else
        {
            const int k =
                std::clamp(static_cast<int>(std::lround(o.position / L * (kDrawPoints - 1))), 0, kDrawPoints - 1);
            heights[size_t(k)] = o.height;
        }
    }
    return heights;
}

// The chunk's buffers, the decimators and each voice's backup for the second core.
void allocateMixing(VoicePack& pack, const VoiceConfig& config, const ModalSolverConfig& solverConfig)
{
    pack.decimators.assign(2, Decimator(pack.oversampling, pack.structure.hostRateHz));
    pack.latencySamples = pack.decimators.front().latencyHostSamples();
    const size_t chunkSteps = size_t(kChunkSamples) * size_t(pack.oversampling);
    pack.mixLeft.assign(chunkSteps, 0.0);
    pack.mixRight.assign(chunkSteps, 0.0);
    pack.stringBlocks.assign(size_t(kSlots) * chunkSteps, 0.0);
    pack.secondBlocks.assign(size_t(kSlots) * chunkSteps, 0.0);
    // Built as the voices are (not copied from them): the same reserved capacities, so copying a
    // voice into its backup never allocates.
    for (int i = 0; i < kSlots; ++i)
        pack.backups.push_back(std::make_unique<Voice>(config, solverConfig));
    pack.workerBlocks.assign(size_t(kSlots) * chunkSteps, 0.0);
    pack.workerSecondBlocks.assign(size_t(kSlots) * chunkSteps, 0.0);
}

// The output's scale, and the second pickup's gain relative to the first.
void setOutputLevels(VoicePack& pack)
{
    const auto& structure = pack.structure;
    auto pickupSine = [](double fraction) { return std::max(std::sin(std::numbers::pi * fraction), 0.02); };
    const double sine = pickupSine(clampFraction(structure.pickupPosition));
    if (structure.body != BodyChoice::none)
    {
        // The pressure (Pa) at full scale over kFullScalePascals; the string's velocity at the pickup
        // at the displacement's level at 1 kHz (|v| = 2 pi f |u|): a tanpura's note then plays about
        // as loud through the pickup, whose velocity is mostly its high partials, as without a body.
        pack.outputScale = 1.0 / kFullScalePascals;
        pack.secondPickupGain = kFullScalePascals * 120.0 / sine / (2.0 * std::numbers::pi * 1000.0);
        return;
    }
    pack.outputScale = 120.0 / sine;
    // The second pickup at the first's level by the same law (it sits further from the end, where
    // the string moves more).
    pack.secondPickupGain = sine / pickupSine(secondPickupFraction(structure.pickupPosition));
}
}  // namespace

VoiceConfig instrumentVoiceConfig(const InstrumentStructure& requested)
{
    const InstrumentStructure structure = playableStructure(requested);
    return voiceConfig(structure, instrumentString(structure), instrumentQuality(structure));
}

std::unique_ptr<VoicePack> buildVoicePack(const InstrumentStructure& requested)
{
    const InstrumentStructure structure = playableStructure(requested);
    auto pack = std::make_unique<VoicePack>();
    pack->structure = structure;
    pack->string = instrumentString(structure);
    const auto quality = instrumentQuality(structure);
    const VoiceConfig config = voiceConfig(structure, pack->string, quality);
    const double L = pack->string.lengthMetres;
    const ModalSolverConfig solverConfig = voiceSolverConfig(config);
    for (int i = 0; i < kSlots; ++i)
        pack->voices.push_back(std::make_unique<Voice>(config, solverConfig));
    // The solver's modes: M, or 2M with two polarisations (the coupled string's modes).
    const int N = solverConfig.modes.size();
    pack->modes = N;
    pack->baseFundamentalHz = verticalFundamentalHz(solverConfig, quality.modes);
    pack->retuner = StringRetuner(pack->string, N);
    pack->drawShapes = drawingShapes(solverConfig, L, quality.modes);
    if (config.secondPolarisation)
    {
        // The horizontal's shapes: the same modes' map of a pluck along the horizontal.
        auto horizontal = config;
        horizontal.secondPolarisation->excitationAngle = std::numbers::pi / 2;
        pack->drawHorizontal = drawingShapes(voiceSolverConfig(horizontal), L, quality.modes);
    }
    pack->drawObstacle = drawingObstacle(config.obstacles, L);
    pack->oversampling = quality.oversampling;
    allocateMixing(*pack, config, solverConfig);
    setOutputLevels(*pack);
    if (auto body = instrumentBody(structure))
    {
        pack->body = std::make_unique<SharedBody>(*body, 1.0, solverConfig.timeStep);
        pack->body->check(pack->voices.front()->solver());
        pack->body->setOneWay(structure.bodyOneWay);
        for (auto& block : pack->bodyBlocks)
            block.assign(size_t(kChunkSamples) * size_t(pack->oversampling), 0.0);
        addSympatheticStrings(*pack, quality);
    }
    return pack;
}

int voicePackLatency(const InstrumentStructure& structure)
{
    const InstrumentStructure s = playableStructure(structure);
    return Decimator(instrumentQuality(s).oversampling, s.hostRateHz).latencyHostSamples();
}

void VoicePack::takeMotionFrom(VoicePack& other)
{
    if (other.modes != modes || other.structure.hostRateHz != structure.hostRateHz)
        return;
    for (size_t i = 0; i < voices.size() && i < other.voices.size(); ++i)
        voices[i]->takeMotionFrom(*other.voices[i]);
    if (sympathetic.size() == other.sympathetic.size())
        for (size_t k = 0; k < sympathetic.size(); ++k)
            sympathetic[k]->takeMotionFrom(*other.sympathetic[k]);
    if (other.oversampling == oversampling)
        for (size_t c = 0; c < decimators.size(); ++c)
            decimators[c] = other.decimators[c];  // equal lengths: no allocation
}

}  // namespace jawari
