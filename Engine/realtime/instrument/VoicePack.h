#pragma once
// A VoicePack: everything built OFF the audio thread for one InstrumentStructure (its string, its
// obstacles, the quality, twelve voices and their backups, the drawing tables, the mix buffers and
// decimators), installed by the Instrument at a block boundary. Also how a structure becomes the
// physics: its string, obstacles, second polarisation and quality.

#include "physics/contact/ContactLaw.h"
#include "physics/contact/Obstacle.h"
#include "physics/body/SharedBody.h"
#include "physics/string/StringModel.h"
#include "realtime/voice/Decimator.h"
#include "realtime/instrument/InstrumentSettings.h"
#include "realtime/voice/Quality.h"
#include "realtime/instrument/StringRetuner.h"
#include "realtime/voice/Voice.h"

#include <memory>
#include <optional>
#include <vector>

namespace jawari
{

// The obstacles an InstrumentStructure stands for, at a given height offset. OFF.
std::vector<Obstacle> instrumentObstacles(const InstrumentStructure& s, const ContactLaw& law, double height);
StringParameters instrumentString(const InstrumentStructure& s);
// The second polarisation of a structure with two (else none): detuned by 1e-3, damped alike,
// plucked in the vertical, and coupled 1 cm from the far end by a spring tilted 30 degrees, a tenth
// as stiff as the string itself is there (0.1 T / 1 cm: it raises the vertical's pitch by about
// 0.1 %, which the tuning takes out).
std::optional<SecondPolarisation> instrumentSecondPolarisation(const InstrumentStructure& s);
// M and the oversampling of the structure's quality at its host rate.
VoiceQuality instrumentQuality(const InstrumentStructure& s);
// The structure's body (FactoryBodies.h) with its tuning and damping, or none. OFF.
std::optional<ModalBody> instrumentBody(const InstrumentStructure& s);
// The played strings' voice configuration as buildVoicePack gives it (the structure taken as
// playableStructure makes it): its string, obstacles, quality, forcing and pickup. OFF.
VoiceConfig instrumentVoiceConfig(const InstrumentStructure& structure);
// The soft pluck's push (PluckStyle::soft): DAFx-16's shape over kPushSeconds, spread over half the
// string, kPushNewtons towards the obstacles at full velocity.
ForcePluck instrumentPush(const InstrumentStructure& s);
inline constexpr double kPushSeconds = 0.05;
inline constexpr double kPushNewtons = 1.8;
// Through a body, the radiated pressure (Pa) that plays at full scale.
inline constexpr double kFullScalePascals = 0.025;

// The right channel's pickup sits this fraction of the length further from the end than the
// first pickup (at least 2 % of the length from either end): a second position weights the modes
// differently, phi_p(x_R) against phi_p(x_L).
inline constexpr double kSecondPickupOffset = 0.05;

inline constexpr int kMidiVoices = 8;
inline constexpr int kDroneStrings = 4;
inline constexpr int kSlots = kMidiVoices + kDroneStrings;
inline constexpr int kDrawPoints = 96;  // the points along the string the editor draws
// The instrument renders in chunks of this many host samples: the pack's buffers hold one.
inline constexpr int kChunkSamples = 32;

// Everything built for one structure. OFF to build and to free.
struct VoicePack
{
    InstrumentStructure structure;
    StringParameters string;
    double baseFundamentalHz = 0.0;              // mode 1 of the built string
    std::vector<std::unique_ptr<Voice>> voices;  // kSlots
    StringRetuner retuner;                       // retunes the voices, with scratch of its own
    std::vector<double> drawShapes;              // kDrawPoints x M: phi_p at the drawing points (the vertical)
    std::vector<double> drawHorizontal;          // the same for the horizontal polarisation; empty with one
    std::vector<double> drawObstacle;            // kDrawPoints: obstacle height at height 0, or NaN
    int modes = 0;
    int latencySamples = 0;
    // Output units per metre at the pickup: 120 / sin(pi x_pickup / L), so a 1.5 mm pluck peaks
    // near -15 dBFS wherever the pickup is (the drone's four strings at half that each).
    double outputScale = 120.0;
    // The second pickup's level matched to the first's (their sines' ratio); through a body, the
    // pickup's (the string's velocity) against the body's.
    double secondPickupGain = 1.0;
    // The strings are mixed at the internal rate and decimated once per channel (the decimator is
    // linear): the two decimators and the chunk's internal-rate buffers (kChunkSamples host
    // samples each).
    std::vector<Decimator> decimators;  // left, right
    std::vector<double> mixLeft, mixRight;
    std::vector<double> stringBlocks;  // kSlots chunks at the internal rate: each string's, before the mix
    std::vector<double> secondBlocks;  // the same from each string's second pickup (the right channel)
    // A second core's share (StringWorker): each slot's backup of its voice (a copy the audio thread
    // steps when the worker is late), and the blocks the worker steps the voice into.
    std::vector<std::unique_ptr<Voice>> backups;
    std::vector<double> workerBlocks, workerSecondBlocks;
    int oversampling = 1;
    // Through a body: the one body every string stands on (SharedBody: the strings step in lockstep
    // with it, on the audio thread), and one chunk at the internal rate of its radiated pressure at
    // each channel (SharedBody::pressure: the left, the right). Null without a body.
    std::unique_ptr<SharedBody> body;
    std::array<std::vector<double>, 2> bodyBlocks;
    // The sympathetic strings on that body (SympatheticStrings.h; none without a body): their voices,
    // their retuner, the fundamental their voices were built at, and one chunk of the
    // radiated pressure that their forces alone make at each channel (SharedBody::partPressure).
    std::vector<std::unique_ptr<Voice>> sympathetic;
    StringRetuner sympatheticRetuner;
    double sympatheticFundamentalHz = 0.0;
    // The loaded pitch's share of the ratio, f(r) / (r f(1)), at log-spaced ratios (SympatheticStrings.cpp):
    // the bridge's spring stays as stiff while the tension scales.
    std::vector<double> sympatheticLoading;
    std::array<std::vector<double>, 2> sympatheticBlocks;

    // RT: takes the string state of another pack slot by slot (new obstacle, pluck point, ...),
    // and the decimators' history.
    void takeMotionFrom(VoicePack& other);
};

// Any structure: it is built as playableStructure(structure) (PlayableStructure.h).
std::unique_ptr<VoicePack> buildVoicePack(const InstrumentStructure& structure);
// The latency (host samples) of the pack buildVoicePack would build, without building it. OFF.
int voicePackLatency(const InstrumentStructure& structure);

}  // namespace jawari
