#pragma once
// The playable instrument behind the plugin (no JUCE): eight MIDI voices and the four strings of
// the tanpura drone, all of one string type against one obstacle (each string with its own copy of
// it), mixed to stereo.
//
// What needs new tables (string type, obstacle shape/position/width, pluck and pickup points,
// inharmonicity, quality, method, release time, host rate) is an InstrumentStructure: a VoicePack
// is built for it OFF the audio thread and installed at a block boundary, each string carrying its
// motion over when the modes match. Everything else is InstrumentControls, applied on the audio
// thread every chunk of 32 samples, smoothed: the note's pitch and bend (every mode's frequency
// scaled, docs/design.md section 1), the obstacle's height, stiffness and exponent, the damping law's
// constants, a global decay scale and a per-mode damping curve, the output gain.

#include "physics/ContactLaw.h"
#include "physics/Obstacle.h"
#include "physics/StringModel.h"
#include "realtime/Quality.h"
#include "realtime/SnapshotBuffer.h"
#include "realtime/StringBank.h"
#include "realtime/StringWorker.h"
#include "realtime/Tuning.h"
#include "realtime/Voice.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

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

    bool operator==(const InstrumentStructure&) const = default;
};

inline constexpr int kDampingCurvePoints = 12;     // the per-mode damping curve: log-spaced 20 Hz .. 20 kHz
inline constexpr double kDampingCurveMin = 0.125;  // its multipliers' range
inline constexpr double kDampingCurveMax = 8.0;

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
    // How far the MIDI strings spread across the stereo field by pitch: 0 all in the centre; 1 from
    // hard left at C3 (48) and below to hard right at C7 (96) and above, C5 (72) in the centre. It
    // also mixes the second pickup into the right channel: (1 - width) of the first pickup and
    // width of the second (kSecondPickupOffset). 0 is mono (the drone keeps its pans).
    double stereoWidth = 0.6;
    double bendRangeSemitones = 2.0;
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
};

// The frequency of the damping curve's point i (Hz) and the curve's multiplier at f (log-log
// interpolation, flat beyond the ends). RT.
double dampingCurveFrequency(int i);
double dampingCurveAt(const std::array<double, kDampingCurvePoints>& curve, double frequencyHz);

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

// How the sounding strings are stepped: each voice alone through its chunk (the default: the faster
// on the machines measured, docs/measurements.md), or the string bank stepping them together with
// their contact solves in SIMD lanes (StringBank.h).
enum class StringScheduling
{
    lone,
    bank
};

// The right channel's pickup sits this fraction of the length further from the end than the
// first pickup (at least 2 % of the length from either end): a second position weights the modes
// differently, phi_p(x_R) against phi_p(x_L).
inline constexpr double kSecondPickupOffset = 0.05;

inline constexpr int kMidiVoices = 8;
inline constexpr int kDroneStrings = 4;
inline constexpr int kSlots = kMidiVoices + kDroneStrings;
inline constexpr int kDrawPoints = 96;

// Everything built for one structure. OFF to build and to free.
struct VoicePack
{
    InstrumentStructure structure;
    StringParameters string;
    double baseFundamentalHz = 0.0;              // mode 1 of the built string
    std::vector<std::unique_ptr<Voice>> voices;  // kSlots
    std::vector<double> sigma;                   // kSlots x M: scratch for retunes
    std::vector<double> drawShapes;              // kDrawPoints x M: phi_p at the drawing points (the vertical)
    std::vector<double> drawHorizontal;          // the same for the horizontal polarisation; empty with one
    std::vector<double> drawObstacle;            // kDrawPoints: obstacle height at height 0, or NaN
    int modes = 0;
    int latencySamples = 0;
    // Output units per metre at the pickup: 120 / sin(pi x_pickup / L), so a 1.5 mm pluck peaks
    // near -15 dBFS wherever the pickup is (the drone's four strings at half that each).
    double outputScale = 120.0;
    double secondPickupGain = 1.0;  // the second pickup's level matched to the first's (their sines' ratio)
    // The strings are mixed at the internal rate and decimated once per channel (the decimator is
    // linear): the two decimators and the chunk's internal-rate buffers (Instrument::kChunk host
    // samples each).
    std::vector<Decimator> decimators;  // left, right
    std::vector<double> mixLeft, mixRight;
    std::vector<double> stringBlocks;   // kSlots chunks at the internal rate: each string's, before the mix
    std::vector<double> secondBlocks;   // the same from each string's second pickup (the right channel)
    // A second core's share (StringWorker): each slot's backup of its voice (a copy the audio thread
    // steps when the worker is late), and the blocks the worker steps the voice into.
    std::vector<std::unique_ptr<Voice>> backups;
    std::vector<double> workerBlocks, workerSecondBlocks;
    int oversampling = 1;

