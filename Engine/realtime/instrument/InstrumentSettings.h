#pragma once
// What the instrument is and how it is played, as two plain structs: an InstrumentStructure needs
// new tables (a VoicePack, built OFF the audio thread); InstrumentControls are applied on the audio
// thread every chunk, smoothed (SmoothedControls). Nothing here runs.

#include "physics/contact/ContactMethod.h"
#include "physics/contact/Obstacle.h"
#include "physics/string/StringModel.h"
#include "realtime/voice/DampingCurve.h"
#include "realtime/sympathetic/SympatheticTuning.h"
#include "realtime/playing/Tuning.h"

#include <algorithm>
#include <array>

namespace jawari
{

// The strings the instrument can be strung with. The tension sets each string's own pitch; a note
// retunes it (tension and bending stiffness scaled together: length, mass and B stay).
struct StringType
{
    const char* name;
    double lengthMetres;
    double linearDensity;  // kg/m
    double diameterMetres;
    double fundamentalHz;  // the flexible string's f0 at its tension
    double inharmonicity;  // default B
};
inline constexpr StringType kStringTypes[] = {
    {"steel (paper)", 1.002, 1.17e-3, 0.43e-3, 195.998, 1.78e-5},  // the paper's string
    {"sitar steel", 0.90, 0.55e-3, 0.30e-3, 220.0, 1.0e-5},
    {"bass E", 0.864, 20.0e-3, 2.6e-3, 41.2, 1.2e-4},
};
inline constexpr int kStringTypeCount = static_cast<int>(sizeof(kStringTypes) / sizeof(kStringTypes[0]));

enum class ObstacleShape
{
    point,     // one point at `position`, `width` of string
    parabola,  // a curved bridge: apex at `position`, extent `width`, curvature `curvature`
    frets      // five frets at x = L 2^(-k/12), k = 1..5 (from the far end), each `width` wide
};

// The body the strings' bridge stands on (FactoryBodies.h), or rigid supports.
enum class BodyChoice
{
    none,
    tanpura,
    sitar
};
inline constexpr const char* kBodyNames[] = {"none", "tanpura", "sitar"};

// How a note plucks its string: a 1.5 ms pulse at the pluck point (a plectrum's flick), or DAFx-16's
// push, which rises over 50 ms and lets go abruptly, spread over half the string (a finger's; through a
// body its sound grows after the pluck: docs/design.md section 1, "The body").
enum class PluckStyle
{
    sharp,
    soft
};

struct InstrumentStructure
{
    int stringType = 0;
    ObstacleShape shape = ObstacleShape::point;
    double obstaclePosition = 0.5;  // fraction of the length
    double obstacleWidth = 1e-3;    // m
    double curvature = 2.0;         // 1/m (parabola)
    double pluckPosition = 0.5;     // fraction of the length
    double pickupPosition = 0.99;   // fraction of the length
    double inharmonicity = 1.78e-5;
    int quality = 1;  // index into qualitySettings() for the obstacle: standard (twelve strings in real time, docs/measurements.md)
    // The quadratic spline by default: the Newton's accuracy at 1.5x its speed (docs/measurements.md).
    ContactMethod method = ContactMethod::quadraticSpline;
    double releaseSeconds = 0.4;
    double hostRateHz = 48000.0;
    // 1, or 2: each string's horizontal polarisation too, coupled near the far end
    // (instrumentSecondPolarisation; docs/design.md section 1, "Two polarisations").
    int polarisations = 1;
    // A thread across the parabolic bridge (Obstacle.h, layThread): the string rests on it, the
    // bridge lies `threadDiameter` below the string there. Ignored for the other shapes.
    bool thread = false;
    double threadOffset = 0.002;     // m from the bridge's edge nearer the termination
    double threadDiameter = 0.2e-3;  // m
    // DAFx-16's damped thread, 1.2 mm wide, by default; or a rigid contact with the bridge's law.
    ThreadModel threadModel = ThreadModel::springDamper;
    double threadStiffness = threadStiffnessForWidth(kThreadWidthMetres);  // N/m, the damped thread's
    double threadDamping = threadDampingForStiffness(threadStiffness);       // kg/s, the damped thread's
    PluckStyle pluck = PluckStyle::sharp;
    // The body under every obstacle of every string, one for all (SharedBody), heard through its
    // radiated sound (InstrumentControls::bodyMix). None: rigid supports.
    BodyChoice body = BodyChoice::none;
    double bodyTuning = 1.0;   // scales every body mode's frequency (a smaller body sounds higher)
    double bodyDamping = 1.0;  // scales every body mode's damping
    // The body driven one way (SharedBody::setOneWay): the strings on rigid supports, their forces
    // there driving it. A comparison for the researcher (jawari-soak --one-way), not the plugin's.
    bool bodyOneWay = false;
    // The sitar's sympathetic strings on the body (SympatheticStrings.h): 0 (none) to
    // kMaxSympatheticStrings, never plucked, tuned by InstrumentControls. Only with a body.
    int sympatheticStrings = 0;
    // Their jawari (SympatheticStrings.h): each grazes a point of its bridge's curved top and buzzes
    // on it. Off: they rest on their bridges' springs alone (linear, cheaper).
    bool sympatheticJawari = false;

