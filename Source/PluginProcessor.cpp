#include "PluginProcessor.h"

#include "PackBuilder.h"
#include "PluginEditor.h"
#include "Presets.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

namespace jawari::plugin
{

JawariAudioProcessor::JawariAudioProcessor()
    : AudioProcessor(BusesProperties().withOutput("Output", juce::AudioChannelSet::stereo(), true))
    , parameters_(*this, nullptr, "Parameters", createParameterLayout())
    , reader_(parameters_)
{
    for (auto& c : curve_)
        c.store(1.0f);
    const auto equal = equalTemperament();
    for (size_t n = 0; n < keyPitches_.size(); ++n)
        keyPitches_[n].store(equal[n]);
    scaleName_ = "equal temperament";
    builder_ = std::make_unique<Builder>(*this);
    builder_->startThread();
}

JawariAudioProcessor::~JawariAudioProcessor()
{
    cancelPendingUpdate();
    // A build under way is let finish (a thread killed mid-build would leave its locks and memory).
    builder_->stopThread(-1);
}

InstrumentStructure JawariAudioProcessor::wantedStructure(double hostRateHz) const
{
    auto structure = reader_.structure(hostRateHz);
    structure.bodyOneWay = bodyOneWay_.load(std::memory_order_relaxed);
    return playableStructure(structure);
}

void JawariAudioProcessor::reportProblem(const juce::String& what)
{
    juce::Logger::writeToLog("Jawari: " + what);
    const std::lock_guard<std::mutex> lock(problemLock_);
    problem_ = what;
}

void JawariAudioProcessor::clearProblem()
{
    const std::lock_guard<std::mutex> lock(problemLock_);
    problem_.clear();
}

juce::String JawariAudioProcessor::problem() const
{
    const std::lock_guard<std::mutex> lock(problemLock_);
    return problem_;
}

void JawariAudioProcessor::collectRetired()
{
    if (exchange_.retiredEmpty())
        return;
    // Every task on the retired pack was posted before it was retired: wait for those.
    worker_.waitForJobs(worker_.postedJobs());
    exchange_.collect();
}

void JawariAudioProcessor::syncWorker()
{
    if (reader_.secondCore())
        worker_.start();
    else
        worker_.stop();
}

// Returns at once: the builder thread builds the pack for this rate (a cheap one first when the
// rate has none), and the instrument plays silence until a pack at this rate arrives. The host
// hears the latency of the pack to come.
void JawariAudioProcessor::prepareToPlay(double sampleRate, int)
{
    try
    {
        keyboard_.drain([](const KeyboardInput::Event&) {});  // keys pressed while audio was stopped
        hostRate_.store(sampleRate);
        if (!playableHostRate(sampleRate))
        {
            reportProblem("the host's sample rate, " + juce::String(sampleRate) + " Hz, is outside 8 to 384 kHz: "
                          + "Jawari stays silent");
            return;
        }
        // Playback starts at the parameters' values: a first note does not hear the gain or the
        // obstacle gliding from their defaults.
        instrument_.setControls(controls());
        instrument_.settleControls();
        latency_.store(voicePackLatency(wantedStructure(sampleRate)));
        setLatencySamples(latency_.load());
        load_.reset(sampleRate, 512);
        builder_->notify();
    }
    catch (const std::exception& e)
    {
        reportProblem(juce::String("preparing to play failed: ") + e.what());
    }
}

InstrumentControls JawariAudioProcessor::controls() const
{
    InstrumentControls c = reader_.controls(curve_);
    for (size_t n = 0; n < c.keyPitches.size(); ++n)
        c.keyPitches[n] = keyPitches_[n].load(std::memory_order_relaxed);
    return c;
}

void JawariAudioProcessor::releaseResources() {}

bool JawariAudioProcessor::isBusesLayoutSupported(const BusesLayout& layouts) const
{
    const auto out = layouts.getMainOutputChannelSet();
    return layouts.inputBuses.isEmpty()
           && (out == juce::AudioChannelSet::mono() || out == juce::AudioChannelSet::stereo());
}

void JawariAudioProcessor::processBlock(juce::AudioBuffer<float>& buffer, juce::MidiBuffer& midi)
{
    juce::ScopedNoDenormals noDenormals;
    juce::AudioProcessLoadMeasurer::ScopedTimer timer(load_, buffer.getNumSamples());
    // Nothing on the audio thread throws by design; should anything, the block is silent and
    // counted (renderFaults()), and the host plays on.
    try
    {
        renderBlock(buffer, midi);
    }
    catch (...)
    {
        buffer.clear();
        renderFaults_.fetch_add(1, std::memory_order_relaxed);
    }
}

// Installs the pack the builder offered, if any; returns whether the instrument has a pack at the
// host's rate (none until one arrives after prepareToPlay at a new rate).
bool JawariAudioProcessor::installOfferedPack()
{
    VoicePack* previous = nullptr;
    if (VoicePack* fresh = exchange_.take(&previous))
    {
        instrument_.install(fresh, previous);
        exchange_.retire();
        packsInstalled_.fetch_add(1, std::memory_order_relaxed);
    }
    const VoicePack* playing = instrument_.pack();
    return playing != nullptr && playing->structure.hostRateHz == hostRate_.load(std::memory_order_relaxed);
}

// The block's first channel into the ring the editor's spectrum reads.
void JawariAudioProcessor::keepRecentOutput(const float* samples, int count)
{
    int w = recentWrite_.load(std::memory_order_relaxed);
    for (int n = 0; n < count; ++n)
    {
        recent_[size_t(w)] = samples[n];
        w = (w + 1) % kRecent;
    }
    recentWrite_.store(w, std::memory_order_release);
}

void JawariAudioProcessor::renderBlock(juce::AudioBuffer<float>& buffer, juce::MidiBuffer& midi)
{
    const int numSamples = buffer.getNumSamples();
    if (!installOfferedPack())
    {
        buffer.clear();  // silence until a pack at the host's rate arrives
        keyboard_.drain([](const KeyboardInput::Event&) {});
        return;
    }
    instrument_.setControls(controls());
    instrument_.setWorker(reader_.secondCore() && worker_.running() ? &worker_ : nullptr);

    float* left = buffer.getWritePointer(0);
    float* right = buffer.getNumChannels() > 1 ? buffer.getWritePointer(1) : nullptr;
    std::array<float, Instrument::kChunk> spare{};
    int position = 0;
    auto renderTo = [&](int end) {
        while (position < end)
        {
            const int count = right != nullptr ? end - position : std::min(end - position, Instrument::kChunk);
            if (right != nullptr)
                instrument_.render(left + position, right + position, count);
            else
            {
                instrument_.render(left + position, spare.data(), count);
                for (int n = 0; n < count; ++n)
                    left[position + n] = 0.5f * (left[position + n] + spare[size_t(n)]);
            }
            position += count;
        }
    };
    keyboard_.drain([this](const KeyboardInput::Event& e) {
        if (e.on)
            instrument_.noteOn(e.note, e.velocity);
        else
            instrument_.noteOff(e.note);
    });
    const MidiSettings settings = reader_.midi();
    for (const auto metadata : midi)
    {
        renderTo(std::clamp(metadata.samplePosition, 0, numSamples));
        handleMidi(metadata.getMessage(), settings);
    }
    renderTo(numSamples);
    for (int c = 2; c < buffer.getNumChannels(); ++c)
        buffer.clear(c, 0, numSamples);
    keepRecentOutput(left, numSamples);
}

// One MIDI message to the instrument. Under MPE (the lower zone) a note on channel 2..16 carries
// its own bend, pressure and slide (CC 74); channel 1's bend, and every bend without MPE, moves
// every note.
void JawariAudioProcessor::handleMidi(const juce::MidiMessage& m, const MidiSettings& settings)
{
    const int channel = m.getChannel();
    const bool member = settings.mpe && channel >= 2;
    const int noteChannel = member ? channel : 0;
    if (m.isNoteOn())
        instrument_.noteOn(m.getNoteNumber(), m.getFloatVelocity(), noteChannel);
    else if (m.isNoteOff())
        instrument_.noteOff(m.getNoteNumber(), noteChannel);
    else if (m.isPitchWheel())
    {
        const double amount = (m.getPitchWheelValue() - 8192) / 8192.0;
        if (member)
            instrument_.channelBend(channel, amount * settings.mpeBendRange);
        else
            instrument_.pitchBend(amount);
    }
    else if (member && m.isChannelPressure())
        instrument_.channelPressure(channel, m.getChannelPressureValue() / 127.0);
    else if (member && m.isControllerOfType(74))
        instrument_.channelSlide(channel, m.getControllerValue() / 127.0);
    else if (m.isSustainPedalOn())
        instrument_.sustain(true);
    else if (m.isSustainPedalOff())
        instrument_.sustain(false);
    else if (m.isAllNotesOff() || m.isAllSoundOff())
        instrument_.allNotesOff();
}

int JawariAudioProcessor::readRecentOutput(float* dest, int count)
{
    count = std::min(count, kRecent);
    const int w = recentWrite_.load(std::memory_order_acquire);
    for (int n = 0; n < count; ++n)
        dest[n] = recent_[size_t((w - count + n + kRecent) % kRecent)];
    return count;
}

bool JawariAudioProcessor::waitForBuilds(int timeoutMs)
{
    const auto deadline = juce::Time::getMillisecondCounter() + juce::uint32(timeoutMs);
    while (juce::Time::getMillisecondCounter() < deadline)
    {
        const double rate = hostRate_.load();
        // Built, and nothing retired in the way: the next processBlock takes the pack.
        if (playableHostRate(rate) && builder_->hasBuilt(wantedStructure(rate)) && exchange_.retiredEmpty())
            return true;
        juce::Thread::sleep(2);
    }
    return false;
}

void JawariAudioProcessor::handleAsyncUpdate()
{
    setLatencySamples(latency_.load());
}

juce::AudioProcessorEditor* JawariAudioProcessor::createEditor()
{
    return new JawariEditor(*this);
}

int JawariAudioProcessor::getNumPrograms()
{
    return static_cast<int>(factoryPresets().size());
}

void JawariAudioProcessor::setCurrentProgram(int index)
{
    const auto& presets = factoryPresets();
    if (index < 0 || index >= static_cast<int>(presets.size()))
        return;
    try
    {
        currentProgram_ = index;
        applyFactoryPreset(parameters_, presets[size_t(index)]);
        for (int i = 0; i < kDampingCurvePoints; ++i)
            setDampingCurvePoint(i, 1.0f);
    }
    catch (const std::exception& e)
    {
        reportProblem(juce::String("the preset could not be applied: ") + e.what());
    }
}

const juce::String JawariAudioProcessor::getProgramName(int index)
{
    const auto& presets = factoryPresets();
    return index >= 0 && index < static_cast<int>(presets.size()) ? presets[size_t(index)].name : "";
}

void JawariAudioProcessor::setDampingCurvePoint(int i, float multiplier)
{
    if (i < 0 || i >= kDampingCurvePoints)
        return;
    const auto lowest = static_cast<float>(kDampingCurveMin), highest = static_cast<float>(kDampingCurveMax);
    curve_[size_t(i)].store(std::isfinite(multiplier) ? std::clamp(multiplier, lowest, highest) : 1.0f);
}

juce::String JawariAudioProcessor::setKeyboardTuning(const juce::String& scale, const juce::String& keyboardMap)
{
    KeyboardPitches pitches = equalTemperament();
    juce::String name = "equal temperament";
    try
    {
        if (scale.trim().isNotEmpty())
        {
            const auto parsed = parseScalaScale(scale.toStdString());
            const auto map =
                keyboardMap.trim().isNotEmpty() ? parseKeyboardMap(keyboardMap.toStdString()) : KeyboardMap{};
            pitches = keyboardPitches(parsed, map);
            name = parsed.description.empty() ? juce::String("Scala scale") : juce::String(parsed.description);
        }
    }
    catch (const std::exception& e)  // TuningError, or running out of memory
    {
        return e.what();
    }
    const std::lock_guard<std::mutex> lock(tuningLock_);
    scaleText_ = scale.trim().isNotEmpty() ? scale : juce::String();
    keyboardMapText_ = scaleText_.isNotEmpty() ? keyboardMap : juce::String();
    scaleName_ = name;
    for (size_t n = 0; n < pitches.size(); ++n)
        keyPitches_[n].store(pitches[n], std::memory_order_relaxed);
    return {};
}

juce::String JawariAudioProcessor::keyboardTuningName() const
{
    const std::lock_guard<std::mutex> lock(tuningLock_);
    return scaleName_;
}

}  // namespace jawari::plugin

juce::AudioProcessor* JUCE_CALLTYPE createPluginFilter()
{
    return new jawari::plugin::JawariAudioProcessor();
}
