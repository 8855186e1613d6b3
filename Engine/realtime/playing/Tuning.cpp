#include "realtime/playing/Tuning.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <limits>
#include <sstream>

namespace jawari
{

double dronePitch(int k, double saPitch, DroneFirstString first, DroneTuning tuning)
{
    if (k == 3)
        return saPitch - 12.0;  // low Sa: an octave is pure in both tunings
    if (k != 0 || first == DroneFirstString::sa)
        return saPitch;
    // Below Sa: Pa, Ma, Ni as pure ratios, or as whole equal-tempered semitones.
    static constexpr double kJust[] = {3.0 / 4.0, 2.0 / 3.0, 15.0 / 16.0};
    static constexpr int kEqual[] = {-5, -7, -1};
    const int i = static_cast<int>(first);
    return tuning == DroneTuning::just ? saPitch + 12.0 * std::log2(kJust[i]) : saPitch + kEqual[i];
}

namespace
{

// The lines of a Scala file that are not comments ('!' first), with their line numbers.
std::vector<std::pair<int, std::string>> contentLines(const std::string& text)
{
    std::vector<std::pair<int, std::string>> lines;
    std::istringstream in(text);
    std::string line;
    int number = 0;
    while (std::getline(in, line))
    {
        ++number;
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        if (!line.empty() && line.front() == '!')
            continue;
        lines.emplace_back(number, line);
    }
    return lines;
}

std::string trimmed(const std::string& s)
{
    const auto begin = s.find_first_not_of(" \t");
    if (begin == std::string::npos)
        return {};
    return s.substr(begin, s.find_last_not_of(" \t") - begin + 1);
}

// The first whitespace-separated word of a line (Scala allows a comment after the value).
std::string firstWord(const std::string& s)
{
    const std::string t = trimmed(s);
    return t.substr(0, t.find_first_of(" \t"));
}

[[noreturn]] void fail(int line, const std::string& what)
{
    throw TuningError("line " + std::to_string(line) + ": " + what);
}

double parseNumber(const std::string& word, int line, const char* what)
{
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(word.c_str(), &end);
    if (word.empty() || end != word.c_str() + word.size() || errno == ERANGE || !std::isfinite(v))
        fail(line, std::string(what) + ": '" + word + "' is not a number");
    return v;
}

long parseWhole(const std::string& word, int line, const char* what)
{
    errno = 0;
    char* end = nullptr;
    const long v = std::strtol(word.c_str(), &end, 10);
    if (word.empty() || end != word.c_str() + word.size() || errno == ERANGE)
        fail(line, std::string(what) + ": '" + word + "' is not a whole number");
    return v;
}

// A pitch line: cents if it has a '.', else a ratio a/b or a whole number.
double pitchCents(const std::string& raw, int line)
{
    const std::string word = firstWord(raw);
    if (word.find('.') != std::string::npos)
        return parseNumber(word, line, "pitch in cents");
    const auto slash = word.find('/');
    const long num = parseWhole(word.substr(0, slash), line, "ratio");
    const long den = slash == std::string::npos ? 1 : parseWhole(word.substr(slash + 1), line, "ratio");
    if (num <= 0 || den <= 0)
        fail(line, "ratio '" + word + "' must be positive");
    return 1200.0 * std::log2(double(num) / double(den));
}

}  // namespace

ScalaScale parseScalaScale(const std::string& text)
{
    const auto lines = contentLines(text);
    if (lines.size() < 2)
        throw TuningError("a Scala scale needs a description line and a note count");
    ScalaScale scale;
    scale.description = trimmed(lines[0].second);
    const long count = parseWhole(firstWord(lines[1].second), lines[1].first, "note count");
    if (count < 1 || count > 1024)
        fail(lines[1].first, "note count must be 1 to 1024 (got " + std::to_string(count) + ")");
    if (lines.size() < size_t(count) + 2)
        throw TuningError("the scale announces " + std::to_string(count) + " pitches but gives "
                          + std::to_string(lines.size() - 2));
    for (long i = 0; i < count; ++i)
    {
        const auto& [number, line] = lines[size_t(i) + 2];
        scale.cents.push_back(pitchCents(line, number));
    }
    if (!(scale.cents.back() > 0.0))
        fail(lines[size_t(count) + 1].first, "the period (the last pitch) must be above the first degree");
    return scale;
}

KeyboardMap parseKeyboardMap(const std::string& text)
{
    const auto lines = contentLines(text);
    std::vector<std::pair<int, std::string>> values;
    for (const auto& l : lines)
        if (!trimmed(l.second).empty())
            values.push_back(l);
    if (values.size() < 7)
        throw TuningError("a keyboard map needs 7 header values (size, first, last, middle, reference note, "
                          "reference frequency, octave degree)");
    auto whole = [&](size_t i, const char* what) {
        return parseWhole(firstWord(values[i].second), values[i].first, what);
    };
    KeyboardMap map;
    map.size = int(std::clamp(whole(0, "map size"), -1L, 1L << 20));
    map.firstNote = int(std::clamp(whole(1, "first note"), -1L, 1L << 20));
    map.lastNote = int(std::clamp(whole(2, "last note"), -1L, 1L << 20));
    map.middleNote = int(std::clamp(whole(3, "middle note"), -1L, 1L << 20));
    map.referenceNote = int(std::clamp(whole(4, "reference note"), -1L, 1L << 20));
    map.referenceHz = parseNumber(firstWord(values[5].second), values[5].first, "reference frequency");
    map.octaveDegree = int(std::clamp(whole(6, "octave degree"), -1L, 1L << 20));
    if (map.size < 0 || map.size > 128)
        fail(values[0].first, "map size must be 0 to 128");
    for (int v : {map.firstNote, map.lastNote, map.middleNote, map.referenceNote})
        if (v < 0 || v > 127)
            throw TuningError("note numbers must be 0 to 127 (got " + std::to_string(v) + ")");
    if (!(map.referenceHz > 0.0))
        fail(values[5].first, "reference frequency must be positive");
    if (map.octaveDegree < 0)
        fail(values[6].first, "octave degree must not be negative");
    for (int i = 0; i < map.size; ++i)
    {
        if (values.size() <= size_t(7 + i))
        {
            map.degrees.push_back(-1);  // Scala: missing entries at the end are unmapped
            continue;
        }
        const auto& [number, line] = values[size_t(7 + i)];
        const std::string word = firstWord(line);
        const long d = word == "x" || word == "X" ? -1 : parseWhole(word, number, "map entry");
        if (d < -1)
            fail(number, "map entry must be a degree or x");
        map.degrees.push_back(int(d));
    }
    return map;
}

namespace
{
// Cents of a total scale degree d above degree 0 (whole periods plus a degree within one).
double degreeCents(const ScalaScale& scale, long d)
{
    const long n = long(scale.cents.size());
    const long period = d >= 0 ? d / n : -((-d + n - 1) / n);
    const long within = d - period * n;
    return double(period) * scale.cents.back() + (within == 0 ? 0.0 : scale.cents[size_t(within - 1)]);
}

// The total degree key `note` plays, or nullopt when unmapped.
std::optional<long> keyDegree(const ScalaScale& scale, const KeyboardMap& map, int note)
{
    const long offset = note - map.middleNote;
    if (map.size == 0)
        return offset;
    const long repeats = offset >= 0 ? offset / map.size : -((-offset + map.size - 1) / map.size);
    const long key = offset - repeats * map.size;
    const int degree = map.degrees[size_t(key)];
    if (degree < 0)
        return std::nullopt;
    const long octave = map.octaveDegree > 0 ? map.octaveDegree : long(scale.cents.size());
    return degree + repeats * octave;
}
}  // namespace

KeyboardPitches keyboardPitches(const ScalaScale& scale, const KeyboardMap& map)
{
    KeyboardPitches pitches;
    pitches.fill(std::numeric_limits<double>::quiet_NaN());
    // Degree 0's frequency, from the reference key's (or from middle C if the reference is unmapped).
    const auto referenceDegree = keyDegree(scale, map, map.referenceNote);
    const double referenceCents = referenceDegree ? degreeCents(scale, *referenceDegree) : 0.0;
    const double basePitch = pitchOfFrequency(map.referenceHz, 440.0) - referenceCents / 100.0;
    for (int note = std::max(0, map.firstNote); note <= std::min(kMidiNotes - 1, map.lastNote); ++note)
        if (const auto d = keyDegree(scale, map, note))
            pitches[size_t(note)] = basePitch + degreeCents(scale, *d) / 100.0;
    return pitches;
}

}  // namespace jawari