    bool operator==(const InstrumentStructure&) const = default;
};

struct InstrumentControls
{
    double obstacleHeight = 0.0;                   // m, > 0 pushes into the string
    double stiffness = 1e13;                       // K
    double exponent = 1.3;                         // alpha
    double decayScale = 1.0;                       // multiplies every mode's damping
    double airScale = 1.0;                         // multiplies the air viscosity of Valette's law
    double deltaVe = DampingParameters{}.deltaVe;  // viscoelastic loss angle
    double qTeInv = DampingParameters{}.qTeInv;    // thermoelastic 1/Q
    std::array<double, kDampingCurvePoints> dampingCurve{1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};  // multipliers
    double gainDb = 0.0;
    // With a body: 1 plays its radiated sound, 0 the string's velocity at the pickup (an electric
    // pickup's), between a mix of the two. Without a body the pickup plays.
    double bodyMix = 1.0;
    // How far the MIDI strings spread across the stereo field by pitch: 0 all in the centre; 1 from
    // hard left at C3 (48) and below to hard right at C7 (96) and above, C5 (72) in the centre. It
    // also mixes the second pickup into the right channel: (1 - width) of the first pickup and
    // width of the second (kSecondPickupOffset). 0 is mono (the drone keeps its pans).
    double stereoWidth = 0.6;
    double bendRangeSemitones = 2.0;
    // How many of the eight MIDI strings may sound at once (1..8): a note beyond them steals one,
    // and the strings above a lowered limit fade out as a stolen string does (MidiNotes).
    int midiVoices = 8;
    double tuningA4Hz = 440.0;
    // The pitch each MIDI key plays (equal temperament, or a Scala scale: Tuning.h); NaN: unmapped.
    KeyboardPitches keyPitches = equalTemperament();
    // Tanpura drone.
    bool drone = false;
    int droneTonic = 49;     // MIDI note of Sa (C#3)
    double droneSaHz = 0.0;  // Sa's frequency (Hz) when above 0, instead of droneTonic
    int droneFirst = 0;      // first string: 0 Pa, 1 Ma, 2 Ni, 3 Sa (DroneFirstString)
    DroneTuning droneTuning = DroneTuning::just;
    std::array<double, 4> droneFineCents{0.0, 0.0, 0.0, 0.0};  // each drone string's fine tuning
    double droneTempo = 60;                                    // plucks per minute
    double humanise = 0.2;                                     // 0..1: timing and strength spread
    double droneStrength = 0.7;
    // The sympathetic strings (InstrumentStructure::sympatheticStrings): tuned from Sa (the drone's)
    // to a thaat or Sa-Pa, their damping scaled (a cloth laid over them: more), and their share of the
    // body's sound (1: as the body radiates it, 0: none of it).
    SympatheticScale sympatheticScale = SympatheticScale::kafi;
    SympatheticIntonation sympatheticIntonation = SympatheticIntonation::just;
    double sympatheticDamping = 1.0;
    double sympatheticLevel = 1.0;
};

// The instrument's Sa as a pitch: from its frequency when one is set, else its MIDI note.
inline double saPitch(const InstrumentControls& c)
{
    return c.droneSaHz > 0.0 ? pitchOfFrequency(c.droneSaHz, c.tuningA4Hz) : double(std::clamp(c.droneTonic, 12, 108));
}

}  // namespace jawari
