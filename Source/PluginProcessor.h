#pragma once
// Jawari's AudioProcessor: the engine's Instrument behind JUCE parameters, MIDI and state.
//
// Threads: processBlock is the audio thread (no allocation, locks, logging or I/O: tested). A
// builder thread watches the structural parameters (string, obstacle shape and position, pluck and
// pickup points, inharmonicity, quality, method, release) and builds a new VoicePack for them,
// handed to the audio thread through LockFreeExchange and freed back on the builder thread. Notes
// played in the editor reach processBlock through KeyboardInput's lock-free queue and sound at the
// start of the next block. With "use a second core" on, a worker thread (StringWorker) steps half the
// sounding strings; the builder starts and stops it, and frees a retired pack only once the worker
// can no longer be stepping its strings.

#include "KeyboardInput.h"
#include "Parameters.h"
#include "realtime/instrument/Instrument.h"
#include "realtime/instrument/LockFreeExchange.h"
#include "realtime/instrument/PlayableStructure.h"

#include <juce_audio_processors/juce_audio_processors.h>

#include <array>
#include <atomic>
#include <memory>
#include <mutex>

namespace jawari::plugin
{

class JawariAudioProcessor : public juce::AudioProcessor, private juce::AsyncUpdater
{
public:
    // 1: 0.1; 2: the damping curve; 3: the thread's model (the states before played it rigid).
    static constexpr int kStateVersion = 3;

    JawariAudioProcessor();
    ~JawariAudioProcessor() override;

    void prepareToPlay(double sampleRate, int samplesPerBlock) override;
    void releaseResources() override;
    bool isBusesLayoutSupported(const BusesLayout& layouts) const override;
    void processBlock(juce::AudioBuffer<float>&, juce::MidiBuffer&) override;
    using AudioProcessor::processBlock;

    juce::AudioProcessorEditor* createEditor() override;
    bool hasEditor() const override { return true; }

    const juce::String getName() const override { return "Jawari"; }
    bool acceptsMidi() const override { return true; }
    bool producesMidi() const override { return false; }
    bool isMidiEffect() const override { return false; }
    double getTailLengthSeconds() const override { return 5.0; }

    int getNumPrograms() override;
    int getCurrentProgram() override { return currentProgram_; }
    void setCurrentProgram(int index) override;
    const juce::String getProgramName(int index) override;
    void changeProgramName(int, const juce::String&) override {}

    void getStateInformation(juce::MemoryBlock& destData) override;
    void setStateInformation(const void* data, int sizeInBytes) override;

    // The state as a ValueTree (parameters, damping curve, version) and back; setState() accepts
    // anything and falls back to defaults for what is missing, out of range or not a number.
    juce::ValueTree state() const;
    void setState(const juce::ValueTree& tree);

    // The state as XML text (UTF-8, as a user preset file or inside getStateInformation's data),
    // checked before it is applied; on failure the result says what is wrong and nothing changes. CT.
    juce::Result setStateFromXml(const char* text, size_t length);

    // User presets: the state as XML files in userPresetFolder(), read by setStateFromXml. CT.
    // Errors are returned, not thrown.
    juce::Result saveUserPreset(const juce::String& name);
    juce::Result loadUserPreset(const juce::File& file);

    // The per-mode damping curve: multipliers at kDampingCurvePoints log-spaced frequencies. CT.
    float dampingCurvePoint(int i) const { return curve_[size_t(i)].load(); }
    void setDampingCurvePoint(int i, float multiplier);

    // The keyboard's tuning: a Scala scale (.scl text) with an optional keyboard map (.kbm text),
    // kept in the state; an empty scale is equal temperament. CT. Returns what is wrong with the
    // texts (the tuning unchanged then), or an empty string.
    juce::String setKeyboardTuning(const juce::String& scale, const juce::String& keyboardMap);
    juce::String keyboardTuningName() const;  // the scale's description, or "equal temperament"

