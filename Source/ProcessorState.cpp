// The processor's state: saved and loaded by the host (the parameters, the program, the damping
// curve and the keyboard's tuning as XML), and the user presets, files of the same XML. Whatever a
// state holds, loading it never throws: a value that is not a number takes the default, and a text
// that is not a state is refused with its reason.

#include "PluginProcessor.h"

#include "Presets.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

namespace jawari::plugin
{

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
    // Version 1 (0.1) had no damping curve; version 2 adds it; version 3 the thread's model, whose
    // threads before were rigid, so an older state without it plays its thread rigid still.
    // Anything else a state lacks, or holds out of range or not as a number, takes the parameter's
    // default. A parameter saved under an id it had before is read too.
    const auto params = tree.getChildWithName("Parameters");
    const double version = numberIn(tree.getProperty("version", kStateVersion));
    for (auto* p : getParameters())
    {
        auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(p);
        if (ranged == nullptr)
            continue;
        float normalised = ranged->getDefaultValue();
        if (ranged->getParameterID() == ids::threadModel && version < 3.0)
            normalised = ranged->convertTo0to1(1.0f);  // rigid
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
