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
//
// Built from parts: SmoothedControls (the controls as played), NoteExpression (bends, MPE),
// StringSlots (the twelve strings as played), MidiNotes (keys, pedal, stealing), TanpuraDrone;
// each chunk the instrument steps them in order, steps the sounding strings (alone, in the bank or
// with a second core), mixes them at the internal rate and decimates the mix.

#include "realtime/playing/ControlSmoothing.h"
#include "realtime/instrument/InstrumentActivity.h"
#include "realtime/instrument/InstrumentSettings.h"
#include "realtime/playing/MidiNotes.h"
#include "realtime/playing/NoteExpression.h"
#include "realtime/instrument/SnapshotBuffer.h"
#include "realtime/instrument/StringBank.h"
#include "realtime/playing/StringSlots.h"
#include "realtime/instrument/StringWorker.h"
#include "realtime/sympathetic/SympatheticStrings.h"
#include "realtime/playing/TanpuraDrone.h"
#include "realtime/voice/Voice.h"
#include "realtime/instrument/VoicePack.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace jawari
{

// How the sounding strings are stepped: each voice alone through its chunk (the default: the faster
// on the machines measured, docs/measurements.md), or the string bank stepping them together with
// their contact solves in SIMD lanes (StringBank.h).
enum class StringScheduling
{
    lone,
    bank
};

// What the editor draws, published by the audio thread without locks (SnapshotBuffer).
struct InstrumentSnapshot
{
    std::array<float, kDrawPoints> shape{};       // the loudest string's displacement (m): its vertical
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

// The output's safety guard, the last step of Instrument::render: a non-finite sample becomes 0 and
// a sample beyond +-kOutputCeiling (+12 dBFS) is clamped to it; between full scale and the ceiling
// a sample passes (hosts mix in floating point). Returns how many samples it changed: any at all
// means something went wrong upstream. RT.
inline constexpr float kOutputCeiling = 4.0f;
long guardOutput(float* samples, int numSamples);

class Instrument
{
public:
    Instrument() = default;

    // RT: installs a pack (the caller keeps ownership and frees the previous one OFF). When
    // `previous` is given and has the same modes, each string keeps sounding.
    void install(VoicePack* pack, VoicePack* previous);
    VoicePack* pack() const { return pack_; }

    // RT, velocity 0..1. `channel`: the note's own MIDI channel under MPE (1..16), whose expression
    // it follows; 0 for none (every note then follows only the instrument's bend).
    void noteOn(int note, double velocity, int channel = 0);
    void noteOff(int note, int channel = 0);  // RT
    // RT: MPE per-note expression for the notes of one channel (NoteExpression).
    void channelBend(int channel, double semitones) { expression_.channelBend(channel, semitones); }
    void channelPressure(int channel, double amount) { expression_.channelPressure(channel, amount); }
    void channelSlide(int channel, double amount) { expression_.channelSlide(channel, amount); }
    static constexpr double kPressureHeightMetres = NoteExpression::kPressureHeightMetres;
    void sustain(bool down) { notes_.sustain(down); }                 // RT
    void pitchBend(double amount) { expression_.pitchBend(amount); }  // RT, -1..1 of the bend range
    void allNotesOff() { notes_.allNotesOff(); }                      // RT: every MIDI string released
    void setControls(const InstrumentControls& controls) { controls_.setTarget(controls); }  // RT
    // RT: the smoothed controls (obstacle, gain) jump to their targets: where playback starts
    // there is nothing to glide from.
    void settleControls() { followControls(1.0); }
    void setScheduling(StringScheduling scheduling) { scheduling_ = scheduling; }  // RT
    // RT: a second core to share the strings with (lone scheduling; StringWorker.h), or null for
    // none. The output is the same bit for bit. The worker must outlive every pack it was given a
    // share of: before a retired pack is freed, StringWorker::waitForJobs(postedJobs()).
    void setWorker(StringWorker* worker) { worker_ = worker; }
    StringBank& bank() { return bank_; }

    // RT: numSamples of stereo at the host rate, replacing what is in left/right.
    void render(float* left, float* right, int numSamples);

    SnapshotBuffer<InstrumentSnapshot>& snapshots() { return snapshots_; }
    int activeStrings() const { return strings_.sounding(); }
    // The voices' blow-ups (a string that ran away, restarted from rest: Voice::blowUps) and the
    // output samples the guard changed, since construction, every pack's. Plain counters.
    long blowUps() const;
    long limitedSamples() const { return limitedSamples_; }
    int maxIterations() const { return maxIterations_; }  // the most of any step since construction
    long dronePlucks() const { return drone_.plucks(); }
    const SympatheticStrings& sympathetic() const { return sympathetic_; }
    const InstrumentActivity& activity() const { return activity_; }
    void clearActivity() { activity_ = {}; }  // RT
    // The pitch ratio, pitch and note a slot plays (tests).
    double slotRatio(int slot) const { return strings_[slot].ratio; }
    double slotPitch(int slot) const { return strings_[slot].pitch; }
    int slotChannel(int slot) const { return strings_[slot].channel; }
    int slotNote(int slot) const { return strings_[slot].note; }
    bool slotSounding(int slot) const { return strings_[slot].sounding; }

    static constexpr int kChunk = kChunkSamples;

private:
    // The steps of one chunk of count host samples, in order.
    void renderChunk(float* left, float* right, int count);
    void followControls(double k20);
    void followExpression(int count, double rate);
    // The sounding strings' chunk (n of them: voices[k] into blocks[k], seconds[k]); with a worker
    // the second core's share may come back in its own blocks, written over blocks[k], seconds[k].
    struct Sounding
    {
        std::array<Voice*, kSlots> voices{};
        std::array<double*, kSlots> blocks{}, seconds{};
        std::array<int, kSlots> slots{};
        int count = 0;
    };
    Sounding soundingStrings();
    void stepStrings(Sounding& sounding, int samples);
    void stepWithWorker(Sounding& sounding, int samples);
    void stepOnBody(Sounding& sounding, int samples);
    void stepBodyOnce(Sounding& sounding, long k, ModalSolver** solvers);
    void silenceBody(Sounding& sounding);
    // Where the chunk's ramps start: the gain and the body's mix as the last chunk left them.
    struct MixStart
    {
        double gain = 1.0, bodyMix = 1.0, sympatheticLevel = 1.0;
    };
    void mixStrings(const Sounding& sounding, int count, const MixStart& start);
    void mixString(int slot, const double* block, const double* second, int count, const MixStart& start);
    void mixBody(int count, const MixStart& start);
    void takeStatistics(Voice& voice);
    void decimate(float* left, float* right, int count);
    void guard(float* left, float* right, int count);
    void publishSnapshotWhenDue(double rate);
    void publishSnapshot();
    long packBlowUps() const;  // the installed pack's voices' own counts

    SmoothedControls controls_;
    NoteExpression expression_;
    InstrumentActivity activity_;
    StringSlots strings_{controls_, expression_, activity_};
    MidiNotes notes_{strings_, controls_};
    TanpuraDrone drone_;
    SympatheticStrings sympathetic_{controls_};

    VoicePack* pack_ = nullptr;
    StringScheduling scheduling_ = StringScheduling::lone;
    StringBank bank_;
    StringWorker* worker_ = nullptr;
    int workerBias_ = 0;  // strings the worker takes beyond half (InstrumentStrings.cpp)
    bool dampingDirty_ = true;
    int maxIterations_ = 0;
    // The width the body is heard at (SharedBody::listenBetween): it follows the stereo width through
    // the controls' 20 ms one-pole, since the centre and a side listener are different sounds and a
    // switch from one to the other would splice them. NaN: take the width at once.
    double bodyWidth_ = std::numeric_limits<double>::quiet_NaN();
    // Whether this chunk's mix hears the sympathetic strings' share apart (their level below 1 at
    // either end of its ramp); at 1 throughout the body's own pressure carries them and the share's
    // copy of the modes rests (SharedBody::keepPart).
    bool tarafShareHeard_ = true;
    // Whether this chunk's sympathetic strings step as one bank (SharedBody::bankLinear): then their
    // voices are not stepped one by one, and their guard is the body's (its pressure kept finite).
    bool tarafBanked_ = false;
    int chunksSinceSnapshot_ = 0;
    double chunkPenetration_ = 0.0;
    long limitedSamples_ = 0;
    long blowUpsRetired_ = 0;    // blow-ups in the packs installed before this one, since their install
    long blowUpsAtInstall_ = 0;  // the installed pack's count when it was installed
    SnapshotBuffer<InstrumentSnapshot> snapshots_;
    uint64_t snapshotSequence_ = 0;
};

}  // namespace jawari