    juce::AudioProcessorValueTreeState& parameters() { return parameters_; }
    // CT: the editor's keyboard. Its notes are played at the start of the next block.
    juce::MidiKeyboardState& keyboardState() { return keyboard_.state(); }
    Instrument& instrument() { return instrument_; }
    // The output for the editor's spectrum: the newest samples, lock-free. CT reads.
    int readRecentOutput(float* dest, int count);
    float cpuLoad() const { return static_cast<float>(load_.getLoadAsProportion()); }
    // CT: blocks until the builder has built and the audio thread could take the pack for the
    // current parameters (tests, offline rendering). Returns false after the timeout.
    bool waitForBuilds(int timeoutMs = 20000);
    // Tests: the second core's worker, to set its pace and mark its thread.
    StringWorker& workerForTesting() { return worker_; }
    // The body driven one way (InstrumentStructure::bodyOneWay) from the next build on: a comparison
    // for jawari-soak, not a parameter.
    void setBodyOneWayForTesting(bool oneWay) { bodyOneWay_ = oneWay; }
    // The structure the audio thread plays now (CT, approximate).
    long packsInstalled() const { return packsInstalled_.load(); }
    // What the plugin last refused or could not do, and why (a build, a state, a preset), or empty
    // once the settings play again. CT, never the audio thread; also written to JUCE's log.
    juce::String problem() const;
    // Blocks the audio thread rendered as silence because something threw (none by design). CT.
    long renderFaults() const { return renderFaults_.load(); }

private:
    class Builder;
    void handleAsyncUpdate() override;
    InstrumentStructure wantedStructure(double hostRateHz) const;  // the parameters' structure, playable
    std::atomic<bool> bodyOneWay_{false};
    void reportProblem(const juce::String& what);
    juce::Result readStateXml(const char* text, size_t length);  // setStateFromXml's work; may throw
    juce::Result writeUserPreset(const juce::String& name);      // saveUserPreset's work; may throw
    void clearProblem();
    void collectRetired();  // CT: frees the pack the audio thread retired, once no worker task can use it
    void syncWorker();      // CT: the second core's thread running exactly when its parameter is on
    void renderBlock(juce::AudioBuffer<float>& buffer, juce::MidiBuffer& midi);  // RT
    bool installOfferedPack();                                                    // RT
    void keepRecentOutput(const float* samples, int count);                       // RT
    void handleMidi(const juce::MidiMessage& m, const MidiSettings& settings);  // RT
    InstrumentControls controls() const;  // the parameters and the keyboard's pitches, as the engine takes them. RT

    juce::AudioProcessorValueTreeState parameters_;
    ParameterReader reader_;
    std::array<std::atomic<float>, kDampingCurvePoints> curve_;
    // The keyboard's tuning as loaded (CT, under tuningLock_) and the pitch table the audio thread
    // reads (written CT, one note at a time: a note read mid-change plays the old or the new pitch).
    mutable std::mutex tuningLock_;
    juce::String scaleText_, keyboardMapText_, scaleName_;
    std::array<std::atomic<double>, kMidiNotes> keyPitches_;
    Instrument instrument_;
    KeyboardInput keyboard_;
    LockFreeExchange<VoicePack> exchange_;
    StringWorker worker_;  // after exchange_: stopped before the packs are freed
    std::unique_ptr<Builder> builder_;
    std::atomic<double> hostRate_{0.0};
    std::atomic<int> latency_{0};
    std::atomic<long> packsInstalled_{0};
    std::atomic<long> renderFaults_{0};
    mutable std::mutex problemLock_;  // builder and message threads only
    juce::String problem_;
    juce::AudioProcessLoadMeasurer load_;
    int currentProgram_ = 0;  // the defaults are factory preset 0
    // Recent output for the spectrum view: a ring written by the audio thread.
    static constexpr int kRecent = 8192;
    std::array<float, kRecent> recent_{};
    std::atomic<int> recentWrite_{0};

    JUCE_DECLARE_NON_COPYABLE_WITH_LEAK_DETECTOR(JawariAudioProcessor)
};

}  // namespace jawari::plugin