    // RT: takes the string state of another pack slot by slot (new obstacle, pluck point, ...),
    // and the decimators' history.
    void takeMotionFrom(VoicePack& other);
};

// Any structure: it is built as playableStructure(structure) (PlayableStructure.h).
std::unique_ptr<VoicePack> buildVoicePack(const InstrumentStructure& structure);
// The latency (host samples) of the pack buildVoicePack would build, without building it. OFF.
int voicePackLatency(const InstrumentStructure& structure);

// What the editor draws, published by the audio thread without locks (SnapshotBuffer).
struct InstrumentSnapshot
{
    std::array<float, kDrawPoints> shape{};     // the loudest string's displacement (m): its vertical
    std::array<float, kDrawPoints> horizontal{};  // its horizontal polarisation's (m), 0 with one
    bool twoPolarisations = false;
    std::array<float, kDrawPoints> obstacle{};  // obstacle height (m) or NaN where none
    float energy = 0.0f;                        // J, all strings
    float penetration = 0.0f;                   // deepest penetration this chunk (m)
    int maxIterations = 0;
    int activeStrings = 0;
    long blowUps = 0;
    long limited = 0;  // output samples the guard changed (Instrument::limitedSamples)
    uint64_t sequence = 0;
};

// What the instrument did since clearActivity(): what can make a block slow (jawari-soak attributes
// its slowest blocks with it). RT: plain counters.
struct InstrumentActivity
{
    int notesStarted = 0;   // strings started from rest (a held shape)
    int pulses = 0;         // strings re-plucked while sounding (a force pulse)
    int dronePlucks = 0;
    int retunes = 0;        // strings retuned (a note's start, a bend, new damping)
    int packsInstalled = 0;
    long newtonIterations = 0;  // contact solve iterations, all strings
    int mostIterations = 0;     // the most in one step
    long workerStrings = 0;     // string chunks the second core stepped
    long workerRevoked = 0;     // string chunks taken back from the second core, late
    long workerUnstarted = 0;   // string chunks the second core had not started when collected
    long limitedSamples = 0;    // output samples the guard changed (guardOutput)
};

// The output's safety guard, the last step of Instrument::render: a non-finite sample becomes 0 and
// a sample beyond +-kOutputCeiling (+12 dBFS) is clamped to it; between full scale and the ceiling
// a sample passes (hosts mix in floating point). Returns how many samples it changed: any at all
// means something went wrong upstream. RT.
inline constexpr float kOutputCeiling = 4.0f;
long guardOutput(float* samples, int numSamples);

class Instrument
{
public:
    Instrument();

    // RT: installs a pack (the caller keeps ownership and frees the previous one OFF). When
    // `previous` is given and has the same modes, each string keeps sounding.
    void install(VoicePack* pack, VoicePack* previous);
    VoicePack* pack() const { return pack_; }

    // RT, velocity 0..1. `channel`: the note's own MIDI channel under MPE (1..16), whose expression
    // it follows; 0 for none (every note then follows only the instrument's bend).
    void noteOn(int note, double velocity, int channel = 0);
    void noteOff(int note, int channel = 0);  // RT
    // RT: MPE per-note expression for the notes of one channel (1..16): their own bend (semitones),
    // pressure (0..1: presses their strings' bridge up to kPressureHeightMetres further in, for more
    // buzz) and slide (0..1, 0.5 neutral: 0 doubles their damping, 1 halves it).
    void channelBend(int channel, double semitones);
    void channelPressure(int channel, double amount);
    void channelSlide(int channel, double amount);
    static constexpr double kPressureHeightMetres = 0.5e-3;
    void sustain(bool down);                                                      // RT
    void pitchBend(double amount);                                                // RT, -1..1 of the bend range
    void allNotesOff();                                                           // RT: every MIDI string released
    void setControls(const InstrumentControls& controls) { target_ = controls; }  // RT
    // RT: the smoothed controls (obstacle, gain) jump to their targets: where playback starts
    // there is nothing to glide from.
    void settleControls();
    void setScheduling(StringScheduling scheduling) { scheduling_ = scheduling; }  // RT
    // RT: a second core to share the strings with (lone scheduling; StringWorker.h), or null for
    // none. The output is the same bit for bit. The worker must outlive every pack it was given a
    // share of: before a retired pack is freed, StringWorker::waitForJobs(postedJobs()).
    void setWorker(StringWorker* worker) { worker_ = worker; }
    StringBank& bank() { return bank_; }

    // RT: numSamples of stereo at the host rate, replacing what is in left/right.
    void render(float* left, float* right, int numSamples);

