#include "PluginProcessor.h"

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

// Watches the structural parameters and builds new packs for them off the audio thread; frees the
// packs the audio thread retires.
class JawariAudioProcessor::Builder : public juce::Thread
{
public:
    explicit Builder(JawariAudioProcessor& owner)
        : juce::Thread("Jawari builder")
        , owner_(owner)
    {}

    void setBuilt(const InstrumentStructure& s)
    {
        const juce::SpinLock::ScopedLockType lock(guard_);  // builder and message threads only
        built_ = s;
    }

    bool hasBuilt(const InstrumentStructure& s)
    {
        const juce::SpinLock::ScopedLockType lock(guard_);
        return built_ == s;
    }

    // Each pass: the worker and the retired packs looked after, then a pack for the wanted
    // structure if it changed. When the host rate has no pack yet, a cheap one (draft, one
    // polarisation) goes first, so that the instrument plays within milliseconds of prepareToPlay.
    // Nothing thrown here leaves the thread: it is reported and the last good pack plays on.
    void run() override
    {
        while (!threadShouldExit())
        {
            try
            {
                if (buildIfWanted())
                    continue;
            }
            catch (const std::exception& e)
            {
                owner_.reportProblem(juce::String("the builder stopped on an error: ") + e.what());
            }
            catch (...)
            {
                owner_.reportProblem("the builder stopped on an unknown error");
            }
            wait(10);
        }
    }

private:
    // Returns whether it built (then it looks again at once).
    bool buildIfWanted()
    {
        owner_.syncWorker();
        owner_.collectRetired();
        const double rate = owner_.hostRate_.load();
        if (!playableHostRate(rate))
            return false;
        const auto wanted = owner_.wantedStructure(rate);
        if (hasBuilt(wanted))
            return false;
        if (offeredRate_ != rate && (wanted.quality != 0 || wanted.polarisations != 1))
        {
            auto cheap = wanted;
            cheap.quality = 0;
            cheap.polarisations = 1;
            offer(cheap);
        }
        if (offer(wanted))
        {
            owner_.clearProblem();
            owner_.triggerAsyncUpdate();  // the latency reported to the host
        }
        setBuilt(wanted);  // built or refused: either way not tried again until it changes
        return true;
    }

    // Builds a pack and offers it to the audio thread; a structure the engine refuses is reported
    // and the instrument keeps the pack it has. Returns whether it offered one.
    bool offer(const InstrumentStructure& s)
    {
        try
        {
            auto pack = buildVoicePack(s);
            owner_.exchange_.offer(std::move(pack));
            offeredRate_ = s.hostRateHz;
            return true;
        }
        catch (const std::exception& e)
        {
            owner_.reportProblem(juce::String("these settings could not be built (") + e.what()
                                 + "); the instrument plays the last ones it could");
        }
        return false;
    }

    JawariAudioProcessor& owner_;
    juce::SpinLock guard_;
    InstrumentStructure built_{};
    double offeredRate_ = 0.0;  // the host rate of the last pack offered (builder thread only)
};

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
    return playableStructure(reader_.structure(hostRateHz));
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