    SnapshotBuffer<InstrumentSnapshot>& snapshots() { return snapshots_; }
    int activeStrings() const;
    // The voices' blow-ups (a string that ran away, restarted from rest: Voice::blowUps) and the
    // output samples the guard changed, since construction, every pack's. Plain counters.
    long blowUps() const;
    long limitedSamples() const { return limitedSamples_; }
    int maxIterations() const { return maxIterations_; }  // the most of any step since construction
    long dronePlucks() const { return dronePlucks_; }
    const InstrumentActivity& activity() const { return activity_; }
    void clearActivity() { activity_ = {}; }  // RT
    // The pitch ratio, pitch and note a slot plays (tests).
    double slotRatio(int slot) const { return slots_[size_t(slot)].ratio; }
    double slotPitch(int slot) const { return slots_[size_t(slot)].pitch; }
    int slotChannel(int slot) const { return slots_[size_t(slot)].channel; }
    int slotNote(int slot) const { return slots_[size_t(slot)].note; }

    static constexpr int kChunk = 32;

private:
    struct Slot
    {
        int note = -1;       // the key (or the drone string's nearest note)
        int channel = 0;     // its MPE channel, 0 for none
        double pitch = 0.0;  // what it plays, a fractional MIDI note (Tuning.h)
        bool held = false, sustained = false, sounding = false;
        uint64_t age = 0;
        double ratio = 1.0;  // the ratio the voice is tuned to
        double peakEnergy = 0.0;
        // A steal: the string fades out over kFadeSamples, then the pending note starts from rest.
        int fade = -1;
        int pendingNote = -1;
        int pendingChannel = 0;
        double pendingVelocity = 0.0;
        bool pendingHeld = false, pendingSustained = false;
        double pan = 0.0;  // -1 .. 1
    };
    void start(int slot, int note, double pitch, double velocity, int channel = 0);
    void startKey(int slot, int note, double velocity, int channel);  // a MIDI key at its pitch in keyPitches
    double slotPitchNow(int slot) const;                              // its pitch with the bends that apply to it
    double slotHeight(int slot) const;                                // its bridge's height with its pressure
    double keyboardPan(double pitch) const;                           // -1 .. 1: where a MIDI string at a pitch sits
    void retune(int slot);
    double noteRatio(double note) const;
    void applyContact();
    ContactLaw contactLaw() const;
    void dronePluck(int string);
    void scheduleDrone(int samples);
    void publishSnapshot();
    void smoothControls(double k20);
    void retuneSounding(int count, double rate);
    void mixChunk(float* left, float* right, int count, double gainStart);
    // The sounding strings' chunk (n of them: voices[k] into blocks[k], seconds[k]); with a worker
    // the second core's share may come back in its own blocks, written over blocks[k], seconds[k].
    struct Sounding
    {
        std::array<Voice*, kSlots> voices{};
        std::array<double*, kSlots> blocks{}, seconds{};
        std::array<int, kSlots> slots{};
        int count = 0;
    };
    void stepStrings(Sounding& sounding, int samples);
    void stepWithWorker(Sounding& sounding, int samples);
    void mixString(int slot, const double* block, const double* second, int count, double gainStart);
    void startPendingNote(int slot);
    long packBlowUps() const;  // the installed pack's voices' own counts

    // Per-note expression of each MIDI channel (index 1..16; 0 stays neutral).
    struct Expression
    {
        double bend = 0.0, pressure = 0.0, slide = 0.5;
    };
    std::array<Expression, 17> channels_{};
    std::array<bool, 17> slideMoved_{};
    bool pressureMoved_ = false;
    VoicePack* pack_ = nullptr;
    StringScheduling scheduling_ = StringScheduling::lone;
    StringBank bank_;
    StringWorker* worker_ = nullptr;
    int workerBias_ = 0;  // strings the worker takes beyond half (InstrumentStrings.cpp)
    int fadeLength_ = 1;  // a steal's fade-out, host samples
    std::array<Slot, kSlots> slots_{};
    InstrumentControls target_, current_;
    bool dampingDirty_ = true;
    double bend_ = 0.0, bendSmoothed_ = 0.0;
    bool sustain_ = false;
    uint64_t clock_ = 0;
    double gain_ = 1.0;

    bool droneOn_ = false;
    double droneCountdown_ = 0.0;  // host samples to the next drone pluck
    int droneNext_ = 0;
    long dronePlucks_ = 0;
    InstrumentActivity activity_;
    uint32_t random_ = 0x2545F491u;
    double nextRandom();  // uniform -1..1
    int maxIterations_ = 0;
    int chunksSinceSnapshot_ = 0;
    uint64_t chunkClock_ = 0;
    double chunkPenetration_ = 0.0;
    long limitedSamples_ = 0;
    long blowUpsRetired_ = 0;    // blow-ups in the packs installed before this one, since their install
    long blowUpsAtInstall_ = 0;  // the installed pack's count when it was installed
    SnapshotBuffer<InstrumentSnapshot> snapshots_;
    uint64_t snapshotSequence_ = 0;
};

}  // namespace jawari