void JawariAudioProcessor::renderBlock(juce::AudioBuffer<float>& buffer, juce::MidiBuffer& midi)
{
    const int numSamples = buffer.getNumSamples();
    VoicePack* previous = nullptr;
    if (VoicePack* fresh = exchange_.take(&previous))
    {
        instrument_.install(fresh, previous);
        exchange_.retire();
        packsInstalled_.fetch_add(1, std::memory_order_relaxed);
    }
    // Silence until a pack at the host's rate arrives (after prepareToPlay at a new rate).
    const VoicePack* playing = instrument_.pack();
    if (playing == nullptr || playing->structure.hostRateHz != hostRate_.load(std::memory_order_relaxed))
    {
        buffer.clear();
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

    int w = recentWrite_.load(std::memory_order_relaxed);
    for (int n = 0; n < numSamples; ++n)
    {
        recent_[size_t(w)] = left[n];
        w = (w + 1) % kRecent;
    }
    recentWrite_.store(w, std::memory_order_release);
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

juce::ValueTree JawariAudioProcessor::state() const
{
    juce::ValueTree tree("JawariState");
    tree.setProperty("version", kStateVersion, nullptr);
    tree.setProperty("program", currentProgram_, nullptr);
    juce::ValueTree params("Parameters");
    for (auto* p : getParameters())
        if (auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(p))
        {
            juce::ValueTree param("Param");
            param.setProperty("id", ranged->getParameterID(), nullptr);
            param.setProperty("value", ranged->convertFrom0to1(ranged->getValue()), nullptr);
            params.appendChild(param, nullptr);
        }
    tree.appendChild(params, nullptr);
    juce::ValueTree curve("DampingCurve");
    for (int i = 0; i < kDampingCurvePoints; ++i)
        curve.setProperty("p" + juce::String(i), curve_[size_t(i)].load(), nullptr);
    tree.appendChild(curve, nullptr);
    const std::lock_guard<std::mutex> lock(tuningLock_);
    if (scaleText_.isNotEmpty())
    {
        juce::ValueTree tuning("KeyboardTuning");
        tuning.setProperty("scale", scaleText_, nullptr);
        tuning.setProperty("keyboardMap", keyboardMapText_, nullptr);
        tree.appendChild(tuning, nullptr);
    }
    return tree;
}

namespace
{
// A state value as a number, or NaN. Text is read with strtod, not JUCE's reader, which overflows a
// signed int on long exponents (undefined behaviour; found by tools/fuzz.sh under UBSan).
double numberIn(const juce::var& v)
{
    if (v.isDouble() || v.isInt() || v.isInt64() || v.isBool())
        return static_cast<double>(v);
    const std::string text = v.toString().trim().toStdString();
    if (text.empty() || text.size() > 64 || text.find_first_not_of("0123456789+-.eE") != std::string::npos)
        return std::nan("");
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    return end == text.c_str() + text.size() ? value : std::nan("");
}

// A parameter's entry in a state's "Parameters": under its id, else under an id it had before
// (kParameterAliases); invalid when there is neither.
juce::ValueTree savedParameter(const juce::ValueTree& params, const juce::String& id)
{
    if (const auto saved = params.getChildWithProperty("id", id); saved.isValid())
        return saved;
    for (const auto& alias : kParameterAliases)
    {
        if (id != alias.id)
            continue;
        if (const auto older = params.getChildWithProperty("id", alias.oldId); older.isValid())
            return older;
    }
    return {};
}

// Whether a processing instruction (<?...?>) follows the XML declaration. JUCE 7's XML reader loops
// for ever on one followed by text inside an element (found by tools/fuzz.sh); a state has none.
bool hasInnerProcessingInstruction(std::string_view text)
{
    size_t from = 0;
    const auto start = text.find_first_not_of(" \t\r\n");
    if (start != std::string_view::npos && text.substr(start, 5) == "<?xml")
    {
        const auto end = text.find("?>", start);
        from = end == std::string_view::npos ? text.size() : end + 2;
    }
    return text.find("<?", from) != std::string_view::npos;
}
}  // namespace

void JawariAudioProcessor::setState(const juce::ValueTree& tree)
{
    // Version 1 (0.1) had no damping curve; version 2 adds it. Anything else a state lacks, or
    // holds out of range or not as a number, takes the parameter's default. A parameter saved under
    // an id it had before is read too.
    const auto params = tree.getChildWithName("Parameters");
    for (auto* p : getParameters())
    {
        auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(p);
        if (ranged == nullptr)
            continue;
        float normalised = ranged->getDefaultValue();
        const auto param = savedParameter(params, ranged->getParameterID());
        if (param.isValid())
        {
            const double value = numberIn(param.getProperty("value"));
            const auto& range = ranged->getNormalisableRange();
            if (std::isfinite(value) && value >= range.start && value <= range.end)
                normalised = ranged->convertTo0to1(static_cast<float>(value));
        }
        ranged->setValueNotifyingHost(normalised);
    }
    const auto curve = tree.getChildWithName("DampingCurve");
    for (int i = 0; i < kDampingCurvePoints; ++i)
    {
        const double value = numberIn(curve.getProperty("p" + juce::String(i), 1.0));
        const bool valid = std::isfinite(value) && value >= kDampingCurveMin && value <= kDampingCurveMax;
        setDampingCurvePoint(i, valid ? static_cast<float>(value) : 1.0f);
    }
    const double program = numberIn(tree.getProperty("program", 0));
    currentProgram_ = program >= 0.0 && program < getNumPrograms() ? static_cast<int>(program) : 0;
    // The keyboard's tuning; a state without one, or with one that does not parse, plays equal
    // temperament.
    const auto tuning = tree.getChildWithName("KeyboardTuning");
    if (setKeyboardTuning(tuning.getProperty("scale").toString(), tuning.getProperty("keyboardMap").toString())
            .isNotEmpty())
        setKeyboardTuning({}, {});
}

void JawariAudioProcessor::getStateInformation(juce::MemoryBlock& destData)
{
    try
    {
        if (const auto xml = state().createXml())
            copyXmlToBinary(*xml, destData);
    }
    catch (const std::exception& e)
    {
        reportProblem(juce::String("the state could not be saved: ") + e.what());
    }
}

void JawariAudioProcessor::setStateInformation(const void* data, int sizeInBytes)
{
    // Anything that is not a Jawari state (empty, truncated, random) is ignored: the current
    // settings stay, nothing crashes. A Jawari state of any version is read field by field.
    // JUCE's binary XML is a magic number, a length and that many bytes of UTF-8.
    if (data == nullptr || sizeInBytes <= 8)
        return;
    const auto* bytes = static_cast<const char*>(data);
    if (juce::ByteOrder::littleEndianInt(bytes) != 0x21324356u)
        return;
    const auto length = static_cast<juce::int64>(juce::ByteOrder::littleEndianInt(bytes + 4));
    if (length <= 0 || length > sizeInBytes - 8)
        return;
    const auto result = setStateFromXml(bytes + 8, static_cast<size_t>(length));
    if (result.failed())
        reportProblem("the host's saved state was not loaded: " + result.getErrorMessage());
}

juce::Result JawariAudioProcessor::setStateFromXml(const char* text, size_t length)
{
    try
    {
        return readStateXml(text, length);
    }
    catch (const std::exception& e)
    {
        return juce::Result::fail(juce::String("the state could not be read: ") + e.what());
    }
}

juce::Result JawariAudioProcessor::readStateXml(const char* text, size_t length)
{
    // The UTF-8 is checked before JUCE parses the XML: its UTF-8 iterator trusts lead bytes and
    // reads past the end of a string whose last sequence is cut short (found by tools/fuzz.sh
    // under ASan).
    if (length >= 3 && std::memcmp(text, "\xEF\xBB\xBF", 3) == 0)  // a byte order mark, as editors may add
    {
        text += 3;
        length -= 3;
    }
    if (length > static_cast<size_t>(std::numeric_limits<int>::max()))
        return juce::Result::fail("too large for a state");
    if (!juce::CharPointer_UTF8::isValidString(text, static_cast<int>(length)))
        return juce::Result::fail("not valid UTF-8 text");
    if (hasInnerProcessingInstruction(std::string_view(text, length)))
        return juce::Result::fail("not a Jawari state: a processing instruction (<?...?>) after the XML declaration");
    juce::XmlDocument document(juce::String::fromUTF8(text, static_cast<int>(length)));
    const auto xml = document.getDocumentElement();
    if (xml == nullptr)
        return juce::Result::fail(document.getLastParseError().isEmpty() ? "not XML"
                                                                         : "not XML: " + document.getLastParseError());
    if (!xml->hasTagName("JawariState"))
        return juce::Result::fail("not a Jawari state: its root element is <" + xml->getTagName()
                                  + ">, not <JawariState>");
    setState(juce::ValueTree::fromXml(*xml));
    return juce::Result::ok();
}

juce::Result JawariAudioProcessor::saveUserPreset(const juce::String& name)
{
    try
    {
        return writeUserPreset(name);
    }
    catch (const std::exception& e)
    {
        return juce::Result::fail(juce::String("the preset could not be saved: ") + e.what());
    }
}

juce::Result JawariAudioProcessor::writeUserPreset(const juce::String& name)
{
    const auto clean = juce::File::createLegalFileName(name.trim());
    if (clean.isEmpty())
        return juce::Result::fail("a preset needs a name");
    const auto folder = userPresetFolder();
    if (const auto made = folder.createDirectory(); made.failed())
        return made;
    const auto xml = state().createXml();
    const auto file = folder.getChildFile(clean + ".jawaripreset");
    // Written to a temporary and moved into place: a failed write leaves any older preset intact.
    juce::TemporaryFile temporary(file);
    if (xml == nullptr || !xml->writeTo(temporary.getFile()) || !temporary.overwriteTargetFileWithTemporary())
        return juce::Result::fail("could not write " + file.getFullPathName());
    return juce::Result::ok();
}

juce::Result JawariAudioProcessor::loadUserPreset(const juce::File& file)
{
    constexpr juce::int64 largest = 1 << 20;  // a state is a few kilobytes
    juce::MemoryBlock data;
    if (!file.existsAsFile())
        return juce::Result::fail(file.getFullPathName() + ": no such file");
    if (file.getSize() > largest)
        return juce::Result::fail(file.getFullPathName() + ": larger than a Jawari state can be");
    if (!file.loadFileAsData(data))
        return juce::Result::fail(file.getFullPathName() + ": cannot be read");
    const auto result = setStateFromXml(static_cast<const char*>(data.getData()), data.getSize());
    return result.wasOk() ? result : juce::Result::fail(file.getFullPathName() + ": " + result.getErrorMessage());
}

}  // namespace jawari::plugin

juce::AudioProcessor* JUCE_CALLTYPE createPluginFilter()
{
    return new jawari::plugin::JawariAudioProcessor();
}
